#include "mss/core/maxima.hpp"

#include <gtest/gtest.h>

using namespace mss;

namespace {
/// A cone E = R - |x - c|: the distance field of a ball near its centre (eq. 9 with b = -1).
ScalarGrid cone(const Vec3& c, double R, int n = 15) {
    GridSpec g;
    g.dims = {n, n, n};
    ScalarGrid f(g, 0.0f);
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) f(i, j, k) = float(std::max(0.0, R - (Vec3(i, j, k) - c).norm()));
    return f;
}
} // namespace

TEST(Maxima, SubVoxelRefinementFindsTheApex) {
    const Vec3 c(7.3, 6.8, 7.15);
    const ScalarGrid f = cone(c, 6.0);
    const auto m = localMaxima(f);
    ASSERT_EQ(m.size(), 1u);
    EXPECT_EQ(m[0], (std::array<int, 3>{7, 7, 7}));
    const Maximum r = refineMaximum(f, m[0]);
    // along each axis the lines of eq. 13/18 meet at the cone's apex coordinate (exact for an axis-aligned
    // section through the apex; here the other coordinates are off by < 0.3, so allow 0.1)
    EXPECT_NEAR(r.position.x(), c.x(), 0.1);
    EXPECT_NEAR(r.position.y(), c.y(), 0.1);
    EXPECT_NEAR(r.position.z(), c.z(), 0.1);
    EXPECT_GE(r.value, f(7, 7, 7)); // eq. 24 never below the voxel value
    EXPECT_LE(r.value, 6.0 + 1e-6); // nor above the true maximum here
}

TEST(Maxima, ExactOnAVoxelCentre) {
    const ScalarGrid f = cone(Vec3(7, 7, 7), 5.0);
    const Maximum r = refineMaximum(f, {7, 7, 7});
    EXPECT_NEAR((r.position - Vec3(7, 7, 7)).norm(), 0.0, 1e-9);
    EXPECT_NEAR(r.value, 5.0, 1e-6);
}

TEST(Maxima, PlateausAreIncluded) {
    GridSpec g;
    g.dims = {9, 9, 9};
    ScalarGrid f(g, 0.0f);
    for (int k = 3; k <= 5; ++k)
        for (int j = 3; j <= 5; ++j)
            for (int i = 3; i <= 5; ++i) f(i, j, k) = 1.0f;
    f(4, 4, 4) = 2.0f;
    f(4, 4, 5) = 2.0f; // plateau of two voxels
    const auto m = localMaxima(f);
    ASSERT_EQ(m.size(), 2u);
    EXPECT_EQ(m[0], (std::array<int, 3>{4, 4, 4})); // ties in voxel order
    EXPECT_EQ(m[1], (std::array<int, 3>{4, 4, 5}));
}
