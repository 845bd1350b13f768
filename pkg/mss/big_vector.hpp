// Large working arrays (grids, the coverage counts) on transparent huge pages.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <new>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace mss {

namespace detail {
/// Writes a zero into every 2 MiB page of the fresh, zero-filled block [p, p + len), on the OpenMP threads
/// (big_vector.cpp). Why: the first touch of memory the virtual machine's host has not yet backed costs
/// ~1.1-1.9 ms a MB here (64 MB: 93-121 ms serially, 68-70 ms on two threads), and a generation's arrays are
/// all fresh; touched in the caller's serial fill, the faults queue up one by one.
void prefaultHugePages(void* p, std::size_t len);
/// A block of exactly @p len mapped bytes given back on this thread while a BigBlockReuse is alive on it, or
/// null (big_vector.cpp).
void* takeReusedBlock(std::size_t len);
/// Keeps the mapped block [p, p + len) for takeReusedBlock() while a BigBlockReuse is alive on this thread;
/// false: not kept (none alive, or a GiB kept already), the caller unmaps it.
bool keepForReuse(void* p, std::size_t len);
} // namespace detail

/// While one of these is alive on a thread, large blocks given back on that thread are kept and handed out
/// again to an allocation of the same size on it, instead of unmapped and mapped afresh; the thread's last
/// one to end unmaps them. Why: fresh memory costs the kernel's zeroing and a fault per huge page (1.7 ms a
/// MB where the virtual machine's host has to back it anew, 0.08 where not), and a generation under a bound
/// runs the optimiser two or three times on one grain, each with a coverage of 3 bytes a voxel (torus 40
/// --clip: 55 MB each, clear_page 11% of the run's CPU). generate() holds one.
class BigBlockReuse {
public:
    BigBlockReuse();
    ~BigBlockReuse();
    BigBlockReuse(const BigBlockReuse&) = delete;
    BigBlockReuse& operator=(const BigBlockReuse&) = delete;
};

/// Allocator for the large arrays of a generation: a block of 2 MiB or more is mapped on its own, aligned to
/// 2 MiB and marked for transparent huge pages (Linux madvise; the kernel's default mode here is "madvise",
/// so std::allocator's blocks get 4 KiB pages). Why: each 4 KiB page of a fresh array costs a page fault on
/// first touch, and under a virtual machine's kernel that was a fifth of a whole run (ellipsoid 10 spheres,
/// 210 x 107 x 107 voxels, ~29 MB of arrays filled once: 0.255 s, of it the EDT 0.043 s; with huge pages
/// 0.20 s and 0.021 s). Smaller blocks, and other systems, use std::allocator. The memory used is the same
/// (the mapping ends at the block's last 4 KiB page; the kernel gives a huge page only to a whole 2 MiB
/// range).
template <class T> struct BigAllocator {
    using value_type = T;

    BigAllocator() noexcept = default;
    template <class U> BigAllocator(const BigAllocator<U>&) noexcept {}

    T* allocate(std::size_t n) {
        if (n > std::numeric_limits<std::size_t>::max() / sizeof(T)) throw std::bad_array_new_length();
#if defined(__linux__)
        const std::size_t bytes = n * sizeof(T);
        if (bytes >= kHuge) {
            const std::size_t len = mappedLength(bytes);
            if (void* kept = detail::takeReusedBlock(len)) return static_cast<T*>(kept);
            void* raw =
                mmap(nullptr, len + kHuge, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
            if (raw == MAP_FAILED) throw std::bad_alloc();
            const auto start = reinterpret_cast<std::uintptr_t>(raw);
            const std::uintptr_t aligned = (start + kHuge - 1) & ~std::uintptr_t(kHuge - 1);
            if (aligned > start) munmap(raw, aligned - start);
            const std::uintptr_t tail = start + len + kHuge - (aligned + len);
            if (tail > 0) munmap(reinterpret_cast<void*>(aligned + len), tail);
#ifdef MADV_HUGEPAGE
            madvise(reinterpret_cast<void*>(aligned), len, MADV_HUGEPAGE); // a hint: failure changes nothing
#endif
            detail::prefaultHugePages(reinterpret_cast<void*>(aligned), len);
            return reinterpret_cast<T*>(aligned);
        }
#endif
        return std::allocator<T>().allocate(n);
    }

    void deallocate(T* p, std::size_t n) noexcept {
#if defined(__linux__)
        if (n * sizeof(T) >= kHuge) {
            const std::size_t len = mappedLength(n * sizeof(T));
            if (!detail::keepForReuse(p, len)) munmap(p, len);
            return;
        }
#endif
        std::allocator<T>().deallocate(p, n);
    }

    template <class U> bool operator==(const BigAllocator<U>&) const noexcept {
        return true;
    }
    template <class U> bool operator!=(const BigAllocator<U>&) const noexcept {
        return false;
    }

private:
    static constexpr std::size_t kHuge = std::size_t(2) << 20;
#if defined(__linux__)
    /// The block's mapping: up to its last 4 KiB page, or up to a whole huge page where the part of the
    /// block beyond its last whole huge page is at least half of one. The kernel gives a huge page only to a
    /// whole 2 MiB range, and each 4 KiB page of such a tail faulted on its own (~11 us each on this VM's
    /// kernel: femur 70 at resolution 103, ~400 of a run's ~1500 faults were the tails of its four grids);
    /// a tail of less than half stays on small pages, so that no block holds more than a MiB it does not use
    /// (femur at resolution 100: peak memory 13.2 -> 13.5 B/voxel, at most; rounding every tail: 14.3).
    static std::size_t mappedLength(std::size_t bytes) {
        static const std::size_t page = std::size_t(sysconf(_SC_PAGESIZE));
        const std::size_t tail = bytes % kHuge;
        if (tail >= kHuge / 2) return bytes - tail + kHuge;
        return (bytes + page - 1) / page * page;
    }
#endif
};

/// A std::vector whose large blocks lie on huge pages (see BigAllocator).
template <class T> using BigVector = std::vector<T, BigAllocator<T>>;

} // namespace mss
