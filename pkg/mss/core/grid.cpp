#include "mss/grid.hpp"

#include <algorithm>
#include <numeric>
#include <sstream>

namespace mss {

std::size_t countSolid(const VoxelGrid& g) {
    // byte counters over runs of 255 (they cannot overflow), so that the loop vectorises into byte compares
    // and adds (a size_t counter widened every byte was several times slower, and this runs five times a
    // generation)
    const std::uint8_t* p = g.data.data();
    const std::size_t size = g.data.size();
    std::size_t n = 0;
    std::size_t at = 0;
    for (; at + 255 <= size; at += 255) {
        std::uint8_t run = 0;
        for (std::size_t i = 0; i < 255; ++i) run = static_cast<std::uint8_t>(run + (p[at + i] != 0));
        n += run;
    }
    for (; at < size; ++at) n += (p[at] != 0);
    return n;
}

void checkGridSize(const char* where, const std::array<long long, 3>& dims, std::size_t bytesPerVoxel,
                   std::size_t memoryLimit) {
    for (long long d : dims) {
        if (d <= 0) {
            std::ostringstream os;
            os << where << ": grid dimensions must be positive, got " << dims[0] << "x" << dims[1] << "x"
               << dims[2];
            throw std::invalid_argument(os.str());
        }
    }
    const long double voxels = static_cast<long double>(dims[0]) * dims[1] * dims[2];
    const long double bytes = voxels * bytesPerVoxel;
    if (voxels > 2147483647.0L || bytes > static_cast<long double>(memoryLimit)) {
        std::ostringstream os;
        os.precision(3);
        os << where << ": a grid of " << dims[0] << "x" << dims[1] << "x" << dims[2] << " voxels would need "
           << static_cast<double>(bytes / (1024.0L * 1024.0L * 1024.0L)) << " GiB";
        if (bytes > static_cast<long double>(memoryLimit))
            os << ", over the limit of " << static_cast<double>(memoryLimit) / (1024.0 * 1024.0 * 1024.0)
               << " GiB";
        else
            os << " and has over 2^31 - 1 voxels, more than a grid can index";
        // the fraction of the voxels along each edge that would fit both bounds (under 1)
        const long double fits =
            std::min(static_cast<long double>(memoryLimit) / bytesPerVoxel, 2147483647.0L);
        os << "; choose a coarser resolution (about " << static_cast<double>(std::cbrt(fits / voxels))
           << " times the voxel count along each edge would fit)";
        throw std::invalid_argument(os.str());
    }
}

} // namespace mss
