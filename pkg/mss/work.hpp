// Heavy requests: an estimate of a step's work before it starts (refused past a limit, naming the option that
// raises it), a progress line while it runs, and a clean stop on request (Ctrl-C).
#pragma once

#include <functional>
#include <stdexcept>
#include <string>

namespace mss {

/// The default limit on a step's estimated work, seconds of this kind of machine (2 cores): a request above
/// it is refused before it starts, with the estimate and the option (maxWork, --max-work) that raises it.
constexpr double kDefaultMaxWork = 600.0;

/// A step's estimated work: its size in its own terms ("4.3e+08 voxels and 65535 spheres") and the seconds
/// it should take. The estimates are calibrated on a 2-core machine and err on the high side.
struct Work {
    std::string what;
    double seconds = 0.0;
};

/// Throws std::invalid_argument("WHERE: WHAT, about N s of work, over the work limit of L s: LIGHTER, or
/// raise maxWork") when @p work exceeds @p maxWork seconds; @p lighter says how to ask for less.
void checkWork(const std::string& where, const Work& work, double maxWork, const std::string& lighter);

/// Thrown from a step's checkpoints once a stop was requested (requestStop: the command line's Ctrl-C, or
/// the stop poll of the Python binding). Whatever the step was writing is not published.
class Interrupted : public std::runtime_error {
public:
    explicit Interrupted(const std::string& where) : std::runtime_error(where + ": interrupted") {}
};

/// Asks the running step to stop at its next checkpoint. Async-signal-safe (a lock-free atomic flag).
void requestStop() noexcept;
/// Clears a stop request (a new step begins).
void clearStop() noexcept;
/// Whether a stop was requested (or the stop poll says so).
bool stopRequested();

/// A front end's own way to learn of a stop (the Python binding: pending signals); called at checkpoints,
/// from the thread that runs the step.
void setStopPoll(std::function<bool()> poll);

/// Where progress lines go (the command line: standard error). None by default: the library prints nothing.
/// @p final is true for a step's last line.
void setProgressSink(std::function<void(const std::string& line, bool final)> sink);

/// The sink of the front ends: progress lines on standard error, rewritten in place on a terminal, a line
/// every 10 s into a log.
void showProgressOnStandardError();

/// The progress of one long step. Lines go to the sink, at most one a second, and only once the step has
/// run for a second or was estimated at more: quick steps stay silent. Not for use inside parallel regions.
class Progress {
public:
    Progress(std::string where, double estimatedSeconds);
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;
    /// The step is @p fraction (0..1) done, in @p stage; a checkpoint: throws Interrupted on a stop request.
    /// A negative @p fraction: the share of the estimate elapsed (steps that cannot count their work).
    void update(double fraction, const std::string& stage = {});

private:
    std::string where_;
    double estimate_;
    double started_, lastLine_;
    bool shown_ = false;
    Progress* outer_; // the step this one runs within, on this thread
};

/// A checkpoint of the innermost Progress of this thread (its update, by time elapsed, in @p stage), for code
/// deep in a step that has no Progress of its own (the engine's rounds); without one, checkpoint("work").

void tick(const std::string& stage);

/// Throws Interrupted(@p where) when a stop was requested.
void checkpoint(const std::string& where);

} // namespace mss
