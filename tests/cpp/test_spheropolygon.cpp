// Spheropolygons (pkg/mss/spheropolygon): the image of a spheropolygon, the boundary, Algorithm 1.
#include "mss/spheropolygon.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace mss;

TEST(Spheropolygon, ImageOfASquareAndOfARoundedOne) {
    Image2 like(40, 40);
    Spheropolygon sq;
    sq.vertices = {Vec2(9.5, 9.5), Vec2(19.5, 9.5), Vec2(19.5, 29.5),
                   Vec2(9.5, 29.5)}; // 10 x 20 pixel centres
    const Image2 a = rasterize(sq, like);
    long long n = 0;
    for (auto v : a.data) n += v;
    EXPECT_EQ(n, 200);
    sq.radius = 3.0; // + the edges' bands and quarter discs: 200 + 3 * 60 + about pi 9
    const Image2 b = rasterize(sq, like);
    n = 0;
    for (auto v : b.data) n += v;
    EXPECT_NEAR(double(n), 200 + 180 + M_PI * 9, 12.0);
    EXPECT_EQ(errorPixels(b, sq), 0);
    const Roundness r = roundness(sq);
    EXPECT_NEAR(r.perimeter, 60 + 2 * M_PI * 3, 1e-12);
    EXPECT_NEAR(r.area, 200 + 60 * 3 + M_PI * 9, 1e-12);
}

TEST(Spheropolygon, BoundaryOfOnePixelAndOfTwoDiagonalOnes) {
    Image2 im(5, 5);
    im(2, 2) = 1;
    const std::vector<Vec2> b = particleBoundary(im);
    ASSERT_EQ(b.size(), 4u);
    double area = 0; // counter-clockwise: positive shoelace area of one pixel
    for (std::size_t i = 0; i < 4; ++i) area += b[i].x() * b[(i + 1) % 4].y() - b[(i + 1) % 4].x() * b[i].y();
    EXPECT_DOUBLE_EQ(area / 2, 1.0);
    im(3, 3) = 1; // diagonal: not 4-connected, the component followed is one pixel
    EXPECT_EQ(particleBoundary(im).size(), 4u);
    Image2 empty(3, 3);
    EXPECT_THROW(particleBoundary(empty), std::invalid_argument);
}

TEST(Spheropolygon, AlgorithmOneRecoversARoundedRectangle) {
    Image2 like(120, 90);
    Spheropolygon truth;
    truth.vertices = {Vec2(30, 25), Vec2(90, 25), Vec2(90, 65), Vec2(30, 65)};
    truth.radius = 8.0;
    const Image2 target = rasterize(truth, like);
    SpOptions o;
    o.vertices = 4;
    o.radius = 8.0;
    for (SpInit init : {SpInit::Boundary, SpInit::Curvature}) {
        o.init = init;
        const SpResult r = fitSpheropolygon(target, o);
        EXPECT_LE(r.error, 0.005);
        EXPECT_LE(r.history.back(), r.history.front()); // Algorithm 1 never raises V
        EXPECT_EQ(r.errorPixels, errorPixels(target, r.sp));
    }
    o.relocations = 3; // relocations only ever lower V
    const SpResult moved = fitSpheropolygon(target, o);
    o.relocations = 0;
    EXPECT_LE(moved.errorPixels, fitSpheropolygon(target, o).errorPixels);
    EXPECT_THROW(parseSpInit("spiral"), std::invalid_argument);
    o.vertices = 2;
    EXPECT_THROW(fitSpheropolygon(target, o), std::invalid_argument);
}

namespace {

/// Whether p is within a disc of radius r(t) about a + t (b - a) for some of 4001 t: the hull of the two
/// vertex discs by brute force, not by the closed form rasterize uses.
bool nearEdgeBrute(const Vec2& p, const Vec2& a, double ra, const Vec2& b, double rb) {
    for (int k = 0; k <= 4000; ++k) {
        const double t = k / 4000.0, r = ra + t * (rb - ra);
        if ((a + t * (b - a) - p).squaredNorm() <= r * r) return true;
    }
    return false;
}

Spheropolygon unevenTriangle() {
    Spheropolygon sp;
    sp.vertices = {Vec2(30, 30), Vec2(110, 40), Vec2(60, 95)};
    sp.radii = {3.0, 8.0, 12.0};
    sp.radius = 3.0;
    return sp;
}

} // namespace

