// pkg/mss/generation/engine/symmetry: mirror planes and orbits.
#include "engine_fixtures.hpp"
#include "mss/generation/engine/symmetry.hpp"

#include <gtest/gtest.h>

#include <random>

using namespace mss;
using namespace mss::engine;
using namespace mss::testing;

TEST(Symmetry, MirrorAxesAndOrbits) {
    VoxelGrid S = ellipsoid(20, 8, 6, 4);
    bool exact = false;
    auto axes = mirrorAxes(S, countSolid(S), exact);
    EXPECT_TRUE(axes[0] && axes[1] && axes[2]);
    EXPECT_TRUE(exact);
    // a voxel off the x mirror in a bigger grain: symmetric within the tolerance (0.1% of the solid), not
    // exactly
    VoxelGrid T = ellipsoid(40, 16, 12, 8);
    T(6, 20, 20) = 0;
    axes = mirrorAxes(T, countSolid(T), exact);
    EXPECT_TRUE(axes[0]);
    EXPECT_FALSE(exact);
    // a slab under the lower half breaks the z symmetry for good
    for (int j = 0; j < 20; ++j)
        for (int i = 0; i < 20; ++i) S(i, j, 0) = S(i, j, 1) = 1;
    axes = mirrorAxes(S, countSolid(S), exact);
    EXPECT_TRUE(axes[0] && axes[1]);
    EXPECT_FALSE(axes[2]);
    const Symmetry sym(S.spec, {true, true, false});
    EXPECT_EQ(sym.planes(), 2);
    const Orbit off = sym.make(Vec3(4, 5, 6), 1);
    EXPECT_EQ(sym.images(off).size(), 4u);
    const Orbit on = sym.make(Vec3(9.8, 5, 6), 1); // within half a voxel of the x plane: snapped onto it
    EXPECT_EQ(on.c.x(), 9.5);
    EXPECT_EQ(sym.images(on).size(), 2u);
    for (const Ball& b : sym.images(off)) EXPECT_EQ((sym.canonical(b.c) - off.c).norm(), 0.0);
    Orbit broken = off;
    broken.broken = true;
    EXPECT_EQ(sym.images(broken).size(), 1u);
}
