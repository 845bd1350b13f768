#include "mss/platform/cores.hpp"

#include <algorithm>
#include <fstream>
#include <limits>
#include <string>

#if defined(__linux__)
#include <dirent.h>
#include <sched.h>
#include <unistd.h>
#endif
#ifdef _OPENMP
#include <omp.h>
#endif
#include <vector>

namespace mss {

long processesRunning() {
    std::ifstream f("/proc/stat");
    std::string key;
    while (f >> key) {
        if (key == "procs_running") {
            long running = -1;
            f >> running;
            return running;
        }
        f.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
    }
    return -1;
}

long ownThreadsRunning() {
#if defined(__linux__)
    DIR* dir = opendir("/proc/self/task");
    if (!dir) return -1;
    long running = 0;
    while (const dirent* e = readdir(dir)) {
        if (e->d_name[0] == '.') continue;
        std::ifstream f(std::string("/proc/self/task/") + e->d_name + "/stat");
        std::string text;
        std::getline(f, text);
        // pid (comm) state ...: the command may hold spaces and parentheses, the state follows the last ')'
        const std::size_t close = text.rfind(')');
        if (close != std::string::npos && close + 2 < text.size() && text[close + 2] == 'R') ++running;
    }
    closedir(dir);
    return std::max(running, 1L); // the caller runs, whatever its stat said a moment ago
#else
    return -1;
#endif
}

long usableCores() {
#if defined(__linux__)
    cpu_set_t mask;
    if (sched_getaffinity(0, sizeof(mask), &mask) == 0) return CPU_COUNT(&mask);
    return std::max(1L, sysconf(_SC_NPROCESSORS_ONLN));
#else
    return 1;
#endif
}

int threadsForFreeCores(long cores, long others, int maxThreads) {
    const long free = cores - std::max(0L, others);
    return int(std::clamp<long>(free, 1, std::max(1, maxThreads)));
}

long othersRunning() {
    long least = -1;
    for (int look = 0; look < 5; ++look) {
        const long all = processesRunning(), own = ownThreadsRunning();
        if (all < 0 || own < 0) return -1;
        least = least < 0 ? std::max(0L, all - own) : std::min(least, std::max(0L, all - own));
        if (least == 0) break;
#if defined(__linux__)
        usleep(200);
#endif
    }
    return least;
}

bool spreadThreads(int threads) {
#if defined(__linux__) && defined(_OPENMP)
    cpu_set_t mask;
    if (threads < 1 || sched_getaffinity(0, sizeof(mask), &mask) != 0) return false;
    const int here = sched_getcpu();
    if (here < 0 || here >= CPU_SETSIZE || !CPU_ISSET(here, &mask)) return false;
    std::vector<int> cpus{here};
    for (int c = 0; c < CPU_SETSIZE && int(cpus.size()) < threads; ++c)
        if (c != here && CPU_ISSET(c, &mask)) cpus.push_back(c);
    if (int(cpus.size()) < threads) return false;
    int failed = 0;
#pragma omp parallel num_threads(threads) reduction(+ : failed)
    {
        const int t = omp_get_thread_num();
        cpu_set_t one;
        CPU_ZERO(&one);
        CPU_SET(cpus[std::size_t(t)], &one);
        failed += sched_setaffinity(0, sizeof(one), &one) != 0;
    }
    return failed == 0;
#else
    (void)threads;
    return false;
#endif
}

} // namespace mss