TEST(Spheropolygon, RadiusPerVertexImageIsTheHullOfTheVertexDiscs) {
    const Image2 like(140, 120);
    const Spheropolygon sp = unevenTriangle();
    const Image2 im = rasterize(sp, like);
    long long differ = 0, inside = 0;
    for (int j = 0; j < like.ny; ++j)
        for (int i = 0; i < like.nx; ++i) {
            const Vec2 p = like.center(i, j);
            bool in = false;
            for (std::size_t a = 0; a < 3 && !in; ++a)
                in = nearEdgeBrute(p, sp.vertices[a], sp.radii[a], sp.vertices[(a + 1) % 3],
                                   sp.radii[(a + 1) % 3]);
            const double c1 = (sp.vertices[1] - sp.vertices[0]).x() * (p - sp.vertices[0]).y() -
                              (sp.vertices[1] - sp.vertices[0]).y() * (p - sp.vertices[0]).x();
            const double c2 = (sp.vertices[2] - sp.vertices[1]).x() * (p - sp.vertices[1]).y() -
                              (sp.vertices[2] - sp.vertices[1]).y() * (p - sp.vertices[1]).x();
            const double c3 = (sp.vertices[0] - sp.vertices[2]).x() * (p - sp.vertices[2]).y() -
                              (sp.vertices[0] - sp.vertices[2]).y() * (p - sp.vertices[2]).x();
            in = in || (c1 >= 0 && c2 >= 0 && c3 >= 0);
            differ += in != (im(i, j) != 0);
            inside += in;
        }
    EXPECT_GT(inside, 3000);
    EXPECT_LE(differ, 2); // only where the brute force's sampling of t falls short by a hair
    // equal radii given per vertex: the paper's image, and its roundness formula
    Spheropolygon equal = sp;
    equal.radii = {4.0, 4.0, 4.0};
    Spheropolygon one = sp;
    one.radii.clear();
    one.radius = 4.0;
    EXPECT_EQ(rasterize(equal, like).data, rasterize(one, like).data);
    EXPECT_NEAR(roundness(equal).area, roundness(one).area, 1e-9);
    EXPECT_NEAR(roundness(equal).perimeter, roundness(one).perimeter, 1e-9);
    Spheropolygon bad = sp;
    bad.radii = {1.0, 2.0};
    EXPECT_THROW(rasterize(bad, like), std::invalid_argument);
    bad.radii = {1.0, -2.0, 1.0};
    EXPECT_THROW(rasterize(bad, like), std::invalid_argument);
}

TEST(Spheropolygon, RadiusPerVertexRecoversUnevenRadii) {
    const Spheropolygon truth = unevenTriangle();
    const Image2 target = rasterize(truth, Image2(140, 120));
    SpOptions o;
    o.vertices = 3;
    o.radius = 3.0;
    o.init = SpInit::Boundary;
    const SpResult equal = fitSpheropolygon(target, o);
    o.vertexRadii = true;
    const SpResult each = fitSpheropolygon(target, o);
    EXPECT_GE(equal.error, 0.02); // one radius cannot round three corners differently
    EXPECT_LE(each.error, 0.01);
    EXPECT_EQ(each.errorPixels, errorPixels(target, each.sp));
    ASSERT_EQ(each.sp.radii.size(), 3u);
    for (std::size_t k = 0; k < 3; ++k) {
        double nearest = 1e9; // the fitted vertex nearest truth's vertex k, and its radius
        std::size_t at = 0;
        for (std::size_t i = 0; i < 3; ++i)
            if ((each.sp.vertices[i] - truth.vertices[k]).norm() < nearest) {
                nearest = (each.sp.vertices[i] - truth.vertices[k]).norm();
                at = i;
            }
        EXPECT_LE(nearest, 2.5);
        EXPECT_NEAR(each.sp.radii[at], truth.radii[k], 1.5);
        EXPECT_GE(each.sp.radii[at], o.radius); // the default bound: the spheroradius
    }
    EXPECT_DOUBLE_EQ(each.sp.radius, *std::min_element(each.sp.radii.begin(), each.sp.radii.end()));
    EXPECT_TRUE(equal.sp.radii.empty());
    o.minRadius = 4.0; // above the spheroradius
    EXPECT_THROW(fitSpheropolygon(target, o), std::invalid_argument);
    o.minRadius = -1.0;
    EXPECT_THROW(fitSpheropolygon(target, o), std::invalid_argument);
    o.minRadius = 1.0;
    o.vertexRadii = false; // a bound on nothing
    EXPECT_THROW(fitSpheropolygon(target, o), std::invalid_argument);
}

