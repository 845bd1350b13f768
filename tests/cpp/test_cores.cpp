// pkg/mss/cores: how busy the cores are, and the thread count that follows.
#include "mss/platform/cores.hpp"

#include <gtest/gtest.h>

#include <csignal>
#include <vector>
#ifdef _OPENMP
#include <omp.h>
#endif
#if defined(__linux__)
#include <sched.h>
#include <sys/wait.h>
#include <unistd.h>
#endif

using namespace mss;

TEST(Cores, ThreadsTakeTheFreeCoresOnly) {
    EXPECT_EQ(threadsForFreeCores(2, 0, 2), 2);
    EXPECT_EQ(threadsForFreeCores(2, 1, 2), 1);
    EXPECT_EQ(threadsForFreeCores(2, 3, 2), 1); // more running than cores: one thread, never none
    EXPECT_EQ(threadsForFreeCores(8, 2, 4), 4); // never more than asked
    EXPECT_EQ(threadsForFreeCores(8, 2, 16), 6);
    EXPECT_EQ(threadsForFreeCores(4, -1, 4), 4); // unknown others count as none
}

#if defined(__linux__)
TEST(Cores, ProcReportsThisProcessRunning) {
    EXPECT_GE(processesRunning(), 1);
    EXPECT_GE(ownThreadsRunning(), 1);
    EXPECT_GE(usableCores(), 1);
    EXPECT_GE(othersRunning(), 0);
}

TEST(Cores, BusyProcessesCountAsOthers) {
    // three children that spin: as many others running (the machine's other work may add to it)
    std::vector<pid_t> kids;
    for (int k = 0; k < 3; ++k) {
        const pid_t pid = fork();
        ASSERT_GE(pid, 0);
        if (pid == 0)
            for (volatile unsigned long spin = 0;; spin = spin + 1) {
            }
        kids.push_back(pid);
    }
    usleep(100000);
    const long others = othersRunning();
    for (pid_t pid : kids) {
        kill(pid, SIGKILL);
        waitpid(pid, nullptr, 0);
    }
    EXPECT_GE(others, 3);
    EXPECT_EQ(threadsForFreeCores(usableCores(), others, int(usableCores())),
              std::max(1L, usableCores() - others));
}

#ifdef _OPENMP
TEST(Cores, SpreadThreadsPinsEachThreadToACoreOfItsOwn) {
    EXPECT_FALSE(spreadThreads(int(usableCores()) + 1)); // more threads than cores: nothing to pin to
    EXPECT_FALSE(spreadThreads(0));
    if (usableCores() < 2) GTEST_SKIP() << "one core: no two threads to spread";
    cpu_set_t saved;
    ASSERT_EQ(sched_getaffinity(0, sizeof(saved), &saved), 0);
    ASSERT_TRUE(spreadThreads(2));
    int count[2] = {0, 0}, cpu[2] = {-1, -1};
#pragma omp parallel num_threads(2)
    {
        const int t = omp_get_thread_num();
        cpu_set_t mask;
        if (sched_getaffinity(0, sizeof(mask), &mask) == 0) {
            count[t] = CPU_COUNT(&mask);
            for (int c = 0; c < CPU_SETSIZE; ++c)
                if (CPU_ISSET(c, &mask)) cpu[t] = c;
        }
        sched_setaffinity(0, sizeof(saved), &saved); // the other tests run free again
    }
    EXPECT_EQ(count[0], 1);
    EXPECT_EQ(count[1], 1);
    EXPECT_NE(cpu[0], cpu[1]);
    EXPECT_TRUE(CPU_ISSET(cpu[0], &saved) && CPU_ISSET(cpu[1], &saved));
}
#endif
#endif
