#include "mss/cores.hpp"

#include <algorithm>
#include <fstream>
#include <limits>
#include <string>

#if defined(__linux__)
#include <dirent.h>
#include <sched.h>
#include <unistd.h>
#endif

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

} // namespace mss
