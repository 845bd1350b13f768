// pkg/mss/generation/engine/coverage: exact mismatch gains against brute force.
#include "engine_fixtures.hpp"
#include "mss/generation/engine/coverage.hpp"
#include "mss/generation/engine/symmetry.hpp"

#include <gtest/gtest.h>

#include <random>

using namespace mss;
using namespace mss::engine;
using namespace mss::testing;

class CoverageCounts : public ::testing::TestWithParam<std::size_t> {};

// counts of 8 bits (at most 255 balls) and of 16 bits
TEST_P(CoverageCounts, GainsAreTheExactMismatchChange) {
    const VoxelGrid S = ellipsoid(24, 10, 7, 5);
    Coverage cov(S, GetParam());
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(2, 21), rr(1, 6);
    std::vector<Ball> placed;
    for (int t = 0; t < 12; ++t) {
        const Ball b{Vec3(u(rng), u(rng), u(rng)), rr(rng)};
        const long long before = cov.mismatch();
        const long long g = cov.gain(b);
        cov.add(b);
        placed.push_back(b);
        EXPECT_EQ(before - cov.mismatch(), g);
        EXPECT_EQ(cov.mismatch(), bruteMismatch(S, placed));
    }
    // removing in another order gives every state back
    for (int t = 11; t >= 0; t -= 2) {
        cov.remove(placed[std::size_t(t)]);
        placed.erase(placed.begin() + t);
        EXPECT_EQ(cov.mismatch(), bruteMismatch(S, placed));
    }
}

TEST_P(CoverageCounts, ManyBallsOnOneVoxelCountExactly) {
    // up to the limit's balls on the same voxels (an 8-bit count at 255), then all removed again
    const VoxelGrid S = ellipsoid(24, 10, 7, 5);
    const std::size_t limit = std::min<std::size_t>(GetParam(), 300);
    Coverage cov(S, GetParam());
    std::vector<Ball> placed;
    for (std::size_t t = 0; t < limit; ++t) {
        placed.push_back(Ball{Vec3(12 + 0.01 * double(t % 7), 11.5, 11.5), 3.0 + 0.01 * double(t % 5)});
        cov.add(placed.back());
    }
    EXPECT_EQ(cov.mismatch(), bruteMismatch(S, placed));
    for (std::size_t t = 0; t + 1 < limit; ++t) cov.remove(placed[t]);
    EXPECT_EQ(cov.mismatch(), bruteMismatch(S, {placed.back()}));
    cov.remove(placed.back());
    EXPECT_EQ(cov.mismatch(), bruteMismatch(S, {}));
}

