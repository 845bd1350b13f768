#include "mss/voxelize.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <tuple>
#include <unordered_map>
#include <utility>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace mss {

namespace {

/// A point in half-voxel units of the whole volume: origin + h (x, y, z) / 2. Integers, so that sums and
/// comparisons are exact and the same however the volume is cut into slabs.
using Half = std::array<std::int64_t, 3>;

/// The offsets from a voxel to the voxels of another grain that count as its contact partners: with a gap
/// tolerance of 0 the three face neighbours (shared faces); otherwise every offset whose voxel cube lies
/// within @p gap voxels of this one's (the squared gap sum max(|d| - 1, 0)^2, an integer), half of them
/// (the other half is the same pair seen from the far voxel).
struct Stencil {
    struct Offset {
        int d[3];
        std::int64_t gap2; ///< squared gap between the two cubes, voxels^2
    };
    std::vector<Offset> offsets;
    int reach = 1;      ///< the largest |d| of an offset
    bool faces = false; ///< shared faces only (a tolerance of 0)

    explicit Stencil(double gap) {
        if (gap == 0) {
            faces = true;
            offsets = {{{1, 0, 0}, 0}, {{0, 1, 0}, 0}, {{0, 0, 1}, 0}};
            return;
        }
        reach = int(std::floor(gap)) + 1;
        const double limit = gap * gap * (1 + 1e-12);
        for (int z = -reach; z <= reach; ++z)
            for (int y = -reach; y <= reach; ++y)
                for (int x = -reach; x <= reach; ++x) {
                    if (!(z > 0 || (z == 0 && (y > 0 || (y == 0 && x > 0))))) continue; // the positive half
                    std::int64_t g2 = 0;
                    for (int v : {x, y, z}) {
                        const std::int64_t beyond = std::max(std::abs(v) - 1, 0);
                        g2 += beyond * beyond;
                    }
                    if (double(g2) <= limit) offsets.push_back({{x, y, z}, g2});
                }
    }
};

using Key = std::pair<std::int64_t, std::int64_t>;

struct KeyHash {
    std::size_t operator()(const Key& k) const {
        const std::uint64_t h = std::uint64_t(k.first) * 0x9E3779B97F4A7C15ull ^ std::uint64_t(k.second);
        return std::size_t(h ^ (h >> 29));
    }
};

/// A hashed map of pairs with the last one asked for at hand: the voxel pairs of one contact come one after
/// another (along a row of voxels), so it answers most asks (a scan of 10^4 grains asks 4 10^7 times; a
/// tree's lookups were half the time). Its elements stay where they are (rehashing moves none).
template <class Value> struct PairMap {
    std::unordered_map<Key, Value, KeyHash> map;
    Value* last = nullptr;
    Key lastKey{0, 0};

    Value& at(std::int64_t a, std::int64_t b) {
        if (last == nullptr || lastKey.first != a || lastKey.second != b) {
            lastKey = {a, b};
            last = &map[lastKey];
        }
        return *last;
    }
};

/// Where a pair's point lies: the least (distance to the centroid, midpoint, axis, sign) over its voxel pairs
/// at the least gap, a total order, so that the choice is the same whatever order the pairs come in (threads,
/// slabs).
struct Spot {
    double best = std::numeric_limits<double>::infinity();
    Half at{0, 0, 0};
    int axis = 0, sign = 1;

    bool before(const Spot& o) const {
        return std::tie(best, at, axis, sign) < std::tie(o.best, o.at, o.axis, o.sign);
    }
};

} // namespace

struct ContactFinder::Pairs {
    struct Pair {
        std::size_t faces = 0;   ///< voxel pairs within the tolerance
        Half normals{0, 0, 0};   ///< the sum of their offsets, a to b: the patch's mean normal
        std::int64_t least = -1; ///< the least squared gap of a voxel pair
        std::size_t nearest = 0; ///< voxel pairs at the least gap
        Half sum{0, 0, 0};       ///< the sum of their midpoints
        Spot spot;               ///< the point (locate)

        /// Adds @p o's voxel pairs (another part of the volume's) to these.
        void merge(const Pair& o) {
            faces += o.faces;
            for (std::size_t e = 0; e < 3; ++e) normals[e] += o.normals[e];
            if (o.least < 0) return;
            if (least < 0 || o.least < least) least = o.least, nearest = 0, sum = {0, 0, 0};
            if (o.least == least) {
                nearest += o.nearest;
                for (std::size_t e = 0; e < 3; ++e) sum[e] += o.sum[e];
            }
        }
    };
    // hashed, contacts() gives them sorted
    std::unordered_map<Key, Pair, KeyHash> pairs;
    Stencil stencil;
    explicit Pairs(double gap) : stencil(gap) {}
};

