#include "mss/edt.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#ifdef _OPENMP
#include <omp.h>
#endif

using namespace mss;

namespace {
VoxelGrid randomVolume(int nx, int ny, int nz, double density, unsigned seed) {
    GridSpec g;
    g.dims = {nx, ny, nz};
    VoxelGrid v(g, 0);
    std::mt19937 rng(seed);
    std::bernoulli_distribution solid(density);
    for (auto& x : v.data) x = solid(rng);
    v(0, 0, 0) = 0; // at least one background voxel
    return v;
}

double bruteForce(const VoxelGrid& v, int i, int j, int k) {
    if (!v(i, j, k)) return 0.0;
    double best = 1e300;
    for (int c = 0; c < v.nz(); ++c)
        for (int b = 0; b < v.ny(); ++b)
            for (int a = 0; a < v.nx(); ++a)
                if (!v(a, b, c))
                    best = std::min(best, double((a - i) * (a - i) + (b - j) * (b - j) + (c - k) * (c - k)));
    return std::sqrt(best);
}
} // namespace

TEST(Edt, MatchesBruteForceOnRandomGrids) {
    for (unsigned seed = 0; seed < 12; ++seed) {
        const int nx = 3 + seed % 9, ny = 2 + (seed * 7) % 11, nz = 1 + (seed * 5) % 8;
        const double density = 0.5 + 0.04 * seed; // up to 0.94: long distances
        const VoxelGrid v = randomVolume(nx, ny, nz, density, seed);
        const ScalarGrid e = distanceTransform(v);
        for (int k = 0; k < nz; ++k)
            for (int j = 0; j < ny; ++j)
                for (int i = 0; i < nx; ++i)
                    // squared distances are integers, exact in float: the only error is the final sqrt
                    ASSERT_NEAR(e(i, j, k), bruteForce(v, i, j, k), 1e-5)
                        << seed << " " << i << " " << j << " " << k;
    }
}

TEST(Edt, SingleBackgroundVoxelGivesEuclideanDistance) {
    GridSpec g;
    g.dims = {9, 7, 5};
    VoxelGrid v(g, 1);
    v(2, 3, 1) = 0;
    const ScalarGrid e = distanceTransform(v);
    EXPECT_FLOAT_EQ(e(8, 6, 4), std::sqrt(36.0f + 9.0f + 9.0f));
    EXPECT_FLOAT_EQ(e(2, 3, 1), 0.0f);
    EXPECT_FLOAT_EQ(e(3, 3, 1), 1.0f);
}

TEST(Edt, IsOneLipschitz) {
    const VoxelGrid v = randomVolume(20, 17, 13, 0.9, 99);
    const ScalarGrid e = distanceTransform(v);
    for (int k = 0; k < 13; ++k)
        for (int j = 0; j < 17; ++j)
            for (int i = 0; i + 1 < 20; ++i) ASSERT_LE(std::abs(e(i + 1, j, k) - e(i, j, k)), 1.0f + 1e-5f);
}

TEST(Edt, SameResultForAnyThreadCount) {
    const VoxelGrid v = randomVolume(64, 48, 40, 0.97, 7);
#ifdef _OPENMP
    omp_set_num_threads(1);
#endif
    const ScalarGrid a = distanceTransform(v);
#ifdef _OPENMP
    omp_set_num_threads(4);
#endif
    const ScalarGrid b = distanceTransform(v);
    EXPECT_EQ(a.data, b.data);
}

TEST(Edt, NoBackgroundIsAnError) {
    GridSpec g;
    g.dims = {3, 3, 3};
    VoxelGrid v(g, 1);
    EXPECT_THROW(distanceTransform(v), std::invalid_argument);
}