TEST_P(CoverageCounts, MirrorPairsChangedTogetherAsEachAlone) {
    // an orbit's x-mirror images (the same rows) are changed in one pass over the union of their runs:
    // overlapping, touching, apart, against the grid's ends, large (changed slice by slice in parallel) and
    // mixed with a ball alone; the mismatch, the covered count and every gain after it as with one change
    // a ball (test_mirror_pair_change)
    const VoxelGrid S = ellipsoid(60, 26, 22, 18);
    Coverage together(S, GetParam()), alone(S, GetParam());
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<std::vector<Ball>> orbits;
    const double cx = 0.5 * (S.nx() - 1);
    for (int t = 0; t < 14; ++t) {
        const double r = t == 0 ? 14.5 : 1 + 9 * u(rng), off = t == 1 ? 0.25 : 25 * u(rng);
        const double y = 4 + 18 * u(rng), z = 4 + 14 * u(rng);
        std::vector<Ball> imgs{Ball{Vec3(cx - off, y, z), r}, Ball{Vec3(cx + off, y, z), r}};
        if (t % 4 == 3) imgs.push_back(Ball{Vec3(cx + off, y + 1, z), r});             // no partner: alone
        if (t == 5) imgs = {Ball{Vec3(-3, y, z), r}, Ball{Vec3(2 * cx + 3, y, z), r}}; // against the ends
        orbits.push_back(imgs);
        together.add(imgs);
        for (const Ball& b : imgs) alone.add(b);
        ASSERT_EQ(together.mismatch(), alone.mismatch()) << t;
        ASSERT_EQ(together.covered(), alone.covered()) << t;
        for (int q = 0; q < 20; ++q) {
            const Ball probe{Vec3(60 * u(rng), 26 * u(rng), 22 * u(rng)), 1 + 8 * u(rng)};
            ASSERT_EQ(together.gain(probe), alone.gain(probe)) << t << " " << q;
        }
    }
    std::vector<Ball> all;
    for (const auto& o : orbits) all.insert(all.end(), o.begin(), o.end());
    EXPECT_EQ(together.mismatch(), bruteMismatch(S, all));
    // removed again, ball by ball from the coverage changed in pairs and in pairs from the other (each
    // voxel's count must be right, not just whether it is covered), until none is left
    for (std::size_t t = 0; t < orbits.size(); ++t) {
        for (const Ball& b : orbits[t]) together.remove(b);
        alone.remove(orbits[t]);
        ASSERT_EQ(together.mismatch(), alone.mismatch()) << t;
        for (int q = 0; q < 20; ++q) {
            const Ball probe{Vec3(60 * u(rng), 26 * u(rng), 22 * u(rng)), 1 + 8 * u(rng)};
            ASSERT_EQ(together.gain(probe), alone.gain(probe)) << t << " " << q;
        }
    }
    EXPECT_EQ(together.mismatch(), bruteMismatch(S, {}));
    // a pair whose runs flip only where they overlap: the rest of each row covered before
    Coverage pre(S, GetParam());
    const std::vector<Ball> sides{Ball{Vec3(cx - 8, 13, 11), 4.5}, Ball{Vec3(cx + 8, 13, 11), 4.5}},
        pair{Ball{Vec3(cx - 3, 13, 11), 6}, Ball{Vec3(cx + 3, 13, 11), 6}};
    for (const Ball& b : sides) pre.add(b);
    pre.add(pair);
    for (const Ball& b : sides) pre.remove(b);
    std::vector<Ball> placed = pair;
    EXPECT_EQ(pre.mismatch(), bruteMismatch(S, placed));
    for (int q = 0; q < 40; ++q) {
        const Ball probe{Vec3(cx - 10 + 20 * u(rng), 13 + 4 * u(rng), 11 + 4 * u(rng)), 1 + 6 * u(rng)};
        std::vector<Ball> with = placed;
        with.push_back(probe);
        ASSERT_EQ(pre.gain(probe), bruteMismatch(S, placed) - bruteMismatch(S, with)) << q;
    }
    pre.remove(pair[0]);
    EXPECT_EQ(pre.mismatch(), bruteMismatch(S, {pair[1]}));
}

INSTANTIATE_TEST_SUITE_P(Widths, CoverageCounts, ::testing::Values(std::size_t(255), std::size_t(65535)));

TEST(Coverage, MoreBallsThanItsLimitAreALogicError) {
    const VoxelGrid S = ellipsoid(24, 10, 7, 5);
    Coverage cov(S, 2);
    const Ball b{Vec3(12, 11.5, 11.5), 3.0};
    cov.add(b);
    cov.add(b);
    EXPECT_THROW(cov.add(b), std::logic_error);
    cov.remove(b);
    EXPECT_NO_THROW(cov.add(b)); // two again
    cov.remove(b);
    cov.remove(b);
    EXPECT_THROW(cov.remove(b), std::logic_error); // none left
    EXPECT_THROW(Coverage(S, 65536), std::invalid_argument);
}

