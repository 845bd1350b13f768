// The union's exact volume (closed forms, the grid integration) and its surface mesh (closed, on the
// boundary, within the tolerance of that volume), and the mesh writers read back by the project's readers.
#include "mss/core/mesh_query.hpp"
#include "mss/generate.hpp"
#include "mss/io.hpp"
#include "mss/mass.hpp"
#include "mss/mesh.hpp"
#include "mss/surface.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <random>
#include <stdexcept>
#include <string>
#include <unistd.h>

using namespace mss;

namespace {

const std::string kData = MSS_TEST_DATA;
constexpr double kPi = 3.14159265358979323846;

double ball(double r) {
    return 4.0 / 3.0 * kPi * r * r * r;
}

/// The lens two balls (radii R, r, centres d apart) share.
double lens(double R, double r, double d) {
    return kPi * std::pow(R + r - d, 2) *
           (d * d + 2 * d * r - 3 * r * r + 2 * d * R + 6 * r * R - 3 * R * R) / (12 * d);
}

/// How far @p x is from the union's boundary (the signed distance to the nearest sphere's surface).
double offBoundary(const SphereSet& s, const Vec3& x) {
    double d = 1e300;
    for (std::size_t i = 0; i < s.size(); ++i) d = std::min(d, (x - s.centers[i]).norm() - s.radii[i]);
    return d;
}

void expectError(const std::function<void()>& f, const std::string& fragment) {
    try {
        f();
        ADD_FAILURE() << "no error; expected one containing: " << fragment;
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
}

SphereSet femur70() {
    GenerateOptions o;
    o.nSpheres = 70;
    Resolution res;
    res.resolution = 100; // the command line's default
    return generate(readMesh(kData + "/human_femur.stl"), res, o).spheres;
}

} // namespace

TEST(SphereUnionVolume, ClosedForms) {
    SphereSet one;
    one.add(Vec3(1, 2, 3), 0.7);
    EXPECT_NEAR(sphereUnionVolume(one) / ball(0.7), 1.0, 1e-13);
    // two overlapping at a slant (the seam of phi and the poles are crossed by the cap)
    SphereSet two;
    two.add(Vec3(0.1, 0.2, 0.3), 1.3);
    two.add(Vec3(0.1 + 1.1 * 0.6, 0.2 + 1.1 * 0.8, 0.3), 0.8);
    EXPECT_NEAR(sphereUnionVolume(two) / (ball(1.3) + ball(0.8) - lens(1.3, 0.8, 1.1)), 1.0, 1e-10);
    // along z: the cap's rim is a circle of latitude
    SphereSet polar;
    polar.add(Vec3(0, 0, 0), 1.0);
    polar.add(Vec3(0, 0, 1.5), 1.0);
    EXPECT_NEAR(sphereUnionVolume(polar) / (2 * ball(1.0) - lens(1.0, 1.0, 1.5)), 1.0, 1e-10);
    // one inside another, a duplicate, a disjoint one: counted once, not at all, in full
    SphereSet nested = polar;
    nested.add(Vec3(0, 0, 0.1), 0.5);
    nested.add(Vec3(0, 0, 1.5), 1.0);
    nested.add(Vec3(10, 0, 0), 2.0);
    EXPECT_NEAR(sphereUnionVolume(nested) / (2 * ball(1.0) - lens(1.0, 1.0, 1.5) + ball(2.0)), 1.0, 1e-10);
}

TEST(SphereUnionVolume, AgreesWithTheGridIntegration) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0), r(0.3, 0.9);
    SphereSet s;
    for (int i = 0; i < 25; ++i) s.add(Vec3(u(rng), u(rng), u(rng)), r(rng));
    const double exact = sphereUnionVolume(s);
    // the grid's error is O(h / R): halving h halves it, and both close on the exact value
    const double e200 = std::abs(sphereUnionMassProperties(s, 200).volume / exact - 1.0);
    const double e400 = std::abs(sphereUnionMassProperties(s, 400).volume / exact - 1.0);
    EXPECT_LT(e200, 1e-4); // the grid's error, O(h / R) but not monotone in h
    EXPECT_LT(e400, 1e-4);
    // moved and turned, the union keeps its volume
    SphereSet moved = s;
    for (Vec3& c : moved.centers) c = Vec3(c.z() + 5.0, -c.x(), c.y() - 2.0);
    EXPECT_NEAR(sphereUnionVolume(moved) / exact, 1.0, 1e-11);
}

