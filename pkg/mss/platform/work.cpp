#include "mss/work.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <mutex>
#include <sstream>
#include <utility>

#include <unistd.h>

namespace mss {

namespace {

std::atomic<bool> gStop{false};
static_assert(std::atomic<bool>::is_always_lock_free, "requestStop must be async-signal-safe");
// the poll (Python's: it takes the GIL) at most every 20 ms, however often the checkpoints come
std::atomic<long long> gLastPoll{0};
constexpr long long kPollEveryNs = 20'000'000;

std::mutex gHooks; // the poll and the sink are set by front ends, rarely; read at checkpoints
std::function<bool()> gPoll;
std::function<void(const std::string&, bool)> gSink;
thread_local Progress* tInnermost = nullptr;

double now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::string seconds(double s) {
    std::ostringstream os;
    os.precision(s < 10 ? 2 : 3);
    os << s << " s";
    return os.str();
}

void emit(const std::string& line, bool final) {
    std::function<void(const std::string&, bool)> sink;
    {
        const std::lock_guard<std::mutex> lock(gHooks);
        sink = gSink;
    }
    if (sink) sink(line, final);
}

} // namespace

void checkWork(const std::string& where, const Work& work, double maxWork, const std::string& lighter) {
    if (!(maxWork > 0.0)) {
        std::ostringstream os;
        os << where << ": maxWork must be > 0 (seconds), got " << maxWork;
        throw std::invalid_argument(os.str());
    }
    if (!(work.seconds > maxWork)) return; // NaN estimates are none
    std::ostringstream os;
    os.precision(3);
    os << where << ": " << work.what << ", about " << seconds(work.seconds)
       << " of work, over the work limit of " << seconds(maxWork) << ": " << lighter
       << ", or raise the option maxWork";
    throw std::invalid_argument(os.str());
}

void requestStop() noexcept {
    gStop.store(true, std::memory_order_relaxed);
}

void clearStop() noexcept {
    gStop.store(false, std::memory_order_relaxed);
}

bool stopRequested() {
    if (gStop.load(std::memory_order_relaxed)) return true;
    const long long t = std::chrono::duration_cast<std::chrono::nanoseconds>(
                            std::chrono::steady_clock::now().time_since_epoch())
                            .count();
    long long last = gLastPoll.load(std::memory_order_relaxed);
    if (t - last < kPollEveryNs || !gLastPoll.compare_exchange_strong(last, t)) return false;
    std::function<bool()> poll;
    {
        const std::lock_guard<std::mutex> lock(gHooks);
        poll = gPoll;
    }
    if (poll && poll()) requestStop();
    return gStop.load(std::memory_order_relaxed);
}

void setStopPoll(std::function<bool()> poll) {
    const std::lock_guard<std::mutex> lock(gHooks);
    gPoll = std::move(poll);
}

void setProgressSink(std::function<void(const std::string&, bool)> sink) {
    const std::lock_guard<std::mutex> lock(gHooks);
    gSink = std::move(sink);
}

void tick(const std::string& stage) {
    if (tInnermost)
        tInnermost->update(-1.0, stage);
    else
        checkpoint("work");
}

void showProgressOnStandardError() {
    setProgressSink([](const std::string& line, bool final) {
        static const bool tty = isatty(STDERR_FILENO) != 0;
        static double last = -1e300;
        if (tty) {
            std::fprintf(stderr, "\r\033[K%s%s", line.c_str(), final ? "\n" : "");
        } else {
            const double t = now();
            if (!final && t - last < 10.0) return;
            last = t;
            std::fprintf(stderr, "%s\n", line.c_str());
        }
        std::fflush(stderr);
    });
}

void checkpoint(const std::string& where) {
    if (stopRequested()) throw Interrupted(where);
}

Progress::Progress(std::string where, double estimatedSeconds)
    : where_(std::move(where)), estimate_(estimatedSeconds), started_(now()), lastLine_(started_),
      outer_(tInnermost) {
    tInnermost = this;
}

Progress::~Progress() {
    tInnermost = outer_;
    if (!shown_) return;
    try {
        const bool stopped = std::uncaught_exceptions() > 0;
        emit(where_ + (stopped ? ": stopped after " : ": done in ") + seconds(now() - started_), true);
    } catch (...) { // a sink that throws must not end the program from a destructor
    }
}

void Progress::update(double fraction, const std::string& stage) {
    checkpoint(where_);
    const double t = now();
    const double elapsed = t - started_;
    if (fraction < 0.0) fraction = estimate_ > 0.0 ? std::min(0.99, elapsed / estimate_) : 0.0;
    if (elapsed < 1.0 && !(estimate_ > 1.0)) return; // quick steps stay silent
    if (shown_ && t - lastLine_ < 1.0) return;       // a line a second
    lastLine_ = t;
    shown_ = true;
    std::ostringstream os;
    os << where_ << ": " << int(std::lround(100.0 * std::min(1.0, std::max(0.0, fraction)))) << "%";
    if (!stage.empty()) os << " (" << stage << ")";
    os << ", " << seconds(elapsed);
    if (estimate_ > 0.0 && std::isfinite(estimate_)) os << " of about " << seconds(estimate_);
    os << "; Ctrl-C stops";
    emit(os.str(), false);
}

} // namespace mss
