#include "mss/core/mesh_query.hpp"
#include "mss/io.hpp"
#include "mss/mass.hpp"
#include "mss/voxelize.hpp"

#include <gtest/gtest.h>

using namespace mss;

namespace {
const std::string kData = MSS_TEST_DATA;
const double kPi = 3.14159265358979323846;
} // namespace

TEST(Mass, EllipsoidMeshMatchesClosedForm) {
    const MassProperties m = meshMassProperties(readMesh(kData + "/ellipsoid_2_1_1.stl"));
    const double V = 4.0 / 3.0 * kPi * 2.0; // semi-axes 2, 1, 1
    // the faceted mesh (20,480 triangles) is inscribed: its volume is 0.05% below the ellipsoid's
    EXPECT_NEAR(m.volume, V, 1e-3 * V);
    EXPECT_NEAR(m.centroid.norm(), 0.0, 1e-9);
    EXPECT_NEAR(m.inertia(0, 0), m.volume * (1 + 1) / 5.0, 2e-3 * m.inertia(0, 0)); // V (b^2 + c^2) / 5
    EXPECT_NEAR(m.inertia(1, 1), m.volume * (4 + 1) / 5.0, 2e-3 * m.inertia(1, 1));
    EXPECT_NEAR(m.inertia(2, 2), m.volume * (4 + 1) / 5.0, 2e-3 * m.inertia(2, 2));
    EXPECT_NEAR(m.inertia(0, 1), 0.0, 1e-9);
    Vec3 moments;
    Eigen::Matrix3d axes;
    m.principal(moments, axes);
    EXPECT_NEAR(std::abs(axes.col(0).x()), 1.0, 1e-9); // smallest moment about the long axis
    EXPECT_NEAR(axes.determinant(), 1.0, 1e-12);
}

TEST(Mass, CubeMeshIsExactAndOrientationFree) {
    TriangleMesh cube = readMesh(kData + "/cube.stl");
    const MassProperties m = meshMassProperties(cube);
    EXPECT_NEAR(m.volume, 1.0, 1e-12); // flat faces: the divergence theorem is exact
    EXPECT_NEAR(m.inertia(0, 0), 1.0 / 6.0, 1e-12);
    EXPECT_NEAR(m.inertia(1, 2), 0.0, 1e-12);
    for (auto& t : cube.triangles) std::swap(t[1], t[2]); // inside out
    const MassProperties f = meshMassProperties(cube);
    EXPECT_NEAR(f.volume, 1.0, 1e-12);
    EXPECT_NEAR(f.inertia(2, 2), 1.0 / 6.0, 1e-12);
}

TEST(Mass, VoxelSumsAreExact) {
    GridSpec g;
    g.dims = {4, 3, 3};
    g.h = 2.0;
    g.origin = Vec3(10, 0, 0);
    VoxelGrid v(g, 0);
    v(1, 1, 1) = 1;
    v(2, 1, 1) = 1; // a 4 x 2 x 2 box centred at (13, 2, 2)
    const MassProperties m = voxelMassProperties(v);
    EXPECT_DOUBLE_EQ(m.volume, 16.0);
    EXPECT_NEAR((m.centroid - Vec3(13, 2, 2)).norm(), 0.0, 1e-12);
    EXPECT_NEAR(m.inertia(0, 0), 16.0 * (4 + 4) / 12.0, 1e-12); // box: m (b^2 + c^2) / 12
    EXPECT_NEAR(m.inertia(1, 1), 16.0 * (16 + 4) / 12.0, 1e-12);
}

TEST(Mass, SphereUnionCountsOverlapsOnce) {
    SphereSet one;
    one.add(Vec3(1, 2, 3), 1.0);
    const MassProperties a = sphereUnionMassProperties(one, 200);
    EXPECT_NEAR(a.volume, 4.0 / 3.0 * kPi, 2e-3 * 4.18879);
    EXPECT_NEAR(a.inertia(0, 0), 0.4 * a.volume, 4e-3 * 0.4 * a.volume);
    SphereSet two;
    two.add(Vec3(0, 0, 0), 1.0);
    two.add(Vec3(1, 0, 0), 1.0); // one radius apart: lens of volume 5 pi / 12 counted once
    const double V = 2 * 4.0 / 3.0 * kPi - 5.0 * kPi / 12.0;
    EXPECT_NEAR(sphereUnionMassProperties(two, 200).volume, V, 2e-3 * V);
    EXPECT_NEAR(sphereUnionMassProperties(two, 200).centroid.x(), 0.5, 1e-9);
}