TEST(Coverage, OverlappingImagesCountedOnce) {
    const VoxelGrid S = ellipsoid(24, 10, 7, 5);
    Coverage cov(S);
    const std::vector<Ball> pair{{Vec3(10, 11.5, 11.5), 4.0}, {Vec3(13, 11.5, 11.5), 4.0}}; // rows shared
    const std::vector<Ball> three{{Vec3(8, 9, 11.5), 3.0}, {Vec3(11, 10, 12), 3.5}, {Vec3(9, 12, 10), 2.5}};
    for (const auto& balls : {pair, three}) {
        const long long g = cov.gain(balls);
        EXPECT_EQ(g, bruteMismatch(S, {}) - bruteMismatch(S, balls));
    }
}

TEST(Coverage, MirroredGainEqualsTheFullSum) {
    const VoxelGrid S = ellipsoid(24, 10, 7, 5);
    Coverage cov(S);
    cov.setMirrorPlanes({true, true, true});
    const Symmetry sym(S.spec, {true, true, true});
    const Orbit o = sym.make(Vec3(7.2, 8.1, 9.3), 2.5);
    const std::vector<Ball> imgs = sym.images(o);
    ASSERT_EQ(imgs.size(), 8u);
    EXPECT_EQ(cov.gain(imgs, true), cov.gain(imgs, false));
    const Orbit wide = sym.make(Vec3(10.0, 10.0, 11.0), 3.0); // images overlap each other
    EXPECT_EQ(cov.gain(sym.images(wide), true), cov.gain(sym.images(wide), false));
    EXPECT_EQ(cov.gain(sym.images(wide), false), bruteMismatch(S, {}) - bruteMismatch(S, sym.images(wide)));
}

TEST(Coverage, VectorGainEqualsTheRowLoop) {
    // gain() runs four rows at a time where the CPU allows; it must count exactly the rows, ends and sums of
    // the portable loop: balls cut by the grid's faces, centres and radii on the lattice (ends exactly on
    // voxel centres) and off it, rows of every count modulo 4, after other balls changed the prefix and its
    // base
    const VoxelGrid S = ellipsoid(31, 17, 13, 6);
    Coverage cov(S);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-4, 35), rr(0.3, 14);
    std::uniform_int_distribution<int> ui(-3, 33), ri(1, 12);
    for (int t = 0; t < 6; ++t) cov.add(Ball{Vec3(u(rng), u(rng), u(rng)), rr(rng)});
    int nonzero = 0;
    for (int t = 0; t < 4000; ++t) {
        Ball b{Vec3(u(rng), u(rng), u(rng)), rr(rng)};
        if (t % 3 == 1) b = Ball{Vec3(ui(rng), ui(rng), ui(rng)), double(ri(rng))};
        if (t % 3 == 2) b = Ball{Vec3(ui(rng) + 0.5, ui(rng), ui(rng) + 0.5), ri(rng) + 0.5};
        const long long g = cov.gainRows(b);
        ASSERT_EQ(cov.gain(b), g) << "ball " << b.c.transpose() << " r " << b.r;
        nonzero += g != 0;
    }
    EXPECT_GT(nonzero, 1000); // most balls reach the solid
    const Coverage empty(S);  // and against brute force where nothing is placed
    for (const Ball& probe : {Ball{Vec3(15.25, 8.5, 6.75), 5.5}, Ball{Vec3(0.5, 3, 12), 7.0}})
        EXPECT_EQ(empty.gain(probe), bruteMismatch(S, {}) - bruteMismatch(S, {probe}));
}

