#include "mss/generation/tiny_grain.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace mss {

void oneSphereOfItsVolume(const VoxelGrid& S, const ScalarGrid& E,
                          const std::function<double(const Vec3&)>& bound, double rMin, SphereSet& out,
                          Metrics& m) {
    constexpr std::size_t kFewVoxels = 64;
    std::vector<std::array<int, 3>> solid;
    Vec3 sum = Vec3::Zero();
    for (int k = 0; k < S.spec.dims[2]; ++k)
        for (int j = 0; j < S.spec.dims[1]; ++j)
            for (int i = 0; i < S.spec.dims[0]; ++i)
                if (S(i, j, k)) {
                    if (solid.size() == kFewVoxels) return;
                    solid.push_back({i, j, k});
                    sum += Vec3(i, j, k);
                }
    if (solid.empty()) return;
    const Vec3 centroid = sum / double(solid.size());
    const auto better = [&](const std::array<int, 3>& a, const std::array<int, 3>& b) {
        const double ea = E(a[0], a[1], a[2]), eb = E(b[0], b[1], b[2]);
        if (ea != eb) return ea > eb;
        return (Vec3(a[0], a[1], a[2]) - centroid).squaredNorm() <
               (Vec3(b[0], b[1], b[2]) - centroid).squaredNorm();
    };
    const std::array<int, 3> at = *std::min_element(solid.begin(), solid.end(), better);
    const Vec3 c = S.spec.voxelCenter(at[0], at[1], at[2]);
    const double h = S.spec.h;
    double radius = std::cbrt(3.0 * double(solid.size()) / (4.0 * M_PI)) * h; // the grain's volume
    if (bound) radius = std::min(radius, bound(c));
    if (!(radius >= rMin) || !(radius > 0)) return;
    out.add(c, radius);
    m.warnings.push_back("the choice left no sphere on a grain of " + std::to_string(solid.size()) +
                         (solid.size() == 1 ? " voxel" : " voxels") +
                         ": one sphere of its volume at its centre");
}

} // namespace mss
