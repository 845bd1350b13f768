// pkg/mss/cores: how busy the cores are, and the thread count that follows.
#include "mss/cores.hpp"

#include <gtest/gtest.h>

#include <csignal>
#include <vector>
#if defined(__linux__)
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
#endif