namespace {

/// A 100 x 70 rectangle with a 30 x 16 notch cut in the middle of its top edge (corners further apart than
/// the smoothing, so that each is its own region).
Image2 notchedBlock() {
    Image2 im(140, 110);
    for (int j = 20; j < 90; ++j)
        for (int i = 20; i < 120; ++i) im(i, j) = !(j >= 74 && i >= 55 && i < 85);
    return im;
}

} // namespace

TEST(Spheropolygon, RegionsOfABlockWithANotch) {
    std::vector<Vec2> boundary;
    const std::vector<SpRegion> regions = boundaryRegions(notchedBlock(), 45.0, &boundary);
    int convex = 0, concave = 0;
    for (const SpRegion& r : regions) {
        (r.turning > 0 ? convex : concave) += 1;
        EXPECT_NEAR(std::abs(r.turning), 90.0, 20.0);
    }
    EXPECT_EQ(convex, 6);  // four block corners, the notch's two upper corners...
    EXPECT_EQ(concave, 2); // ... and its two floor corners
    EXPECT_THROW(boundaryRegions(notchedBlock(), 0.0), std::invalid_argument);
    // a disc turns by 360 degrees in one convex region
    Image2 disc(60, 60);
    for (int j = 0; j < 60; ++j)
        for (int i = 0; i < 60; ++i) disc(i, j) = (i - 30) * (i - 30) + (j - 30) * (j - 30) <= 400;
    const std::vector<SpRegion> round = boundaryRegions(disc, 45.0);
    ASSERT_EQ(round.size(), 1u);
    EXPECT_NEAR(round[0].turning, 360.0, 1.0);
}

TEST(Spheropolygon, RegionVerticesPutOneVertexInEveryRegion) {
    const Image2 target = notchedBlock();
    std::vector<Vec2> boundary;
    const std::vector<SpRegion> regions = boundaryRegions(target, 45.0, &boundary);
    auto regionOf = [&](const Vec2& p) { // of the nearest boundary point, as the option defines it
        std::size_t best = 0;
        for (std::size_t q = 1; q < boundary.size(); ++q)
            if ((boundary[q] - p).squaredNorm() < (boundary[best] - p).squaredNorm()) best = q;
        for (std::size_t k = 0; k < regions.size(); ++k) {
            const SpRegion& r = regions[k];
            const bool in = r.coreFirst <= r.coreLast ? best >= r.coreFirst && best <= r.coreLast
                                                      : best >= r.coreFirst || best <= r.coreLast;
            if (in) return int(k);
        }
        return -1;
    };
    SpOptions o;
    o.vertices = 8;
    o.radius = 2.0;
    o.regionTurning = 45.0;
    o.init = SpInit::Circle; // a start that knows nothing of the corners
    o.maxIterations = 3;     // and too few iterations to find them all
    const SpResult plain = fitSpheropolygon(target, o);
    o.regionVertices = true;
    const SpResult held = fitSpheropolygon(target, o);
    EXPECT_EQ(held.regions, 8);
    EXPECT_EQ(held.regionsMissed, 0);
    std::vector<int> count(regions.size(), 0);
    for (const Vec2& v : held.sp.vertices)
        if (regionOf(v) >= 0) ++count[std::size_t(regionOf(v))];
    for (int c : count) EXPECT_GE(c, 1);
    int plainCovered = 0; // the same fit without the option left some region empty
    std::vector<int> plainCount(regions.size(), 0);
    for (const Vec2& v : plain.sp.vertices)
        if (regionOf(v) >= 0) ++plainCount[std::size_t(regionOf(v))];
    for (int c : plainCount) plainCovered += c > 0;
    EXPECT_LT(plainCovered, 8);
    EXPECT_GE(held.regionsFilled, 1); // (not 8 - plainCovered: the runs part after the first moves)
    // more regions than vertices: the count of those left without one is reported
    o.vertices = 5;
    const SpResult few = fitSpheropolygon(target, o);
    EXPECT_GE(few.regionsMissed, 3);
}
