#include "mss/generate.hpp"
#include "mss/spheres.hpp"
#include "mss/voxelize.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <string>

#include <omp.h>

using namespace mss;

namespace mss {
// exact: the slabs and tolerances must give the very same numbers
bool operator==(const LabelContact& x, const LabelContact& y) {
    return x.a == y.a && x.b == y.b && x.faces == y.faces && x.gap == y.gap && x.point == y.point &&
           x.normal == y.normal;
}
} // namespace mss

namespace {
/// Two boxes side by side along x, sharing a face of ny x nz voxels: label 1 at i < split, 2 at i >= split;
/// a third label apart from them.
LabelGrid twoBoxes(int nx, int ny, int nz, int split, int line = 0) {
    LabelGrid g;
    g.spec.dims = {nx + 8, ny + 4, nz + 4};
    g.spec.h = 0.5;
    g.spec.origin = Vec3(1, 2, 3);
    g.labels.assign(g.spec.size(), 0);
    for (int k = 2; k < nz + 2; ++k)
        for (int j = 2; j < ny + 2; ++j)
            for (int i = 2; i < nx + 2; ++i)
                g.labels[g.spec.index(i, j, k)] = i < split ? 1 : (i < split + line ? 0 : 2);
    g.labels[g.spec.index(nx + 6, 1, 1)] = 7; // touches nobody
    return g;
}

/// A grid of random labels: a draw r in 0 .. kinds - 1 a voxel (a linear congruential sequence from @p seed),
/// background where r < empty, else @p label(r).
template <class L>
LabelGrid randomLabels(std::array<int, 3> dims, double h, unsigned seed, unsigned kinds, unsigned empty,
                       L label) {
    LabelGrid g;
    g.spec.dims = dims;
    g.spec.h = h;
    for (std::size_t q = 0; q < g.spec.size(); ++q) {
        seed = seed * 1103515245u + 12345u;
        const unsigned r = (seed >> 16) % kinds;
        g.labels.push_back(r < empty ? 0 : label(r));
    }
    return g;
}

/// The least gap between two sphere sets (negative: they overlap by that much).
double setGap(const SphereSet& a, const SphereSet& b) {
    double gap = 1e9;
    for (std::size_t i = 0; i < a.size(); ++i)
        for (std::size_t j = 0; j < b.size(); ++j)
            gap = std::min(gap, (a.centers[i] - b.centers[j]).norm() - a.radii[i] - b.radii[j]);
    return gap;
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
    const std::vector<LabelContact> c = findContacts(g, 0.0);
    ASSERT_EQ(c.size(), 1u);
    const std::vector<LabelContact> one = findContacts(g, 1.0);
    ASSERT_EQ(one.size(), 1u); // touching grains: the same point and normal at any tolerance, a larger patch
    EXPECT_EQ(one[0].point, c[0].point);
    EXPECT_EQ(one[0].normal, c[0].normal);
    EXPECT_EQ(one[0].gap, 0.0);
    EXPECT_GT(one[0].faces, c[0].faces);
    EXPECT_EQ(c[0].gap, 0.0);
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
    // the two grains overlap there: a DEM code sees them touch
    EXPECT_LE(setGap(both[0], both[1]), -0.1 * g.spec.h + 1e-12);
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
    g.labels.assign(8, 1);
    EXPECT_THROW(findContacts(g, -1.0), std::invalid_argument);
    EXPECT_THROW(findContacts(g, NAN), std::invalid_argument);
    EXPECT_THROW(findContacts(g, kMaxContactGap + 1), std::invalid_argument);
}

TEST(Contacts, test_watershed_line_hides_the_contact_at_gap_zero_only) {
    // a line of background voxels between the two grains, as a marker watershed draws it: no shared face
    const LabelGrid g = twoBoxes(21, 9, 7, 12, 1);
    EXPECT_TRUE(findContacts(g, 0.0).empty());
    const std::vector<LabelContact> c = findContacts(g, 1.0);
    ASSERT_EQ(c.size(), 1u);
    EXPECT_EQ(c[0].a, 1);
    EXPECT_EQ(c[0].b, 2);
    EXPECT_EQ(c[0].gap, 1.0);
    // the middle of the line (voxel i = 12), at the middle of the patch
    EXPECT_NEAR(c[0].point.x(), 1 + 0.5 * 12, 1e-12);
    EXPECT_NEAR(c[0].point.y(), 2 + 0.5 * 6, 1e-12);
    EXPECT_NEAR(c[0].point.z(), 3 + 0.5 * 5, 1e-12);
    EXPECT_NEAR(c[0].normal.x(), 1.0, 1e-12);
    // pairs across the line: 9 x 7 straight across and the diagonal ones within a voxel
    EXPECT_GT(c[0].faces, 9u * 7u);
    // two voxels of line: a gap of 2, seen at a tolerance of 2, not of 1.5
    const LabelGrid wide = twoBoxes(22, 9, 7, 12, 2);
    EXPECT_TRUE(findContacts(wide, 1.5).empty());
    const std::vector<LabelContact> w = findContacts(wide, 2.0);
    ASSERT_EQ(w.size(), 1u);
    EXPECT_EQ(w[0].gap, 2.0);
    EXPECT_NEAR(w[0].point.x(), 1 + 0.5 * 12.5, 1e-12);
}

TEST(Contacts, SlabsGiveTheWholeVolumesAnswer) {
    // random labels with background: every tolerance, every slab thickness, the same contacts
    LabelGrid g;
    g.spec.dims = {17, 9, 8};
    g.spec.h = 0.25;
    g.spec.origin = Vec3(-1, 0.5, 2);
    unsigned seed = 7;
    for (std::size_t q = 0; q < g.spec.size(); ++q) {
        seed = seed * 1103515245u + 12345u;
        const unsigned r = (seed >> 16) % 10;
        g.labels.push_back(r < 4 ? 0 : std::int64_t(r));
    }
    for (double gap : {0.0, 1.0, 1.5, 2.0}) {
        const std::vector<LabelContact> whole = findContacts(g, gap);
        ASSERT_FALSE(whole.empty());
        for (int layers : {1, 2, 5}) {
            ContactFinder f(g.spec, gap);
            for (int pass = 0; pass < 2; ++pass)
                for (int x0 = 0; x0 < g.spec.dims[0]; x0 += layers) {
                    const int own = std::min(layers, g.spec.dims[0] - x0);
                    const int lo = std::max(0, x0 - f.margin()),
                              hi = std::min(g.spec.dims[0], x0 + own + f.margin());
                    LabelGrid slab;
                    slab.spec = g.spec;
                    slab.spec.dims[0] = hi - lo;
                    for (int k = 0; k < g.spec.dims[2]; ++k)
                        for (int j = 0; j < g.spec.dims[1]; ++j)
                            for (int i = lo; i < hi; ++i) slab.labels.push_back(0);
                    for (int k = 0; k < g.spec.dims[2]; ++k)
                        for (int j = 0; j < g.spec.dims[1]; ++j)
                            for (int i = lo; i < hi; ++i)
                                slab.labels[slab.spec.index(i - lo, j, k)] = g.labels[g.spec.index(i, j, k)];
                    if (pass == 0)
                        f.count(slab, lo, x0 - lo, own);
                    else
                        f.locate(slab, lo, x0 - lo, own);
                }
            EXPECT_EQ(f.contacts(), whole) << "gap " << gap << ", layers " << layers;
        }
    }
}

TEST(Contacts, GrainsAcrossALineReachItsMiddleAndTouch) {
    // each grain's spheres reach the middle of the line (beyond the grain by half a voxel), so that the two
    // clumps overlap there, even under a bound tighter than that (clipped: a contact ball is added, the only
    // sphere beyond the grain); no other sphere leaves the bound
    const LabelGrid g = twoBoxes(25, 10, 10, 12, 1);
    const std::vector<LabelContact> c = findContacts(g, 1.0);
    ASSERT_EQ(c.size(), 1u);
    for (double share : {1.0, 0.25, 0.0}) {
        SphereSet both[2];
        for (std::int64_t label : {1, 2}) {
            GenerateOptions o;
            o.nSpheres = 3;
            o.contacts = contactPointsOf(c, label);
            o.neighbourProtrusion = std::max(share, 0.25);
            if (share == 0) o.clip = true;
            VoxelGrid others(g.spec, 0);
            for (std::size_t q = 0; q < others.data.size(); ++q)
                others.data[q] = g.labels[q] != 0 && g.labels[q] != label;
            o.neighbours = others;
            const Result r = generate(solidOf(g, label), o);
            EXPECT_EQ(r.metrics.contactsMissed, 0u);
            if (share == 0) EXPECT_EQ(r.metrics.contactsAdded, 1u); // clipped, none of its own reaches
            // the contact ball reaches half a voxel and a twentieth beyond the grain, no more
            EXPECT_LE(r.metrics.protrusion, std::max(r.metrics.protrusionLimit, 0.55 * g.spec.h) + 1e-12);
            both[label - 1] = r.spheres;
        }
        // they overlap: a DEM code sees them touch
        EXPECT_LE(setGap(both[0], both[1]), -0.1 * g.spec.h + 1e-12) << "share " << share;
    }
}

#ifdef _OPENMP
#include <omp.h>

TEST(Contacts, ThreadsGiveTheOneThreadsAnswer) {
    // the slab's planes are shared among threads, each with its own table, merged: the same contacts (and the
    // same point of each, whatever voxel pair each thread saw first) on 1, 2, 3 and 7 threads
    const LabelGrid g = randomLabels({13, 11, 23}, 0.5, 11, 7, 2, [](unsigned r) { return std::int64_t(r); });
    const int before = omp_get_max_threads();
    for (double gap : {0.0, 1.0, 2.0}) {
        omp_set_num_threads(1);
        const std::vector<LabelContact> one = findContacts(g, gap);
        ASSERT_FALSE(one.empty());
        for (int n : {2, 3, 7}) {
            omp_set_num_threads(n);
            EXPECT_EQ(findContacts(g, gap), one) << "gap " << gap << ", threads " << n;
        }
    }
    omp_set_num_threads(before);
}
#endif

namespace {
/// @p s as packed rows x y z r, as clumpGaps reads them.
std::vector<double> rowsOf(const SphereSet& s) {
    std::vector<double> rows;
    for (std::size_t k = 0; k < s.size(); ++k)
        rows.insert(rows.end(), {s.centers[k].x(), s.centers[k].y(), s.centers[k].z(), s.radii[k]});
    return rows;
}
} // namespace

TEST(ClumpGaps, EachPairsLeastGapAgainstEverySpherePair) {
    // random packed clumps of 1..12 spheres; every pair's gap against the plain double loop, on 1 and 2
    // threads; overlaps come out negative, an empty clump +inf
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    SphereSet s;
    std::vector<std::int64_t> offsets{0};
    for (int c = 0; c < 40; ++c) {
        const int n = c == 7 ? 0 : 1 + int(u(rng) * 12);
        const Vec3 at(4 * u(rng), 4 * u(rng), 4 * u(rng));
        for (int k = 0; k < n; ++k) s.add(at + Vec3(u(rng), u(rng), u(rng)), 0.1 + 0.4 * u(rng));
        offsets.push_back(std::int64_t(s.size()));
    }
    std::vector<std::int64_t> i, j;
    for (int a = 0; a < 40; ++a)
        for (int b = a + 1; b < 40; ++b) i.push_back(a), j.push_back(b);
    int overlapping = 0;
    const int before = omp_get_max_threads();
    for (int threads : {1, 2}) {
        omp_set_num_threads(threads);
        const std::vector<double> got = clumpGaps(rowsOf(s).data(), s.size(), offsets, i, j);
        ASSERT_EQ(got.size(), i.size());
        for (std::size_t x = 0; x < i.size(); ++x) {
            double want = std::numeric_limits<double>::infinity();
            for (std::int64_t p = offsets[std::size_t(i[x])]; p < offsets[std::size_t(i[x]) + 1]; ++p)
                for (std::int64_t q = offsets[std::size_t(j[x])]; q < offsets[std::size_t(j[x]) + 1]; ++q)
                    want = std::min(want, (s.centers[std::size_t(p)] - s.centers[std::size_t(q)]).norm() -
                                              s.radii[std::size_t(p)] - s.radii[std::size_t(q)]);
            EXPECT_EQ(got[x], want) << i[x] << " " << j[x];
            overlapping += threads == 1 && want < 0;
        }
    }
    omp_set_num_threads(before);
    EXPECT_GT(overlapping, 10); // the test sees overlaps and gaps both
    EXPECT_TRUE(std::isinf(clumpGaps(rowsOf(s).data(), s.size(), offsets, {7}, {8})[0]));
}

TEST(ClumpGaps, BadOffsetsAndIndicesAreNamed) {
    SphereSet s;
    s.add(Vec3(0, 0, 0), 1);
    s.add(Vec3(3, 0, 0), 1);
    EXPECT_EQ(clumpGaps(rowsOf(s).data(), s.size(), {0, 1, 2}, {0}, {1})[0], 1.0);
    const auto fails = [&](const std::vector<std::int64_t>& o, const std::vector<std::int64_t>& i,
                           const std::vector<std::int64_t>& j, const std::string& says) {
        try {
            clumpGaps(rowsOf(s).data(), s.size(), o, i, j);
            ADD_FAILURE() << "no error for " << says;
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
        }
    };
    fails({0, 1}, {0}, {0}, "the offsets must run from 0 to the number of spheres (2)");
    fails({0, 2, 1, 2}, {0}, {1}, "in order");
    fails({}, {}, {}, "the offsets");
    fails({0, 1, 2}, {0}, {2}, "clump 2 of 2");
    fails({0, 1, 2}, {-1}, {1}, "clump -1 of 2");
    fails({0, 1, 2}, {0, 1}, {1}, "2 first clumps but 1 second ones");
}

TEST(Contacts, EveryVoxelPairCountedAsThePlainLoopCountsIt) {
    // the oracle: every pair of boundary voxels of two grains, looked at one by one; the search's voxel pairs
    // (faces) and least gaps must be its own, for stencils of one word of offsets and of several (gap 3.5)
    const LabelGrid g =
        randomLabels({12, 9, 10}, 1.0, 5, 9, 3, [](unsigned r) { return std::int64_t(r % 4 + 1); });
    const int nx = g.spec.dims[0], ny = g.spec.dims[1], nz = g.spec.dims[2];
    const auto at = [&](int i, int j, int k) -> std::int64_t {
        if (i < 0 || j < 0 || k < 0 || i >= nx || j >= ny || k >= nz) return 0;
        return g.labels[g.spec.index(i, j, k)];
    };
    const auto edge = [&](int i, int j, int k) {
        const std::int64_t l = at(i, j, k);
        return l != 0 && (at(i - 1, j, k) != l || at(i + 1, j, k) != l || at(i, j - 1, k) != l ||
                          at(i, j + 1, k) != l || at(i, j, k - 1) != l || at(i, j, k + 1) != l);
    };
    for (double gap : {1.0, 2.0, 3.5}) {
        std::map<std::pair<std::int64_t, std::int64_t>, std::pair<std::size_t, std::int64_t>> want;
        const int reach = int(std::floor(gap)) + 1;
        for (int k = 0; k < nz; ++k)
            for (int j = 0; j < ny; ++j)
                for (int i = 0; i < nx; ++i)
                    for (int z = -reach; z <= reach; ++z)
                        for (int y = -reach; y <= reach; ++y)
                            for (int x = -reach; x <= reach; ++x) {
                                if (!(z > 0 || (z == 0 && (y > 0 || (y == 0 && x > 0))))) continue;
                                std::int64_t g2 = 0;
                                for (int v : {x, y, z})
                                    g2 += std::int64_t(std::max(std::abs(v) - 1, 0)) *
                                          std::max(std::abs(v) - 1, 0);
                                if (double(g2) > gap * gap * (1 + 1e-12)) continue;
                                const std::int64_t a = at(i, j, k), b = at(i + x, j + y, k + z);
                                if (a == 0 || b == 0 || a == b || !edge(i, j, k) ||
                                    !edge(i + x, j + y, k + z))
                                    continue;
                                auto& w = want[{std::min(a, b), std::max(a, b)}];
                                if (w.first == 0 || g2 < w.second) w.second = g2;
                                ++w.first;
                            }
        const std::vector<LabelContact> got = findContacts(g, gap);
        ASSERT_EQ(got.size(), want.size()) << "gap " << gap;
        for (const LabelContact& c : got) {
            const auto& w = want.at({c.a, c.b});
            EXPECT_EQ(c.faces, w.first) << c.a << "-" << c.b << ", gap " << gap;
            EXPECT_EQ(c.gap, std::sqrt(double(w.second))) << c.a << "-" << c.b << ", gap " << gap;
        }
    }
}
