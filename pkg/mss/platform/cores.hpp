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

/// Pins each thread of an OpenMP team of @p threads to a core of its own (the calling thread to the core it
/// is on, the others to the next cores of the affinity mask); false, and nothing changed, when the mask has
/// fewer cores or the system cannot pin (then threads go where the scheduler puts them). For a process that
/// owns cores that are free: a new OpenMP thread starts on its creator's core, and on a 2-core VM the two
/// often shared one core for milliseconds to the whole run (a worker that sleeps is woken onto the waker's
/// core again), each parallel region then as slow as one thread or slower (femur 70: the ASCII STL parsed in
/// two halves, one after the other on one core). libgomp reuses its threads, so later teams of up to
/// @p threads run on distinct cores.
bool spreadThreads(int threads);

} // namespace mss
