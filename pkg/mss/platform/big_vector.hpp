// Large working arrays (grids, the coverage counts) on transparent huge pages.
#pragma once

#include "mss/grid.hpp"

#include <cstddef>

namespace mss {

namespace detail {
/// Writes a zero into every 2 MiB page of the fresh, zero-filled block [p, p + len), on the OpenMP threads
/// (big_vector.cpp). Why: the first touch of memory the virtual machine's host has not yet backed costs
/// about a millisecond or two a MB on a virtual machine (two threads: about a third less than serially), and
/// a generation's arrays are all fresh; touched in the caller's serial fill, the faults queue up one by one.
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
/// one to end unmaps them. Why: fresh memory costs the kernel's zeroing and a fault per huge page (20x more
/// where the virtual machine's host has to back it anew than where not), and a generation under a bound runs
/// the optimiser two or three times on one grain, each with a coverage of 3 bytes a voxel (torus 40 clipped:
/// the kernel's page clearing was a tenth of the run's CPU). generate() holds one.
class BigBlockReuse {
public:
    BigBlockReuse();
    ~BigBlockReuse();
    BigBlockReuse(const BigBlockReuse&) = delete;
    BigBlockReuse& operator=(const BigBlockReuse&) = delete;
};

// BigAllocator (mss/grid.hpp) maps a block of 2 MiB or more on its own, aligned to 2 MiB and marked for
// transparent huge pages (Linux madvise; the kernel's default mode here is "madvise", so std::allocator's
// blocks get 4 KiB pages). Why: each 4 KiB page of a fresh array costs a page fault on first touch, and under
// a virtual machine's kernel that was a fifth of a whole run of a small grain; huge pages take most of it
// away. Smaller blocks, and other systems, use std::allocator. The memory
// used is the same (the mapping ends at the block's last 4 KiB page; the kernel gives a huge page only to a
// whole 2 MiB range).

} // namespace mss
