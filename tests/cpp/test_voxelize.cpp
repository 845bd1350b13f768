#include "mss/generate.hpp"
#include "mss/io.hpp"
#include "mss/mesh.hpp"
#include "mss/voxelize.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace mss;

namespace {
const std::string kData = MSS_TEST_DATA;
const double kPi = 3.14159265358979323846;

double voxelVolume(const VoxelGrid& v) {
    return double(countSolid(v)) * v.spec.h * v.spec.h * v.spec.h;
}
} // namespace

TEST(Voxelize, BallVolumeMatchesFourThirdsPiRCubed) {
    const TriangleMesh ball = readMesh(kData + "/sphere_r1.stl");
    const double meshVolume = analyzeMesh(ball).signedVolume; // the faceted sphere: 4.1865, not 4.18879
    Resolution res;
    res.resolution = 80;
    const VoxelGrid v = voxelizeMesh(ball, res);
    // centre sampling: error ~ surface area * h * O(1/sqrt(n)) cancellation; 0.5% holds at 80 voxels
    EXPECT_NEAR(voxelVolume(v), meshVolume, 0.005 * meshVolume);
    EXPECT_NEAR(meshVolume, 4.0 / 3.0 * kPi, 0.002 * 4.18879); // the mesh itself approximates the unit ball
    const VoxelGrid s = voxelizeMesh(ball, res, 3);            // supersampling: closer still
    EXPECT_NEAR(voxelVolume(s), meshVolume, 0.003 * meshVolume);
}

TEST(Voxelize, DoubleZeroHull) {
    const TriangleMesh ball = readMesh(kData + "/sphere_r1.stl");
    Resolution res;
    res.resolution = 20;
    const VoxelGrid v = voxelizeMesh(ball, res);
    // eq. 6: the two outer layers on every side are empty
    for (int k = 0; k < v.nz(); ++k)
        for (int j = 0; j < v.ny(); ++j)
            for (int i = 0; i < v.nx(); ++i) {
                const bool hull =
                    i < 2 || j < 2 || k < 2 || i >= v.nx() - 2 || j >= v.ny() - 2 || k >= v.nz() - 2;
                if (hull) ASSERT_EQ(v(i, j, k), 0) << i << " " << j << " " << k;
            }
    EXPECT_EQ(v.nx(), 24); // 20 voxels across the ball plus 2 + 2
}

TEST(Voxelize, OrientationDoesNotMatter) {
    const TriangleMesh mesh = readMesh(kData + "/ellipsoid_2_1_1.stl");
    TriangleMesh flipped = mesh, mixed = mesh;
    for (auto& t : flipped.triangles) std::swap(t[1], t[2]);
    for (std::size_t q = 0; q < mixed.triangles.size(); q += 2)
        std::swap(mixed.triangles[q][1], mixed.triangles[q][2]);
    Resolution res;
    res.resolution = 40;
    const VoxelGrid a = voxelizeMesh(mesh, res), b = voxelizeMesh(flipped, res), c = voxelizeMesh(mixed, res);
    EXPECT_GT(countSolid(a), 1000u);
    EXPECT_EQ(a.data, b.data); // inside-out: winding -1 is inside too
    EXPECT_EQ(a.data, c.data); // inconsistent orientation: parity rule
    EXPECT_LT(analyzeMesh(flipped).signedVolume, 0.0);
    EXPECT_FALSE(analyzeMesh(mixed).consistentlyOriented);
}

TEST(Voxelize, WatertightOnSymmetricGrid) {
    // the ellipsoid's grid is centred on it, so rays pass exactly through mesh vertices and edges on the
    // symmetry planes; counting such crossings once or twice would leave streaks. Symmetry must survive.
    const TriangleMesh mesh = readMesh(kData + "/ellipsoid_2_1_1.stl");
    Resolution res;
    res.resolution = 41;
    const VoxelGrid v = voxelizeMesh(mesh, res);
    std::size_t asym = 0;
    for (int k = 0; k < v.nz(); ++k)
        for (int j = 0; j < v.ny(); ++j)
            for (int i = 0; i < v.nx(); ++i) asym += v(i, j, k) != v(v.nx() - 1 - i, j, k);
    EXPECT_LE(asym, countSolid(v) / 1000);
    EXPECT_NEAR(voxelVolume(v), 8.373, 0.02 * 8.373);
}

TEST(Voxelize, SpheresUnion) {
    GridSpec g;
    g.dims = {60, 60, 60};
    g.h = 0.1;
    g.origin = Vec3(-3, -3, -3);
    SphereSet s;
    s.add(Vec3(0, 0, 0), 2.0);
    const VoxelGrid v = voxelizeSpheres(s, g);
    EXPECT_NEAR(voxelVolume(v), 4.0 / 3.0 * kPi * 8.0, 0.01 * 33.51);
    s.add(Vec3(0.1, 0, 0), 2.0); // overlap counted once
    EXPECT_LT(voxelVolume(voxelizeSpheres(s, g)), 1.05 * voxelVolume(v));
}

