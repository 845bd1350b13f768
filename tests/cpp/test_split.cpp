// splitMeshByPlane: the pieces of a grain cut by a plane, each closed, their mass properties summing to the
// grain's (what makes a fragmentation conserve mass and momenta exactly).
#include "mss/io.hpp"
#include "mss/mass.hpp"
#include "mss/planes.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace mss;

namespace {
const std::string kData = MSS_TEST_DATA;

/// Mass properties of several pieces together: volumes added, tensors moved to the common centroid
/// (parallel axes), as the grain's must come out.
MassProperties combined(const std::vector<TriangleMesh>& a, const std::vector<TriangleMesh>& b) {
    std::vector<MassProperties> all;
    for (const auto* side : {&a, &b})
        for (const TriangleMesh& m : *side) all.push_back(meshMassProperties(m));
    MassProperties out;
    for (const auto& p : all) out.volume += p.volume, out.centroid += p.volume * p.centroid;
    out.centroid /= out.volume;
    for (const auto& p : all) {
        const Vec3 r = p.centroid - out.centroid;
        out.inertia +=
            p.inertia + p.volume * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
    }
    return out;
}

void expectSameMass(const MassProperties& got, const MassProperties& want, double tol) {
    const double size = std::cbrt(want.volume);
    EXPECT_NEAR(got.volume, want.volume, tol * want.volume);
    EXPECT_LE((got.centroid - want.centroid).norm(), tol * size);
    EXPECT_LE((got.inertia - want.inertia).cwiseAbs().maxCoeff(), tol * want.inertia.cwiseAbs().maxCoeff());
}

/// Every piece closed (each edge used twice, once each way) and on its side of the plane.
void expectClosedOnSide(const std::vector<TriangleMesh>& pieces, const Plane& p, double sign, double size) {
    for (const TriangleMesh& m : pieces) {
        const MeshInfo info = analyzeMesh(m);
        EXPECT_EQ(info.boundaryEdges, 0u);
        EXPECT_EQ(info.nonManifoldEdges, 0u);
        EXPECT_EQ(info.degenerateTriangles, 0u);
        EXPECT_EQ(info.inconsistentEdges, 0u);
        EXPECT_GT(info.signedVolume, 0.0); // the input's orientation
        for (const Vec3& v : m.vertices) EXPECT_GE(sign * planeDistance(p, v), -1e-12 * size);
    }
}

TriangleMesh shifted(TriangleMesh m, const Vec3& by) {
    for (Vec3& v : m.vertices) v += by;
    return m;
}

TriangleMesh joined(const TriangleMesh& a, const TriangleMesh& b) {
    TriangleMesh out = a;
    const int base = int(a.vertices.size());
    out.vertices.insert(out.vertices.end(), b.vertices.begin(), b.vertices.end());
    for (auto t : b.triangles) out.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    return out;
}
} // namespace

TEST(SplitMesh, CubeInTwoExactly) {
    const TriangleMesh cube = readMesh(kData + "/cube.stl"); // [-0.5, 0.5]^3
    const Plane p{Vec3(0, 0, 0.1), Vec3(0, 0, 2)};
    const MeshSplit s = splitMeshByPlane(cube, p);
    ASSERT_EQ(s.above.size(), 1u);
    ASSERT_EQ(s.below.size(), 1u);
    const MassProperties a = meshMassProperties(s.above[0]), b = meshMassProperties(s.below[0]);
    EXPECT_NEAR(a.volume, 0.4, 1e-14);
    EXPECT_NEAR(b.volume, 0.6, 1e-14);
    EXPECT_NEAR(a.centroid.z(), 0.3, 1e-14);
    EXPECT_NEAR(b.centroid.z(), -0.2, 1e-14);
    EXPECT_NEAR(a.inertia(2, 2), 0.4 * (1.0 + 1.0) / 12, 1e-14); // a 1 x 1 x 0.4 box about its axis z
    expectClosedOnSide(s.above, p, 1, 1);
    expectClosedOnSide(s.below, p, -1, 1);
    expectSameMass(combined(s.above, s.below), meshMassProperties(cube), 1e-13);
}

TEST(SplitMesh, TwoSeparateGrainsGiveTwoPiecesASide) {
    const TriangleMesh cube = readMesh(kData + "/cube.stl");
    const TriangleMesh two = joined(cube, shifted(cube, Vec3(3, 0, 0)));
    const Plane p{Vec3(0, 0, -0.2), Vec3(0, 0, 1)};
    const MeshSplit s = splitMeshByPlane(two, p);
    ASSERT_EQ(s.above.size(), 2u);
    ASSERT_EQ(s.below.size(), 2u);
    for (const auto& m : s.above) EXPECT_NEAR(meshMassProperties(m).volume, 0.7, 1e-14);
    for (const auto& m : s.below) EXPECT_NEAR(meshMassProperties(m).volume, 0.3, 1e-14);
    expectSameMass(combined(s.above, s.below), meshMassProperties(two), 1e-13);
}