TEST(UnionSurface, OneSphereOnItsBoundaryAndClosed) {
    SphereSet s;
    s.add(Vec3(1, -2, 3), 2.5);
    SurfaceReport r;
    const TriangleMesh m = unionSurface(s, {}, &r);
    const MeshInfo i = analyzeMesh(m);
    EXPECT_TRUE(i.closed);
    EXPECT_TRUE(i.consistentlyOriented);
    EXPECT_GT(i.signedVolume, 0.0); // outward
    EXPECT_NEAR(i.signedVolume, r.volume, 1e-9 * r.volume);
    EXPECT_LE(std::abs(r.volume / ball(2.5) - 1.0), 0.002);
    EXPECT_NEAR(r.unionVolume / ball(2.5), 1.0, 1e-13);
    // on the sphere: CGAL's subdivision puts new vertices there by Newton's method, to about 1e-5 r
    double worst = 0.0;
    for (const Vec3& v : m.vertices) worst = std::max(worst, std::abs((v - s.centers[0]).norm() - 2.5));
    EXPECT_LT(worst, 1e-4 * 2.5);
    std::printf("one sphere: %zu triangles, vertices off the sphere by at most %.3g r\n", m.triangles.size(),
                worst / 2.5);
}

TEST(UnionSurface, FemurSeventyClosedAndWithinTheTolerance) {
    const SphereSet s = femur70();
    SurfaceReport r;
    const TriangleMesh m = unionSurface(s, {}, &r);
    const MeshInfo i = analyzeMesh(m);
    EXPECT_TRUE(i.closed);
    EXPECT_TRUE(i.consistentlyOriented);
    EXPECT_EQ(i.degenerateTriangles, 0u);
    EXPECT_GT(i.signedVolume, 0.0);
    const double exact = sphereUnionVolume(s);
    EXPECT_LE(std::abs(i.signedVolume / exact - 1.0), 0.002); // the bar is 0.5%
    EXPECT_GE(r.subdivisions, 1);
    const double size = (i.upper - i.lower).maxCoeff();
    double worst = 0.0;
    for (const Vec3& v : m.vertices) worst = std::max(worst, std::abs(offBoundary(s, v)));
    EXPECT_LT(worst, 1e-4 * size); // every vertex on the union's boundary (as above)
    std::printf(
        "femur 70: %zu triangles, volume %.6g of the union's %.6g (%.3g), vertices off by %.3g of its size\n",
        m.triangles.size(), i.signedVolume, exact, i.signedVolume / exact - 1.0, worst / size);
}

// Regression: the union was meshed in the spheres' own frame, so the mesh depended on their units (the
// femur's spheres in metres: another triangulation, with 5 self-intersecting pairs in its STL where
// millimetres had none).
TEST(UnionSurface, TheSameSurfaceInAnyUnit) {
    const SphereSet mm = femur70();
    SphereSet m = mm;
    for (std::size_t i = 0; i < m.size(); ++i) {
        m.centers[i] *= 1e-3;
        m.radii[i] *= 1e-3;
    }
    SurfaceReport a, b;
    const TriangleMesh inMm = unionSurface(mm, {}, &a), inM = unionSurface(m, {}, &b);
    ASSERT_EQ(inMm.triangles.size(), inM.triangles.size());
    EXPECT_EQ(inMm.triangles, inM.triangles);
    double worst = 0.0;
    for (std::size_t i = 0; i < inMm.vertices.size(); ++i)
        worst = std::max(worst, (1e-3 * inMm.vertices[i] - inM.vertices[i]).norm());
    EXPECT_LT(worst, 1e-12); // metres: a femur of 0.12 m, so 1e-11 of its size
    EXPECT_EQ(a.subdivisions, b.subdivisions);
    EXPECT_NEAR(b.longestEdge, 1e-3 * a.longestEdge, 1e-15);
    // the slivers along the circles where two spheres meet can cross by rounding, in any unit: few
    EXPECT_LE(countSelfIntersections(inM), 2u);
    EXPECT_LE(countSelfIntersections(inMm), 2u);
}