TEST(Coverage, RowPairGainsAreExact) {
    // two images that differ only in x share their rows (a pair of an x mirror plane): the union of their
    // runs summed per row (four rows at a time where the CPU allows), overlapping, touching, one voxel apart,
    // far apart, cut by the grid's faces, on the lattice and off it; against brute force, and with mirror
    // planes on a symmetric coverage (rows off the planes counted twice) against the full sum
    const VoxelGrid S = ellipsoid(31, 17, 13, 6);
    Coverage cov(S);
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> u(-2, 32), rr(0.4, 13), gap(0, 9);
    std::uniform_int_distribution<int> ui(0, 30), ri(1, 10);
    std::vector<Ball> placed;
    for (int t = 0; t < 5; ++t) {
        placed.push_back(Ball{Vec3(u(rng), u(rng), u(rng)), rr(rng)});
        cov.add(placed.back());
    }
    const long long base = bruteMismatch(S, placed);
    int nonzero = 0;
    for (int t = 0; t < 600; ++t) {
        Ball a{Vec3(u(rng), u(rng), u(rng)), rr(rng)};
        if (t % 3 == 1) a = Ball{Vec3(ui(rng), ui(rng), ui(rng)), double(ri(rng))};
        if (t % 3 == 2) a = Ball{Vec3(ui(rng) + 0.5, ui(rng), ui(rng) + 0.5), ri(rng) + 0.5};
        // the partner: its runs overlapping, touching (2 r apart on the lattice) or apart
        const double dx = t % 4 == 0 ? 2.0 * a.r + 1.0 : t % 4 == 1 ? 2.0 * a.r : gap(rng) * a.r / 3.0;
        const std::vector<Ball> pair{a, Ball{Vec3(a.c.x() + (t % 2 ? dx : -dx), a.c.y(), a.c.z()), a.r}};
        if (pair[0].c.x() == pair[1].c.x()) continue;
        std::vector<Ball> with = placed;
        with.insert(with.end(), pair.begin(), pair.end());
        const long long g = cov.gain(pair);
        ASSERT_EQ(g, base - bruteMismatch(S, with))
            << "ball " << a.c.transpose() << " r " << a.r << " dx " << dx;
        nonzero += g != 0;
    }
    EXPECT_GT(nonzero, 300);
    // mirrored: a symmetric coverage (orbits placed whole), and the orbits whose images are an x pair: on the
    // y and z planes (the grid's middle rows, counted once; the rest of the lower half twice)
    Coverage sym(S);
    sym.setMirrorPlanes({true, true, true});
    const Symmetry planes(S.spec, {true, true, true});
    for (const Orbit& o : {planes.make(Vec3(9.3, 5.2, 4.1), 3.5), planes.make(Vec3(15, 8, 3.5), 4.0)})
        sym.add(planes.images(o));
    const double midY = 0.5 * (S.ny() - 1), midZ = 0.5 * (S.nz() - 1);
    for (int t = 0; t < 200; ++t) {
        const Vec3 c(std::uniform_real_distribution<double>(0, 30)(rng), midY, midZ);
        const Ball a{c, rr(rng)};
        const std::vector<Ball> pair{a, Ball{Vec3(30.0 - c.x(), c.y(), c.z()), a.r}};
        if (pair[0].c.x() == pair[1].c.x()) continue;
        ASSERT_EQ(sym.gain(pair, true), sym.gain(pair, false)) << "ball " << c.transpose() << " r " << a.r;
    }
}

