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