TEST(UnionSurface, ComponentsEdgesAndBadOptions) {
    expectError([] { unionSurface(SphereSet{}); }, "no spheres"); // it read the first of none: a crash
    SphereSet s;
    s.add(Vec3(0, 0, 0), 1.0);
    s.add(Vec3(0.8, 0, 0), 0.6);
    s.add(Vec3(5, 5, 5), 0.5); // apart: a second component
    SurfaceOptions o;
    o.maxEdge = 0.1;
    SurfaceReport r;
    const TriangleMesh m = unionSurface(s, o, &r);
    EXPECT_TRUE(analyzeMesh(m).closed);
    EXPECT_LE(r.longestEdge, 0.1);
    for (const auto& t : m.triangles)
        for (int k = 0; k < 3; ++k)
            EXPECT_LE((m.vertices[std::size_t(t[std::size_t(k)])] -
                       m.vertices[std::size_t(t[std::size_t((k + 1) % 3)])])
                          .norm(),
                      0.1 + 1e-12);
    std::size_t near = 0;
    for (const Vec3& v : m.vertices) near += (v - Vec3(5, 5, 5)).norm() < 0.6;
    EXPECT_GT(near, 0u);
    EXPECT_LT(near, m.vertices.size());
    // a tighter tolerance: more triangles, a closer volume
    SurfaceOptions loose, tight;
    loose.tolerance = 0.01;
    tight.tolerance = 0.0005;
    SurfaceReport rl, rt;
    const std::size_t nl = unionSurface(s, loose, &rl).triangles.size(),
                      nt = unionSurface(s, tight, &rt).triangles.size();
    EXPECT_GT(nt, nl);
    EXPECT_LE(std::abs(rl.volume / rl.unionVolume - 1.0), 0.01);
    EXPECT_LE(std::abs(rt.volume / rt.unionVolume - 1.0), 0.0005);
    EXPECT_LT(std::abs(rt.volume / rt.unionVolume - 1.0), std::abs(rl.volume / rl.unionVolume - 1.0));
    SurfaceOptions bad;
    bad.tolerance = 0.0;
    expectError([&] { unionSurface(s, bad); }, "tolerance must be in (0, 0.5)");
    bad = {};
    bad.maxEdge = -1.0;
    expectError([&] { unionSurface(s, bad); }, "maxEdge must be >= 0");
    bad = {};
    bad.maxTriangles = 100;
    expectError([&] { unionSurface(s, bad); }, "more than");
    SphereSet nan;
    nan.add(Vec3(0, 0, std::nan("")), 1.0);
    expectError([&] { unionSurface(nan); }, "unionSurface");
}

TEST(MeshWriters, ReadBackByTheReaders) {
    SphereSet s;
    s.add(Vec3(0, 0, 0), 1.0);
    s.add(Vec3(1.2, 0.3, 0), 0.7);
    const TriangleMesh m = unionSurface(s);
    const std::string base = testing::TempDir() + "mss_surface_" + std::to_string(::getpid());
    for (const std::string ext : {".stl", ".obj", ".ply"}) {
        const std::string path = base + ext;
        writeMesh(m, path);
        const TriangleMesh back = readMesh(path);
        const MeshInfo i = analyzeMesh(back);
        EXPECT_TRUE(i.closed) << ext;
        EXPECT_EQ(back.triangles.size(), m.triangles.size()) << ext;
        EXPECT_EQ(back.vertices.size(), m.vertices.size()) << ext; // STL's corners merge back into vertices
        if (ext != ".stl") {                                       // OBJ and PLY keep the doubles
            for (std::size_t k = 0; k < m.vertices.size(); ++k)
                EXPECT_EQ(back.vertices[k], m.vertices[k]) << ext;
            EXPECT_EQ(back.triangles, m.triangles) << ext;
        } else {
            EXPECT_NEAR(i.signedVolume / analyzeMesh(m).signedVolume, 1.0, 1e-6);
        }
        std::remove(path.c_str());
    }
    expectError([&] { writeMesh(m, base + ".off"); },
                "unknown extension '.off' (expected .stl, .obj or .ply)");
    // what floats cannot hold (the bug: STLs with 696 to 279,921 unpaired edges, written without a word): a
    // tiny sphere on a unit one, two unit spheres near 1e6; refused as STL, closed as OBJ and PLY
    SphereSet tiny, far;
    tiny.add(Vec3(0, 0, 0), 1.0);
    tiny.add(Vec3(1, 0, 0), 1e-9);
    far.add(Vec3(1e6, 1e6, 1e6), 1.0);
    far.add(Vec3(1e6 + 1.5, 1e6, 1e6), 1.0);
    for (const SphereSet* set : {&tiny, &far}) {
        const TriangleMesh u = unionSurface(*set);
        expectError([&] { writeMesh(u, base + ".stl"); }, "binary STL holds single-precision floats");
        EXPECT_FALSE(std::ifstream(base + ".stl").good()); // nothing written
        for (const std::string ext : {".obj", ".ply"}) {
            writeMesh(u, base + ext);
            EXPECT_TRUE(analyzeMesh(readMesh(base + ext)).closed) << ext;
            std::remove((base + ext).c_str());
        }
    }
    expectError([&] { writeMesh(TriangleMesh{}, base + ".stl"); }, "writeMesh");
}
