#include "mss/voxelize.hpp"

#include <map>
#include <stdexcept>
#include <utility>

namespace mss {

namespace {

/// The running sums of one pair's shared faces (first pass), then its face nearest their centroid (second).
struct PairFaces {
    std::size_t faces = 0;
    Vec3 sum = Vec3::Zero();
    Vec3 centroid = Vec3::Zero();
    double best = std::numeric_limits<double>::infinity();
    Vec3 point = Vec3::Zero();
    Vec3 normal = Vec3::UnitZ();
};

/// Calls @p f(a, b, centre, normal from a to b) for every face two different non-zero labels share, in one
/// fixed order (the grid's, then the axis), so that both passes see the same faces.
template <class F> void eachSharedFace(const LabelGrid& v, F&& f) {
    const GridSpec& g = v.spec;
    const std::size_t stride[3] = {1, std::size_t(g.dims[0]),
                                   std::size_t(g.dims[0]) * std::size_t(g.dims[1])};
    for (int k = 0; k < g.dims[2]; ++k)
        for (int j = 0; j < g.dims[1]; ++j)
            for (int i = 0; i < g.dims[0]; ++i) {
                const std::size_t q = g.index(i, j, k);
                const std::int64_t here = v.labels[q];
                if (here == 0) continue;
                const int at[3] = {i, j, k};
                for (int d = 0; d < 3; ++d) {
                    if (at[d] + 1 >= g.dims[d]) continue;
                    const std::int64_t there = v.labels[q + stride[d]];
                    if (there == 0 || there == here) continue;
                    Vec3 e = Vec3::Zero();
                    e[d] = 1.0;
                    const Vec3 centre = g.voxelCenter(i, j, k) + 0.5 * g.h * e;
                    if (here < there)
                        f(here, there, centre, e);
                    else
                        f(there, here, centre, Vec3(-e));
                }
            }
}

} // namespace

std::vector<LabelContact> findContacts(const LabelGrid& volume) {
    if (volume.labels.size() != volume.spec.size())
        throw std::invalid_argument("findContacts: the labels do not fill the grid");
    std::map<std::pair<std::int64_t, std::int64_t>, PairFaces> pairs;
    eachSharedFace(volume, [&](std::int64_t a, std::int64_t b, const Vec3& c, const Vec3&) {
        PairFaces& p = pairs[{a, b}];
        ++p.faces;
        p.sum += c;
    });
    for (auto& [key, p] : pairs) p.centroid = p.sum / double(p.faces);
    // the face nearest the centroid: on a flat facet its middle, where both grains have the most room for a
    // ball touching it; the first in the scan order on a tie, so that the choice is the volume's alone
    eachSharedFace(volume, [&](std::int64_t a, std::int64_t b, const Vec3& c, const Vec3& n) {
        PairFaces& p = pairs[{a, b}];
        const double d = (c - p.centroid).squaredNorm();
        if (d < p.best) p.best = d, p.point = c, p.normal = n;
    });
    std::vector<LabelContact> out;
    out.reserve(pairs.size());
    for (const auto& [key, p] : pairs) {
        LabelContact c;
        c.a = key.first;
        c.b = key.second;
        c.faces = p.faces;
        c.point = p.point;
        c.normal = p.normal;
        out.push_back(c);
    }
    return out;
}

std::vector<ContactPoint> contactPointsOf(const std::vector<LabelContact>& contacts, std::int64_t label) {
    std::vector<ContactPoint> out;
    for (const LabelContact& c : contacts) {
        if (c.a == label) out.push_back({c.point, -c.normal}); // a lies on the normal's back side
        if (c.b == label) out.push_back({c.point, c.normal});
    }
    return out;
}

} // namespace mss
