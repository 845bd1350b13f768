// Comparing sphere sets with a grain (pkg/mss/generation/compare.cpp): frames, alignment, protrusion, mass
// errors.
#include "mss/compare.hpp"
#include "mss/io.hpp"
#include "mss/spheres.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace mss;

namespace {
const std::string kData = MSS_TEST_DATA;

template <class F> void expectError(F&& f, const std::string& fragment) {
    try {
        f();
        FAIL() << "no exception, expected: " << fragment;
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
}
} // namespace

TEST(Compare, ClumpFavierFemurScoresAsMeasuredIndependently) {
    const TriangleMesh femur = readMesh(kData + "/human_femur.stl");
    const Comparison c = compareSpheres(femur, readSpheres(kData + "/clump/FA_femur_N70_min.vtk"), {});
    EXPECT_EQ(c.spheres, 70u);
    EXPECT_NEAR(c.score.dice, 0.604, 0.02); // shared/data/clump/README.md: an independent scorer's 0.604
    EXPECT_GT(c.insideBox, 0.9);
}

TEST(Compare, AnotherFrameIsRefusedAndAlignmentRecoversIt) {
    const TriangleMesh femur = readMesh(kData + "/human_femur.stl");
    const SphereSet eu = readSpheres(kData + "/clump/EU_femur_N70_div150_rMin4_ov0.95.txt");
    expectError([&] { compareSpheres(femur, eu, {}); }, "register it with the option align (bbox");
    CompareOptions o;
    o.align = Align::BoundingBox;
    const Comparison c = compareSpheres(femur, eu, o);
    EXPECT_LE(c.score.dice, 0.085); // 0.0789 with CLUMP's shift undone by hand
    EXPECT_GT(c.transform.translation.norm(), 100.0);
}

TEST(Compare, AlignmentUndoesAKnownMotion) {
    const TriangleMesh ell = readMesh(kData + "/ellipsoid_2_1_1.stl");
    const SphereSet fa = readSpheres(kData + "/clump/FA_ellipsoid_N10_min.txt");
    const double d0 = compareSpheres(ell, fa, {}).score.dice;
    RigidTransform m; // a quarter turn about z and a shift far away
    m.rotation << 0, -1, 0, 1, 0, 0, 0, 0, 1;
    m.translation = Vec3(50, -20, 7);
    const SphereSet moved = transformSpheres(fa, m);
    CompareOptions o;
    for (Align a : {Align::Centroid, Align::Principal}) {
        o.align = a;
        const Comparison c = compareSpheres(
            ell,
            a == Align::Centroid ? transformSpheres(fa, {Eigen::Matrix3d::Identity(), m.translation}) : moved,
            o);
        EXPECT_NEAR(c.score.dice, d0, 0.002) << int(a);
    }
    EXPECT_EQ(parseAlign("bbox"), Align::BoundingBox);
    expectError([] { parseAlign("box"); }, "none, centroid, bbox or principal");
}

TEST(Compare, ProtrusionAndMassErrors) {
    const TriangleMesh unit = readMesh(kData + "/sphere_r1.stl"); // radius 1, inscribed facets
    SphereSet s;
    s.add(Vec3(0, 0, 0), 1.2);
    const Comparison big = compareSpheres(unit, s, {});
    EXPECT_NEAR(big.protrusion, 0.2, 0.01);
    EXPECT_NEAR(big.massError, 1.2 * 1.2 * 1.2 / (4.1865 / (4.0 / 3.0 * M_PI)) - 1, 0.02);
    EXPECT_LT(big.centroidError, 1e-3);
    SphereSet small;
    small.add(Vec3(0.1, 0, 0), 0.5);
    const Comparison in = compareSpheres(unit, small, {});
    EXPECT_EQ(in.protrusion, 0.0); // wholly inside
    EXPECT_EQ(in.smallestRadius, 0.5);
    EXPECT_NEAR(in.centroidError, 0.1 / std::sqrt(12.0), 0.01);
}

TEST(Compare, VoxelTarget) {
    GridSpec g;
    g.dims = {20, 20, 20};
    g.h = 0.5;
    VoxelGrid v(g, 0);
    for (int k = 4; k < 16; ++k)
        for (int j = 4; j < 16; ++j)
            for (int i = 4; i < 16; ++i) v(i, j, k) = 1; // the cube [1.75, 7.75]^3
    SphereSet s;
    s.add(Vec3(4.75, 4.75, 4.75), 4.0); // reaches 1 beyond the faces' middles
    const Comparison c = compareSpheres(v, s, {});
    EXPECT_NEAR(c.protrusion, 1.0, 0.3); // within half a voxel
    EXPECT_GT(c.score.dice, 0.0);
}
