// pkg/mss/generation/engine/selection: greedy selection and pruning.
#include "engine_fixtures.hpp"
#include "mss/core/edt.hpp"
#include "mss/generation/engine/refine.hpp"
#include "mss/generation/engine/selection.hpp"

#include <gtest/gtest.h>

#include <random>

using namespace mss;
using namespace mss::engine;
using namespace mss::testing;

TEST(Selection, GreedyKeepsTheBudgetAndPruneTheTarget) {
    const VoxelGrid S = ellipsoid(28, 12, 6, 6);
    const ScalarGrid E = distanceTransform(S);
    engine::Request opt;
    opt.nSpheres = 5;
    Selection s(S, E, opt, BoundVox{});
    EXPECT_EQ(s.sym.planes(), 3);
    s.greedy();
    EXPECT_LE(s.placed, 5u);
    std::vector<Ball> balls;
    for (const Orbit& o : s.chosen)
        for (const Ball& b : s.sym.images(o)) balls.push_back(b);
    EXPECT_EQ(balls.size(), s.placed);
    EXPECT_EQ(s.cov.mismatch(), bruteMismatch(S, balls));
    // problem (ii): more spheres than a loose Dice target needs; pruning drops some, the target stays met
    engine::Request q;
    q.dice = 0.5;
    Selection t(S, E, q, BoundVox{});
    for (std::size_t i = 0; i < 8 && i < t.cands.size(); ++i) t.place(t.cands[i]);
    ASSERT_TRUE(t.met());
    const std::size_t before = t.placed;
    EXPECT_TRUE(t.prune());
    EXPECT_TRUE(t.met());
    EXPECT_LT(t.placed, before);
    std::vector<Ball> left;
    for (const Orbit& o : t.chosen)
        for (const Ball& b : t.sym.images(o)) left.push_back(b);
    EXPECT_EQ(t.cov.mismatch(), bruteMismatch(S, left));
}