// A grain cut by planes (a fragment): clipped and capped, its mass properties are exact.
TEST(Mass, CutCubeIsExact) {
    const TriangleMesh cube = readMesh(kData + "/cube.stl"); // [-0.5, 0.5]^3
    Plane p;
    p.point = Vec3(-0.2, 0, 0);
    p.normal = Vec3(2, 0, 0); // keep x >= -0.2: a 0.7 x 1 x 1 box
    const MassProperties m = meshMassProperties(clipMeshByPlanes(cube, {p}));
    // exact up to rounding (sums over ~3000 triangles of unit size): 1e-12
    EXPECT_NEAR(m.volume, 0.7, 1e-12);
    EXPECT_NEAR((m.centroid - Vec3(0.15, 0, 0)).norm(), 0.0, 1e-12);
    EXPECT_NEAR(m.inertia(0, 0), 0.7 * (1 + 1) / 12.0, 1e-12);
    EXPECT_NEAR(m.inertia(1, 1), 0.7 * (0.49 + 1) / 12.0, 1e-12);
    EXPECT_NEAR(m.inertia(0, 1), 0.0, 1e-12);
    // two planes cutting off a corner wedge each: the sum of the parts is the whole
    Plane q;
    q.point = Vec3(0.1, 0.2, -0.1);
    q.normal = Vec3(0.3, -1, 0.4);
    Plane qb = q;
    qb.normal = -q.normal;
    const MassProperties a = meshMassProperties(clipMeshByPlanes(cube, {q})),
                         b = meshMassProperties(clipMeshByPlanes(cube, {qb}));
    EXPECT_NEAR(a.volume + b.volume, 1.0, 1e-12);
    EXPECT_NEAR((a.volume * a.centroid + b.volume * b.centroid).norm(), 0.0, 1e-12);
    // second moments about the origin add up too: I_O = I_c + V (|c|^2 1 - c c^T)
    auto aboutOrigin = [](const MassProperties& x) {
        return Eigen::Matrix3d(x.inertia +
                               x.volume * (x.centroid.squaredNorm() * Eigen::Matrix3d::Identity() -
                                           x.centroid * x.centroid.transpose()));
    };
    EXPECT_NEAR((aboutOrigin(a) + aboutOrigin(b) - Eigen::Matrix3d::Identity() / 6.0).norm(), 0.0, 1e-12);
    EXPECT_LT(std::abs(a.volume - 0.5), 0.45); // a real cut
    // nothing left
    Plane away;
    away.point = Vec3(0, 0, 2);
    away.normal = Vec3(0, 0, 1);
    EXPECT_TRUE(clipMeshByPlanes(cube, {away}).triangles.empty());
}

// The femur (a real, bumpy mesh whose cut has several loops in general) split in two: the halves add up.
TEST(Mass, CutFemurHalvesAddUp) {
    const TriangleMesh femur = readMesh(kData + "/human_femur.stl");
    const MassProperties whole = meshMassProperties(femur);
    Plane p;
    p.point = whole.centroid;
    p.normal = Vec3(0.1, 0.2, 1.0);
    Plane q = p;
    q.normal = -p.normal;
    const MassProperties a = meshMassProperties(clipMeshByPlanes(femur, {p})),
                         b = meshMassProperties(clipMeshByPlanes(femur, {q}));
    EXPECT_NEAR(a.volume + b.volume, whole.volume, 1e-9 * whole.volume);
    EXPECT_NEAR((a.volume * a.centroid + b.volume * b.centroid - whole.volume * whole.centroid).norm(), 0.0,
                1e-9 * whole.volume * 100);
    EXPECT_GT(a.volume, 0.1 * whole.volume);
    EXPECT_GT(b.volume, 0.1 * whole.volume);
}
