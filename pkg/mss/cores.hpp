// How busy the cores are, for thread counts that do not oversubscribe a shared machine (Linux /proc).
#pragma once

namespace mss {

/// The threads running on the machine now (/proc/stat's procs_running, the caller's included); -1 where
/// unknown.
long processesRunning();

/// The threads of this process running now (state R in /proc/self/task/*/stat, the caller included); -1
/// where unknown. An OpenMP team's threads that spin while they wait run too: they are the team a parallel
/// region of this process takes, not competition for it.
long ownThreadsRunning();

/// The cores this process may use: its affinity mask (as OpenMP counts them).
long usableCores();

/// Threads for work of up to @p maxThreads threads when @p others threads of other processes run on
/// @p cores cores: the cores free of them, at least one, at most @p maxThreads.
int threadsForFreeCores(long cores, long others, int maxThreads);

/// The threads of other processes running now: the least of five looks 0.2 ms apart (a shell starting the
/// rest of a pipeline runs for a moment) at processesRunning() less ownThreadsRunning(); -1 where unknown.
long othersRunning();

} // namespace mss
