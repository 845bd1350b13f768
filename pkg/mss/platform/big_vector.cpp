#include "mss/platform/big_vector.hpp"

#include <cstdint>
#include <utility>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace mss {

namespace {
/// Per thread: generations on threads side by side (a Dask worker's) keep and reuse their own blocks only,
/// and each thread's last scope gives its blocks back, so that overlapping generations never hold blocks for
/// good.
struct Reuse {
    int alive = 0; // BigBlockReuse objects
    std::vector<std::pair<void*, std::size_t>> blocks;
    std::size_t bytes = 0;
};
Reuse& reuse() {
    thread_local Reuse r;
    return r;
}
constexpr std::size_t kMaxKept = std::size_t(1) << 30;
constexpr std::size_t kHuge = std::size_t(2) << 20;

#if defined(__linux__)
/// The block's mapping: up to its last 4 KiB page, or up to a whole huge page where the part of the block
/// beyond its last whole huge page is at least half of one. The kernel gives a huge page only to a whole 2
/// MiB range, and each 4 KiB page of such a tail faulted on its own (femur 70 at resolution 103: about a
/// quarter of a run's faults were the tails of its four grids); a tail of less than
/// half stays on small pages, so that no block holds more than a MiB it does not use.
std::size_t mappedLength(std::size_t bytes) {
    static const std::size_t page = std::size_t(sysconf(_SC_PAGESIZE));
    const std::size_t tail = bytes % kHuge;
    if (tail >= kHuge / 2) return bytes - tail + kHuge;
    return (bytes + page - 1) / page * page;
}
#endif
} // namespace

namespace detail {

void prefaultHugePages(void* p, std::size_t len) {
    constexpr std::size_t kPage = std::size_t(2) << 20;
    auto* bytes = static_cast<volatile unsigned char*>(p);
    const long long pages = static_cast<long long>(len / kPage);
    // The tail beyond the last whole huge page (under half of one: BigAllocator) has small pages; they are
    // populated in the kernel, in two halves on the threads (MADV_POPULATE_WRITE, Linux 5.14; elsewhere they
    // fault on first touch as before). Faulted one by one in the caller's serial fill, the tails of E, S and
    // the coverage counts were hundreds of faults (populated here, the femur's voxelisation is about a third
    // faster, its EDT about 8%).
    const std::size_t tail = len - std::size_t(pages) * kPage;
    const long long tasks = pages + (tail > 0 ? 2 : 0);
    // the block is fresh from mmap: its bytes are zero, so writing a zero changes nothing but the mapping
#pragma omp parallel for schedule(static, 1) if (tasks >= 2)
    for (long long q = 0; q < tasks; ++q) {
        if (q < pages) {
            bytes[std::size_t(q) * kPage] = 0;
            continue;
        }
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
        constexpr std::size_t kSmall = 4096;
        const std::size_t half = (tail / 2 + kSmall - 1) / kSmall * kSmall;
        const std::size_t from = std::size_t(pages) * kPage + (q == pages ? 0 : half);
        const std::size_t to = q == pages ? std::size_t(pages) * kPage + half : len;
        if (to > from) madvise(static_cast<unsigned char*>(p) + from, to - from, MADV_POPULATE_WRITE);
#endif
    }
}

void* takeReusedBlock(std::size_t len) {
    Reuse& r = reuse();
    for (std::size_t q = 0; q < r.blocks.size(); ++q)
        if (r.blocks[q].second == len) {
            void* p = r.blocks[q].first;
            r.blocks.erase(r.blocks.begin() + std::ptrdiff_t(q));
            r.bytes -= len;
            return p;
        }
    return nullptr;
}

void* allocateBig(std::size_t bytes) {
#if defined(__linux__)
    const std::size_t len = mappedLength(bytes);
    if (void* kept = takeReusedBlock(len)) return kept;
    void* raw = mmap(nullptr, len + kHuge, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (raw == MAP_FAILED) throw std::bad_alloc();
    const auto start = reinterpret_cast<std::uintptr_t>(raw);
    const std::uintptr_t aligned = (start + kHuge - 1) & ~std::uintptr_t(kHuge - 1);
    if (aligned > start) munmap(raw, aligned - start);
    const std::uintptr_t tail = start + len + kHuge - (aligned + len);
    if (tail > 0) munmap(reinterpret_cast<void*>(aligned + len), tail);
#ifdef MADV_HUGEPAGE
    madvise(reinterpret_cast<void*>(aligned), len, MADV_HUGEPAGE); // a hint: failure changes nothing
#endif
    prefaultHugePages(reinterpret_cast<void*>(aligned), len);
    return reinterpret_cast<void*>(aligned);
#else
    return std::allocator<unsigned char>().allocate(bytes);
#endif
}

void freeBig(void* p, std::size_t bytes) noexcept {
#if defined(__linux__)
    const std::size_t len = mappedLength(bytes);
    if (!keepForReuse(p, len)) munmap(p, len);
#else
    std::allocator<unsigned char>().deallocate(static_cast<unsigned char*>(p), bytes);
#endif
}

bool keepForReuse(void* p, std::size_t len) {
    Reuse& r = reuse();
    if (r.alive == 0 || r.bytes + len > kMaxKept) return false;
    r.blocks.emplace_back(p, len);
    r.bytes += len;
    return true;
}

} // namespace detail

BigBlockReuse::BigBlockReuse() {
    Reuse& r = reuse();
    ++r.alive;
}

BigBlockReuse::~BigBlockReuse() {
    Reuse& r = reuse();
    if (--r.alive > 0) return;
#if defined(__linux__)
    for (const auto& [p, len] : r.blocks) munmap(p, len);
#endif
    r.blocks.clear();
    r.bytes = 0;
}

} // namespace mss