TEST(Coverage, OverlappingOrbitImagesGainExactly) {
    // an orbit's images under mirror planes (2, 4 or 8 balls of one radius: every x centre with every (y, z)
    // position) overlapping each other are summed as one union per row, four rows at a time where the CPU
    // allows: against brute force, alone and after other balls, and on a mirrored coverage against the full
    // sum; a set that is no product (three balls of two radii) takes the general merge
    const VoxelGrid S = ellipsoid(31, 17, 13, 6);
    std::mt19937 rng(23);
    std::uniform_real_distribution<double> ux(8, 22), uy(3, 13), uz(2, 10), rr(2, 9);
    const std::array<std::array<bool, 3>, 5> planeSets{{{true, true, true},
                                                        {true, true, false},
                                                        {false, true, true},
                                                        {true, false, true},
                                                        {false, true, false}}};
    Coverage cov(S);
    std::vector<Ball> placed{{Vec3(12.5, 7, 6), 4.5}, {Vec3(20, 10, 5), 3.0}};
    for (const Ball& b : placed) cov.add(b);
    const long long base = bruteMismatch(S, placed);
    int overlapping = 0;
    for (int t = 0; t < 150; ++t) {
        const Symmetry sym(S.spec, planeSets[std::size_t(t % 5)]);
        const std::vector<Ball> imgs = sym.images(sym.make(Vec3(ux(rng), uy(rng), uz(rng)), rr(rng)));
        if (imgs.size() < 2) continue;
        overlapping += (imgs[0].c - imgs[1].c).norm() <= 2 * imgs[0].r;
        std::vector<Ball> with = placed;
        with.insert(with.end(), imgs.begin(), imgs.end());
        ASSERT_EQ(cov.gain(imgs), base - bruteMismatch(S, with))
            << "orbit " << imgs[0].c.transpose() << " r " << imgs[0].r << " images " << imgs.size();
    }
    EXPECT_GT(overlapping, 50);
    Coverage mirrored(S);
    mirrored.setMirrorPlanes({true, true, true});
    const Symmetry all(S.spec, {true, true, true});
    mirrored.add(all.images(all.make(Vec3(11, 6, 4.5), 3.5)));
    for (int t = 0; t < 100; ++t) {
        const std::vector<Ball> imgs = all.images(all.make(Vec3(ux(rng), uy(rng), uz(rng)), rr(rng)));
        ASSERT_EQ(mirrored.gain(imgs, true), mirrored.gain(imgs, false)) << imgs[0].c.transpose();
    }
    const std::vector<Ball> mixed{{Vec3(10, 8, 6), 4.0}, {Vec3(13, 8, 6), 3.0}, {Vec3(10, 10, 6), 4.0}};
    std::vector<Ball> with = placed;
    with.insert(with.end(), mixed.begin(), mixed.end());
    EXPECT_EQ(cov.gain(mixed), base - bruteMismatch(S, with));
}

TEST(Coverage, GainsOfSeveralRadiiEqualEachGain) {
    // gains() evaluates up to four radii about one centre in one pass (refinement's trial groups): each sum
    // must be gain() of that ball alone, also for radii whose rows start or end apart and a radius of
    // nothing in the grid
    const VoxelGrid S = ellipsoid(31, 17, 13, 6);
    Coverage cov(S);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-4, 35), rr(0.3, 14), dr(-1.5, 1.5);
    for (int t = 0; t < 6; ++t) cov.add(Ball{Vec3(u(rng), u(rng), u(rng)), rr(rng)});
    int nonzero = 0;
    for (int t = 0; t < 2000; ++t) {
        const Vec3 c(u(rng), u(rng), u(rng));
        const int n = 1 + t % Coverage::kMaxRadii;
        double radii[Coverage::kMaxRadii];
        radii[0] = rr(rng);
        for (int m = 1; m < n; ++m) radii[m] = std::max(0.3, radii[0] + (t % 5 == 0 ? 6.0 : 1.0) * dr(rng));
        long long all[Coverage::kMaxRadii];
        cov.gains(c, radii, n, all);
        for (int m = 0; m < n; ++m) {
            const long long g = cov.gain(Ball{c, radii[m]});
            ASSERT_EQ(all[m], g) << "centre " << c.transpose() << " r " << radii[m];
            nonzero += g != 0;
        }
    }
    EXPECT_GT(nonzero, 1000);
    long long out[5];
    const double five[5] = {1, 2, 3, 4, 5};
    EXPECT_THROW(cov.gains(Vec3(5, 5, 5), five, 5, out), std::invalid_argument);
}

