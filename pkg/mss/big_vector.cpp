#include "mss/big_vector.hpp"

namespace mss::detail {

void prefaultHugePages(void* p, std::size_t len) {
    constexpr std::size_t kPage = std::size_t(2) << 20;
    auto* bytes = static_cast<volatile unsigned char*>(p);
    const long long pages = static_cast<long long>(len / kPage);
    // the block is fresh from mmap: its bytes are zero, so writing a zero changes nothing but the mapping
#pragma omp parallel for schedule(static, 1) if (pages >= 2)
    for (long long q = 0; q < pages; ++q) bytes[std::size_t(q) * kPage] = 0;
}

} // namespace mss::detail