ContactFinder::ContactFinder(const GridSpec& volume, double gap) : volume_(volume) {
    if (!(gap >= 0) || !std::isfinite(gap) || gap > kMaxContactGap)
        throw std::invalid_argument("findContacts: the contact gap must be in [0, " +
                                    std::to_string(int(kMaxContactGap)) + "] voxels, got " +
                                    std::to_string(gap));
    pairs_ = std::make_shared<Pairs>(gap);
}

int ContactFinder::margin() const {
    return pairs_->stencil.reach + 1;
}

namespace {

/// The labels of the slab's boundary voxels (a face neighbour of another value: the least gap between two
/// grains is always between two such voxels), 0 elsewhere, where the slab knows their neighbours (the caller
/// gives margin() layers on each side of those it owns). Labels, not flags: eachPair compares 64-bit lanes
/// only.
std::vector<std::int64_t> edgesOf(const LabelGrid& slab) {
    const GridSpec& g = slab.spec;
    const long long nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
    const auto at = [&](long long i, long long j, long long k) -> std::int64_t {
        if (i < 0 || j < 0 || k < 0 || i >= nx || j >= ny || k >= nz) return 0;
        return slab.labels[std::size_t(i + nx * (j + ny * k))];
    };
    std::vector<std::int64_t> edge(slab.labels.size(), 0);
#pragma omp parallel for schedule(static)
    for (long long k = 0; k < nz; ++k)
        for (long long j = 0; j < ny; ++j)
            for (long long i = 0; i < nx; ++i) {
                const std::int64_t l = at(i, j, k);
                if (l == 0) continue;
                if (at(i - 1, j, k) != l || at(i + 1, j, k) != l || at(i, j - 1, k) != l ||
                    at(i, j + 1, k) != l || at(i, j, k - 1) != l || at(i, j, k + 1) != l)
                    edge[std::size_t(i + nx * (j + ny * k))] = l;
            }
    return edge;
}

// The hot loop below in AVX2 where the processor has it (chosen when the library loads): the baseline x86-64
// has no 64-bit compare in its vector registers (SSE4.1's), so there the loop runs a voxel at a time
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
#define MSS_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define MSS_CLONES
#endif

/// Sets @p bit of M[i * words] for every i in [lo, hi) where A[i] and B[i] are both non-zero and apart.
MSS_CLONES void markHits(const std::int64_t* __restrict A, const std::int64_t* __restrict B,
                         std::uint64_t* __restrict M, std::size_t words, long long lo, long long hi,
                         unsigned bit) {
    if (words == 1)
        for (long long i = lo; i < hi; ++i)
            M[i] |= std::uint64_t((A[i] != 0) & (B[i] != 0) & (A[i] != B[i])) << bit;
    else
        for (long long i = lo; i < hi; ++i)
            M[std::size_t(i) * words] |= std::uint64_t((A[i] != 0) & (B[i] != 0) & (A[i] != B[i])) << bit;
}

/// Calls @p f(a, b, midpoint, offset a to b, sign, squared gap) for every pair of voxels of two different
/// non-zero labels within the stencil, both on their grain's boundary (@p edge, edgesOf's labels; for shared
/// faces the slab's own), the first in the slab's layers first .. first + own - 1 and in its planes
/// k0 .. k1 - 1. The slab's layer 0 is the volume's layer @p x0.
template <class F>
void eachPair(const LabelGrid& slab, const std::vector<std::int64_t>& edge, long long x0, int first, int own,
              const Stencil& st, long long k0, long long k1, F&& f) {
    const GridSpec& g = slab.spec;
    const long long nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
    // offset by offset along each row of voxels: two contiguous runs compared, a loop without branches over
    // the row (a voxel at a time through its stencil took longer), into each voxel's bit mask of the offsets
    // that hit; then the hits voxel by voxel, so that a voxel's partners (mostly one grain across the line)
    // come one after another and the callers' last-pair caches answer (offset by offset, the pair changed at
    // nearly every hit: hashed lookups were most of the time). The callers' sums and least-of choices do not
    // depend on the order the pairs come in. The labels compared are those of the voxels that can have a
    // partner (edges, which are never background; every voxel for shared faces).
    const std::int64_t* L = st.faces ? slab.labels.data() : edge.data();
    const std::size_t width = std::size_t(std::max<long long>(nx, 1));
    const std::size_t offsets = st.offsets.size(), words = (offsets + 63) / 64;
    std::vector<std::uint64_t> mask(words * width);
    std::vector<long long> steps(offsets);
    for (std::size_t oi = 0; oi < offsets; ++oi) {
        const int* d = st.offsets[oi].d;
        steps[oi] = d[0] + nx * (d[1] + ny * d[2]);
    }
    for (long long k = k0; k < k1; ++k)
        for (long long j = 0; j < ny; ++j) {
            const long long row = nx * (j + ny * k);
            std::fill(mask.begin(), mask.end(), std::uint64_t(0));
            long long from = nx, to = 0; // the voxels of the row that may have a hit
            for (std::size_t oi = 0; oi < offsets; ++oi) {
                const Stencil::Offset& o = st.offsets[oi];
                const long long J = j + o.d[1], K = k + o.d[2];
                const long long lo = std::max<long long>(first, -o.d[0]);
                const long long hi = std::min<long long>(first + own, nx - o.d[0]);
                if (J < 0 || K < 0 || J >= ny || K >= nz || hi <= lo) continue;
                // straight into the masks (a voxel's word of them: the stencil of a gap under 2 voxels has 62
                // offsets, one word; larger ones several)
                markHits(L + row, L + row + steps[oi], mask.data() + oi / 64, words, lo, hi,
                         unsigned(oi % 64));
                from = std::min(from, lo);
                to = std::max(to, hi);
            }
            for (long long i = from; i < to; ++i) {
                const long long q = row + i;
                const std::int64_t here = L[q];
                for (std::size_t w = 0; w < words; ++w)
                    for (std::uint64_t m = mask[std::size_t(i) * words + w]; m != 0; m &= m - 1) {
                        const std::size_t oi = 64 * w + std::size_t(__builtin_ctzll(m));
                        const Stencil::Offset& o = st.offsets[oi];
                        const std::int64_t there = L[q + steps[oi]];
                        const Half mid{2 * (x0 + i) + o.d[0], 2 * j + o.d[1], 2 * k + o.d[2]};
                        if (here < there)
                            f(here, there, mid, o.d, 1, o.gap2);
                        else
                            f(there, here, mid, o.d, -1, o.gap2);
                    }
            }
        }
}

/// The parts a slab of @p nz planes is cut into, one a thread (OpenMP's).
int partsOf(long long nz) {
#ifdef _OPENMP
    return int(std::max<long long>(1, std::min<long long>(omp_get_max_threads(), nz)));
#else
    (void)nz;
    return 1;
#endif
}

/// Runs @p work(t, k0, k1) for parts t = 0 .. n - 1 of the slab's @p nz planes, on n threads. Each part's
/// results go to its own table, merged by the caller in part order.
template <class W> void byPlanes(long long nz, int n, W&& work) {
#pragma omp parallel for schedule(static, 1) num_threads(n)
    for (int t = 0; t < n; ++t) work(t, nz * t / n, nz * (t + 1) / n);
}

} // namespace

