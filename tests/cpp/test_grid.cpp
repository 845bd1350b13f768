#include "mss/grid.hpp"

#include <gtest/gtest.h>

using namespace mss;

TEST(Grid, IndexIsXFastest) {
    GridSpec g;
    g.dims = {4, 5, 6};
    EXPECT_EQ(g.index(1, 0, 0), 1u);
    EXPECT_EQ(g.index(0, 1, 0), 4u);
    EXPECT_EQ(g.index(0, 0, 1), 20u);
    EXPECT_EQ(g.size(), 120u);
}

TEST(Grid, WorldVoxelRoundTrip) {
    GridSpec g;
    g.dims = {10, 10, 10};
    g.h = 0.25;
    g.origin = Vec3(1.0, -2.0, 3.0);
    const Vec3 p(1.6, -1.1, 3.9);
    EXPECT_NEAR((g.toWorld(g.toVoxel(p)) - p).norm(), 0.0, 1e-14); // exact up to rounding
    EXPECT_EQ(g.voxelCenter(2, 0, 0).x(), 1.5);
    // a point 0.49 voxel from a centre belongs to that voxel; 0.51 to the next
    auto v = g.voxelOf(g.voxelCenter(3, 4, 5) + Vec3(0.49 * g.h, -0.49 * g.h, 0.0));
    EXPECT_EQ(v, (std::array<int, 3>{3, 4, 5}));
    v = g.voxelOf(g.voxelCenter(3, 4, 5) + Vec3(0.51 * g.h, 0.0, 0.0));
    EXPECT_EQ(v[0], 4);
    EXPECT_TRUE(g.contains(9, 9, 9));
    EXPECT_FALSE(g.contains(10, 0, 0));
    EXPECT_FALSE(g.contains(-1, 0, 0));
}

TEST(Grid, SizeGuardNamesTheMemory) {
    try {
        checkGridSize("test", {100000, 100000, 100000}, 14, std::size_t(8) << 30);
        FAIL() << "no exception";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("would need"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("GiB"), std::string::npos) << e.what();
    }
    EXPECT_THROW(checkGridSize("test", {0, 5, 5}, 1, 1 << 20), std::invalid_argument);
    EXPECT_NO_THROW(checkGridSize("test", {100, 100, 100}, 14, std::size_t(8) << 30));
}

TEST(Grid, CountSolidCountsEveryNonzeroByte) {
    // countSolid sums runs of 255 bytes in byte counters: sizes around the run length, every byte value
    // (a count of 255 in one run must not wrap), against a plain loop
    for (int nx : {1, 254, 255, 256, 511, 1000}) {
        GridSpec g;
        g.dims = {nx, 3, 1};
        VoxelGrid v(g, 0);
        for (std::size_t i = 0; i < v.data.size(); ++i) v.data[i] = std::uint8_t((i * 37 + nx) % 256);
        std::size_t plain = 0;
        for (std::uint8_t x : v.data) plain += x != 0;
        EXPECT_EQ(countSolid(v), plain) << nx;
        VoxelGrid full(g, 255);
        EXPECT_EQ(countSolid(full), full.data.size()) << nx;
    }
}