TEST(Voxelize, BadResolutionsAreRefused) {
    Resolution r;
    EXPECT_THROW(gridForBox(Vec3(0, 0, 0), Vec3(1, 1, 1), r, "t"), std::invalid_argument); // neither given
    r.resolution = -3;
    EXPECT_THROW(gridForBox(Vec3(0, 0, 0), Vec3(1, 1, 1), r, "t"), std::invalid_argument);
    r.resolution = 100000; // 1e15 voxels: refused before allocating
    try {
        gridForBox(Vec3(0, 0, 0), Vec3(1, 1, 1), r, "t");
        FAIL();
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("would need"), std::string::npos) << e.what();
    }
    r.resolution = 10;
    EXPECT_THROW(gridForBox(Vec3(0, 0, 0), Vec3(1, 1, 0), r, "t"), std::invalid_argument); // flat
    r.resolution = 0;
    r.voxelSize = -1;
    EXPECT_THROW(gridForBox(Vec3(0, 0, 0), Vec3(1, 1, 1), r, "t"), std::invalid_argument);
}

TEST(Voxelize, PaddingKeepsWorldPositions) {
    GridSpec g;
    g.dims = {10, 10, 10};
    g.h = 0.5;
    g.origin = Vec3(1, 2, 3);
    VoxelGrid v(g, 0);
    v(4, 5, 6) = 1;
    v(5, 5, 6) = 1;
    const VoxelGrid p = padVoxels(v, 2);
    EXPECT_EQ(p.nx(), 6);
    EXPECT_EQ(p.ny(), 5);
    EXPECT_EQ(p(2, 2, 2), 1);
    EXPECT_NEAR((p.spec.voxelCenter(2, 2, 2) - g.voxelCenter(4, 5, 6)).norm(), 0.0, 1e-12);
    VoxelGrid empty(g, 0);
    EXPECT_THROW(padVoxels(empty), std::invalid_argument);
}

TEST(Voxelize, SpheresFarOutsideTheGridAreIgnored) {
    GridSpec g;
    g.dims = {10, 10, 10};
    SphereSet s;
    s.add(Vec3(-1e9, 5, 5), 3.0);
    s.add(Vec3(5, 5, 5), 1.0);
    EXPECT_EQ(countSolid(voxelizeSpheres(s, g)), 7u); // only the last: its centre and 6 neighbours
    s.add(Vec3(1e300, 0, 0), 1.0); // would overflow any index maths: outside the range of sphere sets
    EXPECT_THROW(voxelizeSpheres(s, g), std::invalid_argument);
}

namespace {
/// @p n triangles with random corners in the unit cube: a soup, every triangle spanning much of the grid.
TriangleMesh triangleSoup(int n) {
    TriangleMesh m;
    unsigned state = 12345u;
    auto next = [&state] {
        state = state * 1664525u + 1013904223u;
        return double(state >> 8) / double(1u << 24);
    };
    for (int i = 0; i < 3 * n; ++i) m.vertices.emplace_back(next(), next(), next());
    for (int i = 0; i < n; ++i) m.triangles.push_back({3 * i, 3 * i + 1, 3 * i + 2});
    return m;
}
} // namespace

TEST(Voxelize, TriangleSoupIsRefusedBeforeItsCrossingsAreStored) {
    // every ray meets a fair share of the soup's triangles: 2000 triangles at 100 voxels, about 5e6
    // crossings (a surface's rays meet a few each); under a 16 MiB limit refused at once, naming the soup
    const TriangleMesh soup = triangleSoup(2000);
    Resolution res;
    res.resolution = 100;
    res.memoryLimit = std::size_t(16) << 20;
    try {
        voxelizeMesh(soup, res);
        FAIL() << "a soup over the memory limit was voxelised";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("triangle soup"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("memory limit"), std::string::npos) << e.what();
    }
    // the same limit leaves a real surface alone: the ball's rays cross it twice
    const TriangleMesh ball = readMesh(kData + "/sphere_r1.stl");
    EXPECT_GT(countSolid(voxelizeMesh(ball, res)), 0u);
}

TEST(Voxelize, OpenMeshWindingWorkIsEstimatedBeforeItStarts) {
    // an open soup's inside is a winding number a run: refused past maxWork with the estimate, not run
    const TriangleMesh soup = triangleSoup(2000);
    Resolution res;
    res.resolution = 100;
    try {
        voxelizeMesh(soup, res, 1, nullptr, 1.0);
        FAIL() << "an open soup's winding numbers were computed past the work limit";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("winding number"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("work limit of 1 s"), std::string::npos) << e.what();
    }
}