void ContactFinder::count(const LabelGrid& slab, long long x0, int first, int own) {
    if (slab.labels.size() != slab.spec.size())
        throw std::invalid_argument("findContacts: the labels do not fill the grid");
    const Stencil& st = pairs_->stencil;
    const std::vector<std::int64_t> edge = st.faces ? std::vector<std::int64_t>() : edgesOf(slab);
    const int n = partsOf(slab.spec.dims[2]);
    std::vector<PairMap<Pairs::Pair>> parts(static_cast<std::size_t>(n));
    byPlanes(slab.spec.dims[2], n, [&](int t, long long k0, long long k1) {
        PairMap<Pairs::Pair>& m = parts[std::size_t(t)];
        eachPair(
            slab, edge, x0, first, own, st, k0, k1,
            [&](std::int64_t a, std::int64_t b, const Half& mid, const int* d, int sign, std::int64_t g2) {
                Pairs::Pair& p = m.at(a, b);
                ++p.faces;
                for (int e = 0; e < 3; ++e) p.normals[std::size_t(e)] += sign * d[e];
                if (p.least < 0 || g2 < p.least) p.least = g2, p.nearest = 0, p.sum = {0, 0, 0};
                if (g2 == p.least) {
                    ++p.nearest;
                    for (int e = 0; e < 3; ++e) p.sum[std::size_t(e)] += mid[std::size_t(e)];
                }
            });
    });
    for (int t = 0; t < n; ++t)
        for (const auto& kv : parts[std::size_t(t)].map) pairs_->pairs[kv.first].merge(kv.second);
}

