#include "mss/generate.hpp"
#include "mss/voxelize.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace mss;

namespace {
/// Two boxes side by side along x, sharing a face of ny x nz voxels: label 1 at i < split, 2 at i >= split;
/// a third label apart from them.
LabelGrid twoBoxes(int nx, int ny, int nz, int split) {
    LabelGrid g;
    g.spec.dims = {nx + 8, ny + 4, nz + 4};
    g.spec.h = 0.5;
    g.spec.origin = Vec3(1, 2, 3);
    g.labels.assign(g.spec.size(), 0);
    for (int k = 2; k < nz + 2; ++k)
        for (int j = 2; j < ny + 2; ++j)
            for (int i = 2; i < nx + 2; ++i) g.labels[g.spec.index(i, j, k)] = i < split ? 1 : 2;
    g.labels[g.spec.index(nx + 6, 1, 1)] = 7; // touches nobody
    return g;
}

/// The solid of one label, as a VoxelGrid on the same grid.
VoxelGrid solidOf(const LabelGrid& g, std::int64_t label) {
    VoxelGrid v(g.spec, 0);
    for (std::size_t q = 0; q < v.data.size(); ++q) v.data[q] = g.labels[q] == label;
    return v;
}
} // namespace

TEST(Contacts, TwoBoxesShareOneFaceAtItsMiddle) {
    const LabelGrid g = twoBoxes(20, 9, 7, 12);
    const std::vector<LabelContact> c = findContacts(g);
    ASSERT_EQ(c.size(), 1u);
    EXPECT_EQ(c[0].a, 1);
    EXPECT_EQ(c[0].b, 2);
    EXPECT_EQ(c[0].faces, 9u * 7u);
    // the face between voxels i = 11 and 12, at the middle of the 9 x 7 patch (j = 6, k = 5)
    EXPECT_NEAR(c[0].point.x(), 1 + 0.5 * 11.5, 1e-12);
    EXPECT_NEAR(c[0].point.y(), 2 + 0.5 * 6, 1e-12);
    EXPECT_NEAR(c[0].point.z(), 3 + 0.5 * 5, 1e-12);
    EXPECT_EQ(c[0].normal, Vec3::UnitX()); // from 1 into 2
    const std::vector<ContactPoint> of1 = contactPointsOf(c, 1), of2 = contactPointsOf(c, 2);
    ASSERT_EQ(of1.size(), 1u);
    EXPECT_EQ(of1[0].inward, -Vec3::UnitX());
    EXPECT_EQ(of2[0].inward, Vec3::UnitX());
    EXPECT_TRUE(contactPointsOf(c, 7).empty());
}

TEST(Contacts, EachGrainReachesTheSharedPointWithoutBumps) {
    const LabelGrid g = twoBoxes(24, 10, 10, 12);
    const std::vector<LabelContact> c = findContacts(g);
    SphereSet both[2];
    for (std::int64_t label : {1, 2}) {
        GenerateOptions o;
        o.nSpheres = 3;
        o.contacts = contactPointsOf(c, label);
        const Result r = generate(solidOf(g, label), o);
        EXPECT_EQ(r.metrics.contacts, 1u);
        EXPECT_EQ(r.metrics.contactsMissed, 0u);
        EXPECT_LE(r.metrics.protrusion, r.metrics.protrusionLimit + 1e-12); // no bump beyond the bound
        double gap = 1e9;
        for (std::size_t i = 0; i < r.spheres.size(); ++i)
            gap = std::min(gap, (c[0].point - r.spheres.centers[i]).norm() - r.spheres.radii[i]);
        EXPECT_LE(gap, -0.05 * g.spec.h + 1e-12); // the point inside the spheres
        both[label - 1] = r.spheres;
    }
    double gap = 1e9;
    for (std::size_t i = 0; i < both[0].size(); ++i)
        for (std::size_t j = 0; j < both[1].size(); ++j)
            gap = std::min(gap, (both[0].centers[i] - both[1].centers[j]).norm() - both[0].radii[i] -
                                    both[1].radii[j]);
    EXPECT_LE(gap, -0.1 * g.spec.h + 1e-12); // the two grains overlap there: a DEM code sees them touch
}

TEST(Contacts, BadContactPointsAreRefused) {
    GenerateOptions o;
    o.nSpheres = 2;
    o.contacts = {{Vec3(0, 0, 0), Vec3::Zero()}};
    EXPECT_THROW(validateOptions(o), std::invalid_argument);
    o.contacts = {{Vec3(NAN, 0, 0), Vec3::UnitX()}};
    EXPECT_THROW(validateOptions(o), std::invalid_argument);
    LabelGrid g;
    g.spec.dims = {2, 2, 2};
    EXPECT_THROW(findContacts(g), std::invalid_argument); // labels that do not fill the grid
}
