#include "mss/grid.hpp"
#include "mss/platform/big_vector.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <future>
#include <sstream>
#include <string>
#include <thread>
#include <vector>
#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

using namespace mss;

namespace {
/// The VmFlags line of the mapping of /proc/self/smaps that holds @p p ("" when none is found); @p end, if
/// given, receives the end of that mapping.
std::string vmFlagsOf(const void* p, std::uintptr_t* end = nullptr) {
    std::ifstream smaps("/proc/self/smaps");
    const auto a = reinterpret_cast<std::uintptr_t>(p);
    std::string line;
    bool inside = false;
    while (std::getline(smaps, line)) {
        std::uintptr_t lo = 0, hi = 0;
        char dash = 0;
        std::istringstream head(line);
        if (head >> std::hex >> lo >> dash >> hi && dash == '-') {
            inside = a >= lo && a < hi;
            if (inside && end) *end = hi;
            continue;
        }
        if (inside && line.rfind("VmFlags:", 0) == 0) return line;
    }
    return "";
}
} // namespace

TEST(BigVector, SmallAndLargeBlocksHoldTheirValues) {
    for (std::size_t n : {std::size_t(10), std::size_t(3) << 20}) { // 40 B and 12 MiB of floats
        BigVector<float> v(n);
        for (std::size_t q = 0; q < n; ++q) ASSERT_EQ(v[q], 0.0f) << q; // value-initialised
        for (std::size_t q = 0; q < n; ++q) v[q] = float(q % 1000);
        BigVector<float> copy = v;
        v.resize(2 * n, 7.0f); // grows into a new block, the old one given back
        for (std::size_t q = 0; q < n; q += 997) EXPECT_EQ(v[q], float(q % 1000));
        EXPECT_EQ(v[2 * n - 1], 7.0f);
        EXPECT_EQ(copy[n - 1], float((n - 1) % 1000));
    }
}

#if defined(__linux__)
TEST(BigVector, LargeBlocksAreAlignedAndMarkedForHugePages) {
    BigVector<std::uint8_t> big(std::size_t(5) << 20); // 5 MiB: two whole huge pages and a tail
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(big.data()) % (std::size_t(2) << 20), 0u);
    const std::string flags = vmFlagsOf(big.data());
    ASSERT_FALSE(flags.empty()) << "no mapping in /proc/self/smaps holds the block";
    EXPECT_NE(flags.find(" hg"), std::string::npos) << flags; // madvise(MADV_HUGEPAGE) took
    // a grid's values use it
    const VoxelGrid g(GridSpec{{256, 128, 128}, 1.0, Vec3::Zero()}, 1);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(g.data.data()) % (std::size_t(2) << 20), 0u);
    EXPECT_EQ(countSolid(g), g.size());
}

#ifdef MADV_POPULATE_WRITE
TEST(BigVector, ASmallPageTailIsPopulatedAtAllocation) {
    // 2 MiB and 300 KiB: a tail of small pages, populated when the block is mapped (not faulted one by one
    // in the caller's first fill); reserve() allocates without writing
    const long page = sysconf(_SC_PAGESIZE);
    void* probe =
        mmap(nullptr, std::size_t(page), PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    ASSERT_NE(probe, MAP_FAILED);
    const bool supported = madvise(probe, std::size_t(page), MADV_POPULATE_WRITE) == 0;
    munmap(probe, std::size_t(page));
    if (!supported) GTEST_SKIP() << "this kernel has no MADV_POPULATE_WRITE (Linux < 5.14)";
    constexpr std::size_t kHuge = std::size_t(2) << 20, kTail = 300 << 10;
    BigVector<std::uint8_t> v;
    v.reserve(kHuge + kTail);
    const std::size_t pages = kTail / std::size_t(page);
    std::vector<unsigned char> resident(pages);
    ASSERT_EQ(mincore(v.data() + kHuge, pages * std::size_t(page), resident.data()), 0);
    for (std::size_t q = 0; q < pages; ++q) EXPECT_TRUE(resident[q] & 1) << "tail page " << q;
}
#endif

TEST(BigVector, ATailOfHalfAHugePageOrMoreIsMappedWhole) {
    // 5 MiB: two whole huge pages and a tail of half of one, which gets a whole huge page of its own (4 KiB
    // pages there each faulted on their own); the mapping reaches to the end of that page
    constexpr std::size_t kHuge = std::size_t(2) << 20;
    BigVector<std::uint8_t> big(5 * (kHuge / 2));
    std::uintptr_t end = 0;
    ASSERT_FALSE(vmFlagsOf(big.data(), &end).empty());
    const auto begin = reinterpret_cast<std::uintptr_t>(big.data());
    EXPECT_GE(end, begin + 3 * kHuge);
    big.back() = 1; // the block's own bytes are usable to the last
    EXPECT_EQ(big.back(), 1);
}

TEST(BigVector, BlocksAreReusedWhileAScopeIsAliveAndUnmappedAfter) {
    constexpr std::size_t kN = std::size_t(3) << 20; // 3 MiB: a large block
    const void* first = nullptr;
    {
        const BigBlockReuse reuse;
        {
            BigVector<std::uint8_t> a(kN, 7);
            first = a.data();
        } // given back: kept
        BigVector<std::uint8_t> b(kN);
        EXPECT_EQ(static_cast<const void*>(b.data()), first);               // the same block again
        for (std::size_t q = 0; q < kN; q += 4093) ASSERT_EQ(b[q], 0) << q; // value-initialised anew
        BigVector<std::uint8_t> c(kN); // none kept of that size now: a fresh one
        EXPECT_NE(static_cast<const void*>(c.data()), first);
        {
            const BigBlockReuse nested; // ends first: nothing is unmapped while the outer one lives
        }
        const void* kept = c.data();
        c = BigVector<std::uint8_t>();
        BigVector<std::uint8_t> d(kN);
        EXPECT_EQ(static_cast<const void*>(d.data()), kept);
    } // the last scope ends: every kept block is unmapped
    BigVector<std::uint8_t> e(kN);
    {
        const void* p = e.data();
        e = BigVector<std::uint8_t>(); // no scope: unmapped at once
        EXPECT_TRUE(vmFlagsOf(p).empty()) << "a block given back outside any scope is still mapped";
    }
    // a scope on another thread keeps nothing of this one's (generations side by side on a worker's threads
    // never hold each other's blocks)
    std::promise<void> started, done;
    std::thread other([&] {
        const BigBlockReuse theirs;
        started.set_value();
        done.get_future().wait();
    });
    started.get_future().wait();
    BigVector<std::uint8_t> f(kN);
    const void* p = f.data();
    f = BigVector<std::uint8_t>();
    EXPECT_TRUE(vmFlagsOf(p).empty()) << "another thread's scope kept this thread's block";
    done.set_value();
    other.join();
}
#endif
