// Scores on the exact shapes by Monte Carlo (mss compare --exact): the grain (a mesh by its winding number, a
// voxel volume as the union of its voxels' cubes) and the spheres sampled at the same uniform points of a box
// that holds both. A grid score voxelises both shapes, and a flat face that lies on a lattice plane is
// counted whole or not at all there (the axis-aligned tetrahedron scores 4-5% above its exact D); points
// drawn independently of any lattice have no such bias, only a standard error, which is reported.
#include "mss/core/mesh_query.hpp"
#include "mss/generation/estimates.hpp"
#include "mss/score.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace mss {

namespace {

/// SplitMix64 (Steele, Lea and Flood, "Fast splittable pseudorandom number generators", OOPSLA 2014) of a
/// counter: point i's coordinates are the same whatever the threads, and on every platform.
inline std::uint64_t mix(std::uint64_t z) {
    z += 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}
inline double unit(std::uint64_t z) {
    return double(mix(z) >> 11) * (1.0 / 9007199254740992.0); // 53 bits in [0, 1)
}

/// The spheres bucketed in a uniform grid of cells: a point's candidates are its cell's.
class SphereBuckets {
public:
    explicit SphereBuckets(const SphereSet& s) : s_(s) {
        lo_ = hi_ = s.centers[0];
        double mean = 0.0;
        for (std::size_t i = 0; i < s.size(); ++i) {
            lo_ = lo_.cwiseMin(s.centers[i] - Vec3::Constant(s.radii[i]));
            hi_ = hi_.cwiseMax(s.centers[i] + Vec3::Constant(s.radii[i]));
            mean += s.radii[i] / double(s.size());
        }
        cell_ = 2.0 * mean;
        for (;;) { // at most about a million cells
            for (int a = 0; a < 3; ++a) n_[a] = std::max(1, int(std::ceil((hi_[a] - lo_[a]) / cell_)));
            if (double(n_[0]) * n_[1] * n_[2] <= 1e6) break;
            cell_ *= 2.0;
        }
        cells_.assign(std::size_t(n_[0]) * n_[1] * n_[2], {});
        for (std::size_t i = 0; i < s.size(); ++i) {
            const auto a = cellOf(s.centers[i] - Vec3::Constant(s.radii[i]));
            const auto b = cellOf(s.centers[i] + Vec3::Constant(s.radii[i]));
            for (int x = a[0]; x <= b[0]; ++x)
                for (int y = a[1]; y <= b[1]; ++y)
                    for (int z = a[2]; z <= b[2]; ++z) cells_[index(x, y, z)].push_back(int(i));
        }
    }
    bool inside(const Vec3& p) const {
        for (int a = 0; a < 3; ++a)
            if (p[a] < lo_[a] || p[a] > hi_[a]) return false;
        const auto c = cellOf(p);
        for (int i : cells_[index(c[0], c[1], c[2])])
            if ((p - s_.centers[std::size_t(i)]).squaredNorm() <
                s_.radii[std::size_t(i)] * s_.radii[std::size_t(i)])
                return true;
        return false;
    }

private:
    std::array<int, 3> cellOf(const Vec3& p) const {
        std::array<int, 3> c{};
        for (int a = 0; a < 3; ++a)
            c[std::size_t(a)] = std::clamp(int((p[a] - lo_[a]) / cell_), 0, n_[a] - 1);
        return c;
    }
    std::size_t index(int x, int y, int z) const {
        return (std::size_t(z) * n_[1] + std::size_t(y)) * n_[0] + x;
    }
    const SphereSet& s_;
    Vec3 lo_, hi_;
    double cell_ = 1.0;
    int n_[3] = {1, 1, 1};
    std::vector<std::vector<int>> cells_;
};

/// A closed mesh's inside, answered for most points by a lookup: the mesh's box in cells, a cell that no part
/// of the surface comes within its half-diagonal of lies wholly inside or wholly outside, and face-adjacent
/// such cells are on the same side (their union holds no surface), so one winding number decides each
/// connected group of them. Only points in the cells the surface passes through are asked of the mesh: on the
/// femur about a tenth of them.
class InsideCells {
public:
    InsideCells(const MeshQuery& q, const Vec3& lo, const Vec3& hi) : q_(q), lo_(lo) {
        const double longest = (hi - lo).maxCoeff();
        cell_ = longest / 48.0;
        for (int a = 0; a < 3; ++a) n_[a] = std::max(1, int(std::ceil((hi[a] - lo[a]) / cell_)));
        const std::size_t total = std::size_t(n_[0]) * n_[1] * n_[2];
        state_.assign(total, kUnknown);
        const double half = 0.5 * std::sqrt(3.0) * cell_;
#pragma omp parallel for schedule(dynamic, 16)
        for (long long c = 0; c < (long long)total; ++c)
            state_[std::size_t(c)] = q_.fartherThan(centre(std::size_t(c)), half) ? kUnknown : kSurface;
        std::vector<std::size_t> stack;
        for (std::size_t c = 0; c < total; ++c) {
            if (state_[c] != kUnknown) continue;
            const std::uint8_t side = q_.inside(centre(c)) ? kInside : kOutside;
            state_[c] = side;
            stack.assign(1, c);
            while (!stack.empty()) {
                const std::size_t k = stack.back();
                stack.pop_back();
                const int x = int(k % std::size_t(n_[0])),
                          y = int(k / std::size_t(n_[0]) % std::size_t(n_[1])),
                          z = int(k / (std::size_t(n_[0]) * n_[1]));
                const int nb[6][3] = {{x - 1, y, z}, {x + 1, y, z}, {x, y - 1, z},
                                      {x, y + 1, z}, {x, y, z - 1}, {x, y, z + 1}};
                for (const auto& b : nb) {
                    if (b[0] < 0 || b[1] < 0 || b[2] < 0 || b[0] >= n_[0] || b[1] >= n_[1] || b[2] >= n_[2])
                        continue;
                    const std::size_t j = index(b[0], b[1], b[2]);
                    if (state_[j] != kUnknown) continue;
                    state_[j] = side;
                    stack.push_back(j);
                }
            }
        }
    }
    bool inside(const Vec3& p) const {
        int c[3];
        for (int a = 0; a < 3; ++a) {
            c[a] = int(std::floor((p[a] - lo_[a]) / cell_));
            if (c[a] < 0 || c[a] >= n_[a]) return false; // outside the mesh's box
        }
        const std::uint8_t s = state_[index(c[0], c[1], c[2])];
        return s == kSurface ? q_.inside(p) : s == kInside;
    }

private:
    static constexpr std::uint8_t kUnknown = 0, kSurface = 1, kInside = 2, kOutside = 3;
    std::size_t index(int x, int y, int z) const {
        return (std::size_t(z) * std::size_t(n_[1]) + std::size_t(y)) * std::size_t(n_[0]) + std::size_t(x);
    }
    Vec3 centre(std::size_t k) const {
        const std::size_t x = k % std::size_t(n_[0]), y = k / std::size_t(n_[0]) % std::size_t(n_[1]),
                          z = k / (std::size_t(n_[0]) * n_[1]);
        return lo_ + cell_ * Vec3(double(x) + 0.5, double(y) + 0.5, double(z) + 0.5);
    }
    const MeshQuery& q_;
    Vec3 lo_;
    double cell_ = 1.0;
    int n_[3] = {1, 1, 1};
    std::vector<std::uint8_t> state_;
};

ExactScore monteCarlo(const Vec3& targetLo, const Vec3& targetHi,
                      const std::function<bool(const Vec3&)>& target, const SphereSet& spheres,
                      std::size_t samples, std::uint64_t seed, std::size_t triangles, double maxWork) {
    if (samples < 1000 || samples > 1000000000ull)
        throw std::invalid_argument("scoreSpheresExact: samples must be in [1000, 1e9], got " +
                                    std::to_string(samples));
    const Work work = detail::exactScoreWork(samples, triangles, spheres.size());
    checkWork("scoreSpheresExact", work, maxWork, "ask for fewer points (the option samples)");
    Progress progress("scoreSpheresExact", work.seconds);
    Vec3 lo = targetLo, hi = targetHi;
    for (std::size_t i = 0; i < spheres.size(); ++i) {
        lo = lo.cwiseMin(spheres.centers[i] - Vec3::Constant(spheres.radii[i]));
        hi = hi.cwiseMax(spheres.centers[i] + Vec3::Constant(spheres.radii[i]));
    }
    const SphereBuckets buckets(spheres);
    const Vec3 size = hi - lo;
    long long onlyA = 0, onlyB = 0, both = 0;
    const long long n = static_cast<long long>(samples);
    // by chunks, for the progress line and a stop between them; point i is the same whatever the chunks
    constexpr long long kChunk = 1 << 20;
    for (long long from = 0; from < n; from += kChunk) {
        progress.update(double(from) / double(n), "points");
        const long long to = std::min(n, from + kChunk);
#pragma omp parallel for schedule(static, 4096) reduction(+ : onlyA, onlyB, both)
        for (long long i = from; i < to; ++i) {
            const std::uint64_t k = (seed * 0x100000001b3ull + std::uint64_t(i)) * 3;
            const Vec3 p = lo + Vec3(unit(k) * size.x(), unit(k + 1) * size.y(), unit(k + 2) * size.z());
            const bool a = target(p), b = buckets.inside(p);
            onlyA += a && !b;
            onlyB += b && !a;
            both += a && b;
        }
    }
    const double N = double(samples), box = size.prod();
    const double pA = double(onlyA + both) / N, pB = double(onlyB + both) / N, pX = double(onlyA + onlyB) / N,
                 pAB = double(both) / N;
    if (onlyA + both == 0) throw std::invalid_argument("scoreSpheresExact: no sample fell inside the grain");
    ExactScore e;
    e.samples = samples;
    e.seed = seed;
    // D = x / y with x = [a xor b], y = a + b (eq. 27 on the exact sets); its standard error by the delta
    // method: Var(x - D y) / (N E[y]^2), E[x - D y] = 0
    e.dice = pX / (pA + pB);
    e.diceError = std::sqrt((pX * (1 - e.dice) * (1 - e.dice) + 4 * pAB * e.dice * e.dice) / N) / (pA + pB);
    e.eta = pX / pA; // eq. 7: |A xor B| / |A|
    const double pOnlyA = double(onlyA) / N, pOnlyB = double(onlyB) / N;
    e.etaError = std::sqrt((pOnlyA * (1 - e.eta) * (1 - e.eta) + pOnlyB + pAB * e.eta * e.eta) / N) / pA;
    e.targetVolume = box * pA;
    e.targetVolumeError = box * std::sqrt(pA * (1 - pA) / N);
    e.sphereVolume = box * pB;
    e.sphereVolumeError = box * std::sqrt(pB * (1 - pB) / N);
    return e;
}

} // namespace