TEST(Coverage, LongRowsKeepExactSumsModulo16Bits) {
    // The prefix is kept modulo 2^16: sums over rows up to 32767 voxels long must stay exact however far
    // the prefix and its base drift as balls come and go (a ball of radius 20000 spans whole rows)
    GridSpec g;
    g.dims = {32767, 5, 5};
    VoxelGrid S(g, 0);
    for (int i = 0; i < 32767; ++i) {
        S(i, 2, 2) = 1;                                     // a solid row end to end
        S(i, 1, 2) = static_cast<std::uint8_t>(i % 3 == 0); // and one a third solid
    }
    Coverage cov(S);
    const Ball whole{Vec3(16383, 2, 2), 20000.0};
    EXPECT_EQ(cov.gain(whole), 32767 + 10923 - (32767 * 25 - 32767 - 10923)); // solid in, background in
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> x(0, 32766);
    std::vector<Ball> placed;
    for (int t = 0; t < 400; ++t) { // drift: 400 balls of radius 1.5 in, every other one out again
        const Ball b{Vec3(x(rng), 2, 2), 1.5};
        const long long before = cov.mismatch(), gain = cov.gain(b);
        cov.add(b);
        EXPECT_EQ(before - cov.mismatch(), gain);
        if (t % 2)
            cov.remove(b);
        else
            placed.push_back(b);
    }
    // the whole-row ball now gains what the rows hold uncovered
    long long uncovered = 0;
    for (int k = 0; k < 5; ++k)
        for (int j = 0; j < 5; ++j)
            for (int i = 0; i < 32767; ++i) {
                bool in = false;
                for (const Ball& b : placed) in = in || (Vec3(i, j, k) - b.c).squaredNorm() <= b.r * b.r;
                if (!in) uncovered += S(i, j, k) ? 1 : -1;
            }
    EXPECT_EQ(cov.gain(whole), uncovered);
    EXPECT_EQ(cov.gainRows(whole), uncovered);
}

TEST(Coverage, ByteCountsOverLongRunsCountExactly) {
    // byte counts (at most 255 balls) are changed 16 voxels at a time, their flips summed in byte lanes every
    // 255 blocks: runs of thousands of voxels, alone and as overlapping mirror images (a double change over
    // their overlap), against brute force and the row loop
    GridSpec g;
    g.dims = {9001, 3, 3};
    VoxelGrid S(g, 0);
    for (int i = 1; i < 9000; ++i) {
        S(i, 1, 1) = static_cast<std::uint8_t>(i % 5 != 0);
        S(i, 2, 1) = static_cast<std::uint8_t>(i % 7 < 3);
    }
    Coverage cov(S, 255);
    std::vector<Ball> placed;
    auto check = [&](const char* what) {
        EXPECT_EQ(cov.mismatch(), bruteMismatch(S, placed)) << what;
        for (const Ball& probe : {Ball{Vec3(4500.3, 1, 1), 4400.0}, Ball{Vec3(17.5, 1.2, 1), 9.0}}) {
            std::vector<Ball> with = placed;
            with.push_back(probe);
            EXPECT_EQ(cov.gain(probe), bruteMismatch(S, placed) - bruteMismatch(S, with)) << what;
            EXPECT_EQ(cov.gainRows(probe), cov.gain(probe)) << what;
        }
    };
    const Ball big{Vec3(4000.25, 1, 1), 3990.0}, small{Vec3(3.0, 1, 1), 2.5};
    cov.add(big);
    placed.push_back(big);
    check("one ball over 7980 voxels a row");
    cov.add(small);
    placed.push_back(small);
    check("a small ball at the row's start");
    const std::vector<Ball> pair{{Vec3(3000.5, 1.4, 1), 2600.0}, {Vec3(6000.5, 1.4, 1), 2600.0}};
    cov.add(pair); // x-mirror partners whose runs overlap over 2200 voxels: one pass, counts + 2 there
    placed.insert(placed.end(), pair.begin(), pair.end());
    check("overlapping mirror images");
    cov.remove(big);
    placed.erase(placed.begin());
    check("the first ball removed");
    cov.remove(pair);
    placed.resize(1);
    check("the pair removed");
    cov.remove(small);
    placed.clear();
    check("all removed");
}

TEST(Coverage, RowsLongerThan32767VoxelsAreRefused) {
    GridSpec g;
    g.dims = {32768, 3, 3};
    const VoxelGrid S(g, 0);
    try {
        Coverage cov(S);
        FAIL() << "no error";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("32768 voxels along x"), std::string::npos) << e.what();
    }
}
