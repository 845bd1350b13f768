// pkg/mss/generation/engine/polish: the joint polish of all centres and radii.
#include "engine_fixtures.hpp"
#include "mss/core/edt.hpp"
#include "mss/generate.hpp"
#include "mss/generation/engine/polish.hpp"
#include "mss/generation/engine/refine.hpp"
#include "mss/generation/engine/selection.hpp"
#include "mss/io.hpp"
#include "mss/voxelize.hpp"

#include <gtest/gtest.h>

using namespace mss;
using namespace mss::engine;
using namespace mss::testing;

namespace {

// resolution 40 and 8 spheres: on coarser grids and on smooth grains (ellipsoids, the two-lobed bean these
// tests first used) the refinement leaves nothing for the polish, and these tests would not see a set taken
const int RES = 40, NS = 8;
const std::string kData = MSS_TEST_DATA;

/// The bunny voxelised with @p res voxels along its shortest edge; @p mirrored: united with its mirror image
/// under the plane normal to x through the grid's centre (then that plane holds).
VoxelGrid bunny(int res, bool mirrored) {
    Resolution r;
    r.resolution = res;
    VoxelGrid v = voxelizeMesh(readMesh(kData + "/stanford_bunny_open.stl"), r);
    if (mirrored)
        for (int k = 0; k < v.nz(); ++k)
            for (int j = 0; j < v.ny(); ++j)
                for (int i = 0; i < v.nx() / 2; ++i) {
                    const std::uint8_t u = v(i, j, k) || v(v.nx() - 1 - i, j, k);
                    v(i, j, k) = v(v.nx() - 1 - i, j, k) = u;
                }
    return v;
}

std::vector<Ball> balls(const Selection& s) {
    std::vector<Ball> out;
    for (const Orbit& o : s.chosen)
        for (const Ball& b : s.sym.images(o)) out.push_back(b);
    return out;
}

} // namespace

TEST(Polish, NeverRaisesTheMismatchKeepsTheCoverageExactAndTheBound) {
    const VoxelGrid S = bunny(RES, false);
    const ScalarGrid E = distanceTransform(S);
    for (const bool bounded : {false, true}) {
        engine::Request opt;
        opt.nSpheres = NS;
        // a wall across the bunny
        const BoundVox bound =
            bounded ? BoundVox([](const Vec3& c) { return 0.6 * RES - c.x(); }) : BoundVox{};
        Selection s(S, E, opt, bound);
        s.greedy();
        refine(s);
        const std::vector<Orbit> before = s.chosen;
        const PolishReport p = polish(s);
        EXPECT_EQ(p.before, bruteMismatch(S, [&] {
                      std::vector<Ball> b;
                      for (const Orbit& o : before) b.push_back({o.c, o.r});
                      return b;
                  }()));
        EXPECT_LE(p.after, p.before) << "bounded " << bounded;
        EXPECT_LT(p.after, p.before) << "bounded " << bounded; // a moved set was taken
        EXPECT_EQ(p.after, s.cov.mismatch());
        EXPECT_EQ(s.cov.mismatch(), bruteMismatch(S, balls(s))); // the coverage is the set's
        ASSERT_EQ(s.chosen.size(), before.size());
        for (const Orbit& o : s.chosen) {
            EXPECT_GE(o.r, s.rMinVox);
            if (bounded) EXPECT_LE(o.r, 0.6 * RES - o.c.x() + 1e-9);
        }
        EXPECT_GT(p.steps, 0);
    }
}

TEST(Polish, KeepsTheMirrorPlanes) {
    // coordinates on a plane stay on it, the rest move as whole orbits
    const VoxelGrid S = bunny(RES, true);
    const ScalarGrid E = distanceTransform(S);
    engine::Request opt;
    opt.nSpheres = NS;
    Selection s(S, E, opt, BoundVox{});
    ASSERT_GE(s.sym.planes(), 1);
    s.greedy();
    refine(s);
    const std::vector<Orbit> before = s.chosen;
    const PolishReport p = polish(s);
    EXPECT_LT(p.after, p.before);
    ASSERT_EQ(s.chosen.size(), before.size());
    for (std::size_t q = 0; q < before.size(); ++q)
        for (int a = 0; a < 3; ++a)
            if (before[q].onPlane[std::size_t(a)]) {
                EXPECT_TRUE(s.chosen[q].onPlane[std::size_t(a)]);
                EXPECT_EQ(s.chosen[q].c[a], before[q].c[a]);
            }
    EXPECT_EQ(s.cov.mismatch(), bruteMismatch(S, balls(s)));
}

// The polish as the optimised method's last stage (GenerateOptions::polish): a lower mismatch at the same
// count, the bound held by the choice itself (nothing left for the final clipping to cut), rMin and a
// constraint plane kept.
TEST(Polish, LowersTheBunnysMismatchUnderTheBound) {
    const TriangleMesh bunny = readMesh(kData + "/stanford_bunny_open.stl");
    Resolution res;
    res.resolution = 50;
    GenerateOptions o;
    o.nSpheres = 30;
    const Result plain = generate(bunny, res, o);
    o.polish = true;
    const Result polished = generate(bunny, res, o);
    ASSERT_EQ(polished.spheres.size(), 30u);
    EXPECT_LE(polished.metrics.dice, 0.98 * plain.metrics.dice); // 0.0548 -> 0.0529 when written
    EXPECT_LE(polished.metrics.protrusion, polished.grid.h * (1 + 1e-9));
    EXPECT_EQ(polished.metrics.clipped, 0u);
    // with rMin and a plane through the middle
    const MeshInfo info = analyzeMesh(bunny);
    Plane cut;
    cut.point = 0.5 * (info.lower + info.upper);
    cut.normal = Vec3(0.3, 1.0, -0.2);
    o.planes = {cut};
    o.rMin = 4.0 * polished.grid.h;
    o.nSpheres = 12;
    const Result half = generate(bunny, res, o);
    ASSERT_GT(half.spheres.size(), 5u);
    EXPECT_EQ(half.metrics.clipped, 0u);
    for (std::size_t i = 0; i < half.spheres.size(); ++i) {
        EXPECT_GE(half.spheres.radii[i], o.rMin * (1 - 1e-12));
        EXPECT_GE(planeDistance(cut, half.spheres.centers[i]), half.spheres.radii[i] - 1e-12);
    }
}