void ContactFinder::locate(const LabelGrid& slab, long long x0, int first, int own) {
    // the midpoint of a pair at the least gap nearest the centroid of all of them: on a flat facet its
    // middle, where both grains have the most room for a ball through it (across a separating line, the
    // line's middle); on a tie the least (x, y, z), so that the choice is the volume's alone, whatever the
    // slabs and threads
    const Stencil& st = pairs_->stencil;
    const std::vector<std::int64_t> edge = st.faces ? std::vector<std::int64_t>() : edgesOf(slab);
    const auto& pairs = pairs_->pairs; // read only here: every pair was counted
    const int n = partsOf(slab.spec.dims[2]);
    std::vector<PairMap<Spot>> parts(static_cast<std::size_t>(n));
    byPlanes(slab.spec.dims[2], n, [&](int t, long long k0, long long k1) {
        PairMap<Spot>& m = parts[std::size_t(t)];
        const Pairs::Pair* p = nullptr;
        Key key{0, 0};
        eachPair(
            slab, edge, x0, first, own, st, k0, k1,
            [&](std::int64_t a, std::int64_t b, const Half& mid, const int* d, int sign, std::int64_t g2) {
                if (p == nullptr || key.first != a || key.second != b) {
                    key = {a, b};
                    p = &pairs.at(key);
                }
                if (g2 != p->least) return;
                Spot s;
                s.best = 0;
                for (int e = 0; e < 3; ++e) {
                    const double x =
                        double(mid[std::size_t(e)]) - double(p->sum[std::size_t(e)]) / double(p->nearest);
                    s.best += x * x;
                }
                s.at = mid;
                s.axis = int(
                    std::max_element(d, d + 3, [](int u, int v) { return std::abs(u) < std::abs(v); }) - d);
                s.sign = sign * (d[s.axis] > 0 ? 1 : -1);
                Spot& mine = m.at(a, b);
                if (s.before(mine)) mine = s;
            });
    });
    for (int t = 0; t < n; ++t)
        for (const auto& kv : parts[std::size_t(t)].map) {
            Spot& s = pairs_->pairs.at(kv.first).spot;
            if (kv.second.before(s)) s = kv.second;
        }
}

std::vector<LabelContact> ContactFinder::contacts() const {
    std::vector<LabelContact> out;
    out.reserve(pairs_->pairs.size());
    std::vector<std::pair<std::int64_t, std::int64_t>> keys;
    keys.reserve(pairs_->pairs.size());
    for (const auto& kv : pairs_->pairs) keys.push_back(kv.first);
    std::sort(keys.begin(), keys.end()); // in (a, b) order, whatever the hashing
    for (const auto& key : keys) {
        const Pairs::Pair& p = pairs_->pairs.at(key);
        const Spot& spot = p.spot;
        LabelContact c;
        c.a = key.first;
        c.b = key.second;
        c.faces = p.faces;
        c.gap = std::sqrt(double(p.least));
        c.point = volume_.origin +
                  0.5 * volume_.h * Vec3(double(spot.at[0]), double(spot.at[1]), double(spot.at[2]));
        // the patch's mean normal: a facet oblique to the axes is a staircase of voxel faces, whose own
        // normals (the axes) point into the steps; a ball along the mean one stays clear of them (on a
        // Voronoi specimen the contact balls along the face's axis had radii of 0.7-0.9 voxels and set the
        // time step)
        c.normal = Vec3(double(p.normals[0]), double(p.normals[1]), double(p.normals[2]));
        if (c.normal.norm() > 0)
            c.normal.normalize();
        else { // offsets whose sum cancels: the chosen pair's main axis
            c.normal = Vec3::Zero();
            c.normal[spot.axis] = spot.sign;
        }
        out.push_back(c);
    }
    return out;
}

std::vector<LabelContact> findContacts(const LabelGrid& volume, double gap) {
    ContactFinder f(volume.spec, gap);
    f.count(volume, 0, 0, volume.spec.dims[0]);
    f.locate(volume, 0, 0, volume.spec.dims[0]);
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
