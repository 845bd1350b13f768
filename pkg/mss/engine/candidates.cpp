#include "mss/engine/candidates.hpp"
#include "mss/maxima.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <set>

namespace mss::engine {

namespace {
/// The ridge voxels of E in voxel order, whatever the threads.
std::vector<std::array<int, 3>> medialRidge(const ScalarGrid& E) {
    const auto& d = E.spec.dims;
    std::vector<std::vector<std::array<int, 3>>> ridgeSlices(std::size_t(std::max(d[2], 1)));
#pragma omp parallel for schedule(dynamic, 4)
    for (int k = 1; k < d[2] - 1; ++k)
        for (int j = 1; j < d[1] - 1; ++j)
            for (int i = 1; i < d[0] - 1; ++i) {
                const float e = E(i, j, k);
                if (e < 1.0f) continue;
                const float up = std::max({E(i - 1, j, k), E(i + 1, j, k), E(i, j - 1, k), E(i, j + 1, k),
                                           E(i, j, k - 1), E(i, j, k + 1)}) -
                                 e;
                if (up < 0.5f) ridgeSlices[std::size_t(k)].push_back({i, j, k});
            }
    std::vector<std::array<int, 3>> ridge;
    for (const auto& slice : ridgeSlices) ridge.insert(ridge.end(), slice.begin(), slice.end());
    return ridge;
}
} // namespace

std::vector<Orbit> candidateOrbits(const ScalarGrid& E, const Symmetry& sym, double rMinVox,
                                   std::size_t* ridgeCount) {
    std::vector<Orbit> cands;
    std::set<std::array<long long, 3>> seen;
    auto addCandidate = [&](const Vec3& c, double r) {
        if (r < rMinVox) return;
        Orbit o = sym.make(c, r); // constraints applied when the greedy first looks at it (bounded)
        const Vec3 key = sym.canonical(o.c) * 8.0;
        if (!seen.insert({std::llround(key.x()), std::llround(key.y()), std::llround(key.z())}).second)
            return;
        cands.push_back(o);
    };
    // A ball of radius E reaches the centre of the nearest background voxel; the surface lies about half a
    // voxel nearer, so candidates start at E - 0.5 + kRadiusSlack and the refinement tunes each radius.
    constexpr double kRadiusSlack = 0.5;
    for (const auto& v : localMaxima(E, 0.0f)) {
        const Maximum mx = refineMaximum(E, v);
        addCandidate(mx.position, mx.value - 0.5 + kRadiusSlack);
    }
    const std::vector<std::array<int, 3>> ridge = medialRidge(E);
    if (ridgeCount) *ridgeCount = ridge.size();
    constexpr std::size_t kMaxRidge = 10000;
    const std::size_t stride = std::max<std::size_t>(1, (ridge.size() + kMaxRidge - 1) / kMaxRidge);
    for (std::size_t q = 0; q < ridge.size(); q += stride) {
        const auto& v = ridge[q];
        addCandidate(Vec3(v[0], v[1], v[2]), E(v[0], v[1], v[2]) - 0.5 + kRadiusSlack);
    }
    return cands;
}

} // namespace mss::engine
