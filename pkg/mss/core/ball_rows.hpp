// Internal: the voxels of a ball, row by row. The one place this is written, so that the generator's running
// mismatch and the voxelisation of its result (voxelizeSpheres) count exactly the same voxels.
#pragma once

#include "mss/grid.hpp"

#include <algorithm>
#include <cmath>

namespace mss::detail {

/// floor and ceil to int without a libm call (x86-64 baseline has no rounding instruction); |x| < 2^31.
inline int floorInt(double x) {
    const int i = static_cast<int>(x);
    return i - (static_cast<double>(i) > x);
}
inline int ceilInt(double x) {
    const int i = static_cast<int>(x);
    return i + (static_cast<double>(i) < x);
}

/// Calls f(j, k, i0, i1) for every x-row (j, k), with kLo <= k <= kHi, of the voxels whose centres lie in the
/// ball of centre @p c and radius @p r (voxel coordinates and units; a centre at distance <= r is inside);
/// i0..i1 is the row's run, clipped to the grid @p dims.
template <class F>
inline void forBallRows(const Vec3& c, double r, const std::array<int, 3>& dims, int kLo, int kHi, F&& f) {
    const double r2 = r * r;
    const int k0 = std::max({0, kLo, ceilInt(c.z() - r)}),
              k1 = std::min({dims[2] - 1, kHi, floorInt(c.z() + r)});
    for (int k = k0; k <= k1; ++k) {
        const double dz = k - c.z();
        const double rz2 = r2 - dz * dz;
        if (rz2 < 0) continue;
        const double ry = std::sqrt(rz2);
        const int j0 = std::max(0, ceilInt(c.y() - ry)), j1 = std::min(dims[1] - 1, floorInt(c.y() + ry));
        for (int j = j0; j <= j1; ++j) {
            const double dy = j - c.y();
            const double rx2 = rz2 - dy * dy;
            if (rx2 < 0) continue;
            const double rx = std::sqrt(rx2);
            const int i0 = std::max(0, ceilInt(c.x() - rx)), i1 = std::min(dims[0] - 1, floorInt(c.x() + rx));
            if (i0 <= i1) f(j, k, i0, i1);
        }
    }
}

} // namespace mss::detail
