// pkg/mss/generation/engine/candidates: E's maxima and ridge as candidate orbits.
#include "engine_fixtures.hpp"
#include "mss/core/edt.hpp"
#include "mss/generation/engine/candidates.hpp"

#include <gtest/gtest.h>

#include <random>

using namespace mss;
using namespace mss::engine;
using namespace mss::testing;

TEST(Candidates, MaximaFirstOnePerCanonicalPosition) {
    const VoxelGrid S = ellipsoid(24, 10, 7, 5);
    const ScalarGrid E = distanceTransform(S);
    const Symmetry sym(S.spec, {true, true, true});
    std::size_t ridge = 0;
    const std::vector<Orbit> c = candidateOrbits(E, sym, 0.5, &ridge);
    ASSERT_FALSE(c.empty());
    EXPECT_GT(ridge, 0u);
    // the first candidate is E's maximum: at the centre, on all three planes, radius about the half-axis 5
    EXPECT_NEAR((c[0].c - Vec3(11.5, 11.5, 11.5)).norm(), 0.0, 1.0);
    EXPECT_NEAR(c[0].r, 5.0, 1.0);
    for (std::size_t p = 0; p < c.size(); ++p)
        for (std::size_t q = p + 1; q < c.size(); ++q)
            EXPECT_GT((sym.canonical(c[p].c) - sym.canonical(c[q].c)).norm(), 1e-9);
    // rMinVox drops small candidates
    for (const Orbit& o : candidateOrbits(E, sym, 3.0)) EXPECT_GE(o.r, 3.0);
}
