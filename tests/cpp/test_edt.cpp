#include "mss/core/edt.hpp"

#include <gtest/gtest.h>

#include <array>
#include <climits>
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

TEST(Edt, SparseSolidInALargeGridMatchesBruteForce) {
    // The strided passes run only on the solid's box per slice and plane (test_solid_box_window): blobs of
    // dense solid in a mostly empty grid, slices and planes with no solid, a blob against the grid's faces
    // and rows solid from end to end (no background in the row: infinite after the first pass)
    for (unsigned seed = 0; seed < 6; ++seed) {
        GridSpec g;
        g.dims = {19 + int(seed), 23 - int(seed), 17 + int(seed) % 3};
        VoxelGrid v(g, 0);
        std::mt19937 rng(seed);
        std::uniform_int_distribution<int> cx(0, g.dims[0] - 1), cy(0, g.dims[1] - 1), cz(0, g.dims[2] - 1);
        std::bernoulli_distribution dense(0.93);
        for (int blob = 0; blob < 3; ++blob) {
            const int x = cx(rng), y = cy(rng), z = cz(rng), rad = 2 + blob;
            for (int k = std::max(0, z - rad); k <= std::min(g.dims[2] - 1, z + rad); ++k)
                for (int j = std::max(0, y - rad); j <= std::min(g.dims[1] - 1, y + rad); ++j)
                    for (int i = std::max(0, x - rad); i <= std::min(g.dims[0] - 1, x + rad); ++i)
                        v(i, j, k) = dense(rng);
        }
        for (int i = 0; i < g.dims[0]; ++i) v(i, 3, 5) = 1; // a row without background
        for (int i = 0; i < 4; ++i) v(i, 0, 0) = 1;         // at the grid's corner
        const ScalarGrid e = distanceTransform(v);
        for (int k = 0; k < g.dims[2]; ++k)
            for (int j = 0; j < g.dims[1]; ++j)
                for (int i = 0; i < g.dims[0]; ++i)
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

TEST(Edt, FewSeedsFarApartMatchBruteForce) {
    // long distances along y and z (up to ~90 voxels): the envelope's intersections are fractions of whole
    // numbers up to ~10^4 compared by multiplying out (test_envelope_without_division); a few background
    // seeds in a solid block, checked against the distance to the nearest seed
    GridSpec g;
    g.dims = {12, 130, 110};
    VoxelGrid v(g, 1);
    std::mt19937 rng(7);
    std::vector<std::array<int, 3>> seeds{{0, 0, 0}, {11, 129, 109}};
    for (int s = 0; s < 5; ++s) seeds.push_back({int(rng() % 12), int(rng() % 130), int(rng() % 110)});
    for (const auto& s : seeds) v(s[0], s[1], s[2]) = 0;
    const ScalarGrid e = distanceTransform(v);
    for (int k = 0; k < g.dims[2]; ++k)
        for (int j = 0; j < g.dims[1]; ++j)
            for (int i = 0; i < g.dims[0]; ++i) {
                long long best = LLONG_MAX;
                for (const auto& s : seeds)
                    best = std::min(best, (long long)(s[0] - i) * (s[0] - i) +
                                              (long long)(s[1] - j) * (s[1] - j) +
                                              (long long)(s[2] - k) * (s[2] - k));
                ASSERT_NEAR(e(i, j, k), std::sqrt(double(best)), 1e-4) << i << " " << j << " " << k;
            }
}