ExactScore scoreSpheresExact(const TriangleMesh& target, const SphereSet& spheres, std::size_t samples,
                             std::uint64_t seed, const std::vector<Plane>& planes, double maxWork) {
    validateMesh(target, "scoreSpheresExact");
    validateSpheres(spheres, "scoreSpheresExact");
    const MeshQuery q(target);
    const MeshInfo info = analyzeMesh(target);
    // an open mesh's winding number varies smoothly across its holes, away from any surface: asked point by
    // point
    std::unique_ptr<InsideCells> cells;
    if (info.closed) cells = std::make_unique<InsideCells>(q, info.lower, info.upper);
    const std::vector<PlaneDistance> distances(planes.begin(), planes.end());
    return monteCarlo(
        info.lower, info.upper,
        [&](const Vec3& p) {
            for (const PlaneDistance& distance : distances)
                if (distance(p) < 0) return false;
            return cells ? cells->inside(p) : q.inside(p);
        },
        spheres, samples, seed, target.triangles.size(), maxWork);
}

ExactScore scoreSpheresExact(const VoxelGrid& target, const SphereSet& spheres, std::size_t samples,
                             std::uint64_t seed, const std::vector<Plane>& planes, double maxWork) {
    validateSpheres(spheres, "scoreSpheresExact");
    const VoxelGrid part = planes.empty() ? VoxelGrid() : cutVoxelsByPlanes(target, planes);
    const VoxelGrid& v = planes.empty() ? target : part;
    const GridSpec& g = v.spec;
    const Vec3 lo = g.toWorld(Vec3::Constant(-0.5)),
               hi = g.toWorld(Vec3(g.dims[0], g.dims[1], g.dims[2]) - Vec3::Constant(0.5));
    return monteCarlo(
        lo, hi,
        [&](const Vec3& p) {
            const auto c = g.voxelOf(p);
            return g.contains(c[0], c[1], c[2]) && v(c[0], c[1], c[2]) != 0;
        },
        spheres, samples, seed, 0, maxWork);
}

} // namespace mss
