// Small voxel grains and a brute-force mismatch for the engine's unit tests (test_coverage, test_symmetry,
// ...).
#pragma once

#include "mss/generation/engine/ball.hpp"

#include <vector>

namespace mss::testing {

using engine::Ball;

inline VoxelGrid grid(int nx, int ny, int nz) {
    GridSpec g;
    g.dims = {nx, ny, nz};
    g.h = 1.0;
    return VoxelGrid(g, 0);
}

/// An ellipsoid (semi-axes a, b, c voxels) centred in a grid: symmetric under all three mirror planes.
inline VoxelGrid ellipsoid(int n, double a, double b, double c) {
    VoxelGrid v = grid(n, n, n);
    const double m = 0.5 * (n - 1);
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const double x = (i - m) / a, y = (j - m) / b, z = (k - m) / c;
                v(i, j, k) = x * x + y * y + z * z <= 1.0;
            }
    return v;
}

/// |S xor union of balls| by brute force: a voxel is covered when its centre is within r of a centre.
inline long long bruteMismatch(const VoxelGrid& S, const std::vector<Ball>& balls) {
    long long n = 0;
    for (int k = 0; k < S.nz(); ++k)
        for (int j = 0; j < S.ny(); ++j)
            for (int i = 0; i < S.nx(); ++i) {
                bool in = false;
                for (const Ball& b : balls) in = in || (Vec3(i, j, k) - b.c).squaredNorm() <= b.r * b.r;
                n += in != (S(i, j, k) != 0);
            }
    return n;
}

} // namespace mss::testing
