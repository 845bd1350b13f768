// pkg/mss/generation/engine/refine: coordinate-descent refinement.
#include "engine_fixtures.hpp"
#include "mss/core/edt.hpp"
#include "mss/generation/engine/refine.hpp"
#include "mss/generation/engine/selection.hpp"

#include <gtest/gtest.h>

#include <random>

using namespace mss;
using namespace mss::engine;
using namespace mss::testing;

TEST(Refine, NeverRaisesTheMismatchAndRespectsTheBound) {
    const VoxelGrid S = ellipsoid(28, 12, 6, 6);
    const ScalarGrid E = distanceTransform(S);
    engine::Request opt;
    opt.nSpheres = 6;
    opt.keepSymmetry = false;
    const BoundVox bound = [](const Vec3& c) { return 13.5 - c.x(); }; // a wall at x = 13.5 voxels
    Selection s(S, E, opt, bound);
    s.greedy();
    const long long before = s.cov.mismatch();
    refine(s);
    EXPECT_LE(s.cov.mismatch(), before);
    for (const Orbit& o : s.chosen) EXPECT_LE(o.r, 13.5 - o.c.x() + 1e-9);
}