TEST(SplitMesh, TorusHalvesHaveTwoCutLoopsEach) {
    const TriangleMesh torus = readMesh(kData + "/torus.stl");
    const MeshInfo info = analyzeMesh(torus);
    const Vec3 c = 0.5 * (info.lower + info.upper);
    const Vec3 e = info.upper - info.lower;
    // the axis is the shortest extent; a plane containing it cuts the ring twice
    int axis = 0;
    for (int a = 1; a < 3; ++a)
        if (e[a] < e[axis]) axis = a;
    Vec3 n = Vec3::Zero();
    n[(axis + 1) % 3] = 1;
    const Plane p{c, n};
    const MeshSplit s = splitMeshByPlane(torus, p);
    ASSERT_EQ(s.above.size(), 1u);
    ASSERT_EQ(s.below.size(), 1u);
    expectClosedOnSide(s.above, p, 1, e.maxCoeff());
    expectClosedOnSide(s.below, p, -1, e.maxCoeff());
    expectSameMass(combined(s.above, s.below), meshMassProperties(torus), 1e-12);
    EXPECT_NEAR(meshMassProperties(s.above[0]).volume, meshMassProperties(s.below[0]).volume,
                1e-3 * info.signedVolume); // the torus is symmetric about the plane, to its tessellation
}

TEST(SplitMesh, FemurPiecesSumToTheGrainAndSplitAgain) {
    const TriangleMesh femur = readMesh(kData + "/human_femur.stl");
    const MassProperties whole = meshMassProperties(femur);
    const double size = std::cbrt(whole.volume);
    const Plane p{whole.centroid, Vec3(0.3, -0.2, 1.0)};
    const MeshSplit s = splitMeshByPlane(femur, p);
    ASSERT_GE(s.above.size(), 1u);
    ASSERT_GE(s.below.size(), 1u);
    expectClosedOnSide(s.above, p, 1, size);
    expectClosedOnSide(s.below, p, -1, size);
    expectSameMass(combined(s.above, s.below), whole, 1e-12);
    // the pieces on one side are clipMeshByPlanes' fragment
    EXPECT_NEAR(combined(s.above, {}).volume, meshMassProperties(clipMeshByPlanes(femur, {p})).volume,
                1e-12 * whole.volume);
    // a piece splits again, and its pieces sum to it
    const TriangleMesh& piece = s.above[0];
    const MassProperties pm = meshMassProperties(piece);
    const Plane q{pm.centroid, Vec3(1.0, 0.4, -0.1)};
    const MeshSplit again = splitMeshByPlane(piece, q);
    ASSERT_GE(again.above.size(), 1u);
    ASSERT_GE(again.below.size(), 1u);
    expectClosedOnSide(again.above, q, 1, size);
    expectSameMass(combined(again.above, again.below), pm, 1e-12);
}

TEST(SplitMesh, VertexOnThePlaneUpToRoundingGivesClosedPieces) {
    // the vertex (1/16, 1/4, -11/16) lies 3.5e-18 above the plane, not on it, in floating point: once a
    // sliver of zero area at it and edges used four times
    const TriangleMesh oct = readMesh(kData + "/octahedron.stl");
    const MassProperties whole = meshMassProperties(oct);
    for (const Vec3& n : {Vec3(1.0, 0.3, 0.2), Vec3(-1.0, -0.3, -0.2)}) {
        const Plane p{Vec3::Zero(), n};
        ASSERT_LT(std::abs(planeDistance(p, Vec3(0.0625, 0.25, -0.6875))), 1e-15);
        const MeshSplit s = splitMeshByPlane(oct, p);
        ASSERT_EQ(s.above.size(), 1u);
        ASSERT_EQ(s.below.size(), 1u);
        expectClosedOnSide(s.above, p, 1, 2.0);
        expectClosedOnSide(s.below, p, -1, 2.0);
        expectSameMass(combined(s.above, s.below), whole, 1e-12);
    }
}

TEST(SplitMesh, PlaneOnAFaceOrMissingLeavesOnePiece) {
    const TriangleMesh cube = readMesh(kData + "/cube.stl");
    for (const Plane& p : {Plane{Vec3(0, 0, 0.5), Vec3(0, 0, 1)}, Plane{Vec3(0, 0, 2), Vec3(0, 0, 1)},
                           Plane{Vec3(0, 0, -0.5), Vec3(0, 0, -1)}}) {
        const MeshSplit s = splitMeshByPlane(cube, p);
        EXPECT_TRUE(s.above.empty());
        ASSERT_EQ(s.below.size(), 1u);
        EXPECT_NEAR(meshMassProperties(s.below[0]).volume, 1.0, 1e-14);
    }
}

TEST(SplitMesh, BadPlaneIsRefusedByName) {
    const TriangleMesh cube = readMesh(kData + "/cube.stl");
    try {
        splitMeshByPlane(cube, Plane{Vec3(0, 0, 0), Vec3(0, 0, 0)});
        FAIL() << "a zero normal was accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("splitMeshByPlane"), std::string::npos);
    }
}

TEST(InsideClearance, CubeCentreAndOutside) {
    const TriangleMesh cube = readMesh(kData + "/cube.stl"); // [-0.5, 0.5]^3
    EXPECT_NEAR(insideClearance(cube, Vec3(0, 0, 0)), 0.5, 1e-12);
    EXPECT_NEAR(insideClearance(cube, Vec3(0.3, 0.1, -0.2)), 0.2, 1e-12);
    EXPECT_EQ(insideClearance(cube, Vec3(0.7, 0, 0)), 0.0);
    EXPECT_THROW(insideClearance(cube, Vec3(std::nan(""), 0, 0)), std::invalid_argument);
}
