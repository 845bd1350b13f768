#include "mss/voxelize.hpp"

#include <map>
#include <stdexcept>
#include <tuple>
#include <utility>

namespace mss {

namespace {

/// A shared face in half-voxel units of the whole volume: its centre is origin + h (x, y, z) / 2. Integers,
/// so that sums and comparisons are exact and the same however the volume is cut into slabs.
using Face = std::array<std::int64_t, 3>;

/// Calls @p f(a, b, face, axis, sign of the normal from a to b) for every face two different non-zero labels
/// share in @p slab, whose layer x = 0 is the volume's layer @p x0. Faces across x are taken between all its
/// layers; faces across y and z in its first @p own layers only (the last layer of a slab that overlaps the
/// next by one is the next one's).
template <class F> void eachSharedFace(const LabelGrid& slab, long long x0, int own, F&& f) {
    const GridSpec& g = slab.spec;
    const std::size_t stride[3] = {1, std::size_t(g.dims[0]),
                                   std::size_t(g.dims[0]) * std::size_t(g.dims[1])};
    for (int k = 0; k < g.dims[2]; ++k)
        for (int j = 0; j < g.dims[1]; ++j)
            for (int i = 0; i < g.dims[0]; ++i) {
                const std::size_t q = g.index(i, j, k);
                const std::int64_t here = slab.labels[q];
                if (here == 0) continue;
                const int at[3] = {i, j, k};
                for (int d = 0; d < 3; ++d) {
                    if (at[d] + 1 >= g.dims[d] || (d > 0 && i >= own)) continue;
                    const std::int64_t there = slab.labels[q + stride[d]];
                    if (there == 0 || there == here) continue;
                    Face c{2 * (x0 + i), 2 * std::int64_t(j), 2 * std::int64_t(k)};
                    c[std::size_t(d)] += 1;
                    if (here < there)
                        f(here, there, c, d, 1);
                    else
                        f(there, here, c, d, -1);
                }
            }
}

} // namespace

struct ContactFinder::Pairs {
    struct Pair {
        std::size_t faces = 0;
        Face sum{0, 0, 0};
        Face normals{0, 0, 0}; ///< the sum of the faces' normals (a to b): the patch's mean normal
        double best = std::numeric_limits<double>::infinity();
        Face at{0, 0, 0};
        int axis = 0, sign = 1;
    };
    std::map<std::pair<std::int64_t, std::int64_t>, Pair> pairs;
};

ContactFinder::ContactFinder(const GridSpec& volume) : volume_(volume), pairs_(std::make_shared<Pairs>()) {}

void ContactFinder::count(const LabelGrid& slab, long long x0, int own) {
    if (slab.labels.size() != slab.spec.size())
        throw std::invalid_argument("findContacts: the labels do not fill the grid");
    eachSharedFace(slab, x0, own, [&](std::int64_t a, std::int64_t b, const Face& c, int axis, int sign) {
        Pairs::Pair& p = pairs_->pairs[{a, b}];
        ++p.faces;
        for (int d = 0; d < 3; ++d) p.sum[std::size_t(d)] += c[std::size_t(d)];
        p.normals[std::size_t(axis)] += sign;
    });
}

void ContactFinder::locate(const LabelGrid& slab, long long x0, int own) {
    // the face nearest the centroid of the pair's faces: on a flat facet its middle, where both grains have
    // the most room for a ball through it; on a tie the least (x, y, z), so that the choice is the volume's
    // alone, whatever the slabs
    eachSharedFace(slab, x0, own, [&](std::int64_t a, std::int64_t b, const Face& c, int axis, int sign) {
        Pairs::Pair& p = pairs_->pairs[{a, b}];
        double d = 0;
        for (int e = 0; e < 3; ++e) {
            const double x = double(c[std::size_t(e)]) - double(p.sum[std::size_t(e)]) / double(p.faces);
            d += x * x;
        }
        if (d < p.best || (d == p.best && c < p.at)) p.best = d, p.at = c, p.axis = axis, p.sign = sign;
    });
}

std::vector<LabelContact> ContactFinder::contacts() const {
    std::vector<LabelContact> out;
    out.reserve(pairs_->pairs.size());
    for (const auto& [key, p] : pairs_->pairs) {
        LabelContact c;
        c.a = key.first;
        c.b = key.second;
        c.faces = p.faces;
        c.point = volume_.origin + 0.5 * volume_.h * Vec3(double(p.at[0]), double(p.at[1]), double(p.at[2]));
        // the patch's mean normal: a facet oblique to the axes is a staircase of voxel faces, whose own
        // normals (the axes) point into the steps; a ball along the mean one stays clear of them (on a
        // Voronoi specimen the contact balls along the face's axis had radii of 0.7-0.9 voxels and set the
        // time step)
        c.normal = Vec3(double(p.normals[0]), double(p.normals[1]), double(p.normals[2]));
        if (c.normal.norm() > 0)
            c.normal.normalize();
        else { // faces whose normals cancel: the chosen face's own
            c.normal = Vec3::Zero();
            c.normal[p.axis] = p.sign;
        }
        out.push_back(c);
    }
    return out;
}

std::vector<LabelContact> findContacts(const LabelGrid& volume) {
    ContactFinder f(volume.spec);
    f.count(volume, 0, volume.spec.dims[0]);
    f.locate(volume, 0, volume.spec.dims[0]);
    return f.contacts();
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
