#include "mss/generate.hpp"
#include "mss/ball_rows.hpp"
#include "mss/edt.hpp"
#include "mss/maxima.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>
#include <queue>
#include <set>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace mss {

namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

using detail::ceilInt;
using detail::floorInt;

/// Largest radius allowed for a sphere centred at a point (clipping, constraint planes); negative where no
/// centre may be; +inf without constraint. BoundVox: voxel coordinates and units of the generation grid.
using BoundVox = std::function<double(const Vec3&)>;

/// A sphere in continuous voxel coordinates of the generation grid.
struct Ball {
    Vec3 c;
    double r;
};

/// Coverage of the target by a union of balls, with the exact change of the mismatch |S Δ S~| (eq. 2 on
/// voxels) that adding balls would make. Per voxel: the number of balls covering it; per x-row the prefix sum
/// of g = (S ? 1 : -1) over the uncovered voxels. The gain of a ball is then a sum over its (y, z) columns of
/// O(1) interval sums: O(r^2) for radius r in voxels. Adding or removing a ball rebuilds the prefix of a row
/// from its first voxel whose coverage flips.
class Coverage {
public:
    explicit Coverage(const VoxelGrid& target)
        : S_(target), cover_(target.size(), 0), prefix_(target.size()), nx_(target.nx()) {
        solid_ = countSolid(target);
        mismatch_ = static_cast<long long>(solid_);
        const long long rows = static_cast<long long>(target.size() / std::size_t(nx_));
#pragma omp parallel for schedule(static)
        for (long long row = 0; row < rows; ++row) rebuildRow(std::size_t(row) * std::size_t(nx_), 0);
    }

    /// Decrease of the mismatch if @p b were added (negative if it would add more outside than inside).
    long long gain(const Ball& b) const {
        long long total = 0;
        forColumns(b, [&](std::size_t row, int i0, int i1) { total += sum(row, i0, i1); });
        return total;
    }
    /// Decrease of the mismatch if all @p balls were added together (they may overlap each other).
    /// @p mirrored: the balls are mirror images of the first under planes that map the target and the
    /// coverage onto themselves, so apart from each other they all gain the same.
    long long gain(const std::vector<Ball>& balls, bool mirrored = false) const {
        bool independent = true;
        for (std::size_t p = 0; p < balls.size() && independent; ++p)
            for (std::size_t q = p + 1; q < balls.size(); ++q)
                if ((balls[p].c - balls[q].c).norm() <= balls[p].r + balls[q].r + 1.0) {
                    independent = false;
                    break;
                }
        if (independent && mirrored) return gain(balls[0]) * static_cast<long long>(balls.size());
        if (independent) {
            long long total = 0;
            for (const Ball& b : balls) total += gain(b);
            return total;
        }
        const auto& d = S_.spec.dims;
        // Images that differ only in x (mirror plane normal to x) share their rows: one root per row.
        bool sameRows = true;
        for (const Ball& b : balls)
            sameRows =
                sameRows && b.r == balls[0].r && b.c.y() == balls[0].c.y() && b.c.z() == balls[0].c.z();
        if (sameRows && balls.size() == 2) {
            const double xa = std::min(balls[0].c.x(), balls[1].c.x()),
                         xb = std::max(balls[0].c.x(), balls[1].c.x());
            const Ball& b = balls[0];
            const double r2 = b.r * b.r;
            long long total = 0;
            const int k0 = std::max(0, ceilInt(b.c.z() - b.r)),
                      k1 = std::min(halfEnd(mirrored, 2), floorInt(b.c.z() + b.r));
            for (int k = k0; k <= k1; ++k) {
                const double dz = k - b.c.z();
                const double rz2 = r2 - dz * dz;
                if (rz2 < 0) continue;
                const double ry = std::sqrt(rz2);
                const int j0 = std::max(0, ceilInt(b.c.y() - ry)),
                          j1 = std::min(halfEnd(mirrored, 1), floorInt(b.c.y() + ry));
                for (int j = j0; j <= j1; ++j) {
                    const long long w = weight(mirrored, j, k);
                    const double dy = j - b.c.y();
                    const double rx2 = rz2 - dy * dy;
                    if (rx2 < 0) continue;
                    const double rx = std::sqrt(rx2);
                    const int a0 = std::max(0, ceilInt(xa - rx)), a1 = std::min(d[0] - 1, floorInt(xa + rx));
                    const int b0 = std::max(0, ceilInt(xb - rx)), b1 = std::min(d[0] - 1, floorInt(xb + rx));
                    const std::size_t row = S_.spec.index(0, j, k);
                    const bool hasA = a0 <= a1, hasB = b0 <= b1;
                    if (hasA && hasB && b0 <= a1 + 1)
                        total += w * sum(row, a0, std::max(a1, b1));
                    else
                        total += w * ((hasA ? sum(row, a0, a1) : 0) + (hasB ? sum(row, b0, b1) : 0));
                }
            }
            return total;
        }
        // Overlapping images: per row of the union's bounding box, merge the balls' intervals (at most 8).
        Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
        for (const Ball& b : balls) {
            lo = lo.cwiseMin(b.c - Vec3::Constant(b.r));
            hi = hi.cwiseMax(b.c + Vec3::Constant(b.r));
        }
        const int k0 = std::max(0, ceilInt((lo.z()))),
                  k1 = std::min(halfEnd(mirrored, 2), floorInt((hi.z())));
        const int j0 = std::max(0, ceilInt((lo.y()))),
                  j1 = std::min(halfEnd(mirrored, 1), floorInt((hi.y())));
        long long total = 0;
        std::array<std::pair<int, int>, 8> iv;
        for (int k = k0; k <= k1; ++k)
            for (int j = j0; j <= j1; ++j) {
                int n = 0;
                for (const Ball& b : balls) {
                    const double dz = k - b.c.z(), dy = j - b.c.y();
                    const double rx2 = b.r * b.r - dz * dz - dy * dy;
                    if (rx2 < 0) continue;
                    const double rx = std::sqrt(rx2);
                    const int i0 = std::max(0, ceilInt((b.c.x() - rx))),
                              i1 = std::min(d[0] - 1, floorInt((b.c.x() + rx)));
                    if (i0 > i1) continue;
                    int p = n++;
                    for (; p > 0 && iv[p - 1].first > i0; --p) iv[p] = iv[p - 1];
                    iv[p] = {i0, i1};
                }
                if (n == 0) continue;
                const std::size_t row = S_.spec.index(0, j, k);
                long long rowTotal = 0;
                int a = iv[0].first, e = iv[0].second;
                for (int p = 1; p < n; ++p) {
                    if (iv[p].first <= e + 1) {
                        e = std::max(e, iv[p].second);
                    } else {
                        rowTotal += sum(row, a, e);
                        a = iv[p].first;
                        e = iv[p].second;
                    }
                }
                rowTotal += sum(row, a, e);
                total += weight(mirrored, j, k) * rowTotal;
            }
        return total;
    }
    /// Mirror planes (normal to x, y, z, through the grid centre) that map the target onto itself exactly.
    void setMirrorPlanes(const std::array<bool, 3>& planes) {
        mirror_ = planes;
    }
    void add(const Ball& b) {
        change(b, +1);
    }
    void remove(const Ball& b) {
        change(b, -1);
    }

    long long mismatch() const {
        return mismatch_;
    }
    std::size_t solid() const {
        return solid_;
    }
    std::size_t covered() const {
        return covered_;
    }
    double eta() const {
        return solid_ ? double(mismatch_) / double(solid_) : 0.0;
    }
    double dice() const {
        return (solid_ + covered_) ? double(mismatch_) / double(solid_ + covered_) : 0.0;
    }

private:
    // A mirrored union of images under a symmetric coverage gains the same in rows (j, k) and their mirror
    // images under the y and z planes: only the lower half is visited, rows off the plane counted twice.
    int halfEnd(bool mirrored, int axis) const {
        const int n = S_.spec.dims[axis];
        return mirrored && mirror_[axis] ? (n - 1) / 2 : n - 1;
    }
    long long weight(bool mirrored, int j, int k) const {
        long long w = 1;
        if (mirrored && mirror_[1] && 2 * j != S_.spec.dims[1] - 1) w *= 2;
        if (mirrored && mirror_[2] && 2 * k != S_.spec.dims[2] - 1) w *= 2;
        return w;
    }
    long long sum(std::size_t row, int i0, int i1) const {
        return prefix_[row + i1] - (i0 > 0 ? prefix_[row + i0 - 1] : 0);
    }
    void rebuildRow(std::size_t row, int from) {
        std::int32_t acc = from > 0 ? prefix_[row + from - 1] : 0;
        for (int i = from; i < nx_; ++i) {
            if (cover_[row + i] == 0) acc += S_.data[row + i] ? 1 : -1;
            prefix_[row + i] = acc;
        }
    }
    template <class F> void forColumns(const Ball& b, F&& f) const {
        detail::forBallRows(b.c, b.r, S_.spec.dims, 0, S_.spec.dims[2] - 1,
                            [&](int j, int k, int i0, int i1) { f(S_.spec.index(0, j, k), i0, i1); });
    }
    void change(const Ball& b, int delta) {
        forColumns(b, [&](std::size_t row, int i0, int i1) {
            std::uint16_t* c = cover_.data() + row;
            const std::uint8_t* s = S_.data.data() + row;
            const std::uint16_t flipAt = delta > 0 ? 0 : 1; // coverage before a flip
            int flips = 0, inside = 0;
            for (int i = i0; i <= i1; ++i) { // vectorised
                const bool flip = c[i] == flipAt;
                flips += flip;
                inside += flip & (s[i] != 0);
            }
            for (int i = i0; i <= i1; ++i) c[i] = static_cast<std::uint16_t>(c[i] + delta);
            if (flips == 0) return; // no voxel changes between covered and uncovered: prefix unchanged
            int first = i0;
            while (c[first] != flipAt + delta) ++first;
            // from the first flip: prefix recomputed to the end of the ball's interval, then shifted
            std::int32_t* p = prefix_.data() + row;
            std::int32_t acc = first > 0 ? p[first - 1] : 0;
            const std::int32_t old = p[i1];
            for (int i = first; i <= i1; ++i) {
                acc += c[i] == 0 ? (s[i] ? 1 : -1) : 0;
                p[i] = acc;
            }
            const std::int32_t shift = acc - old;
            for (int i = i1 + 1; i < nx_; ++i) p[i] += shift;
            // each flipped voxel inside S changes the mismatch by -delta, outside by +delta
            mismatch_ -= delta * (2LL * inside - flips);
            covered_ += static_cast<std::size_t>(static_cast<long long>(delta) * flips);
        });
    }

    const VoxelGrid& S_;
    std::vector<std::uint16_t> cover_;
    std::vector<std::int32_t> prefix_;
    std::array<bool, 3> mirror_{false, false, false};
    int nx_;
    std::size_t solid_ = 0, covered_ = 0;
    long long mismatch_ = 0;
};

/// Mirror planes through the grid centre, normal to x, y or z, under which the volume is invariant up to a
/// tolerance (a voxelised mesh of a symmetric grain can differ in a few voxels where the surface passes
/// exactly through voxel centres). @p exact: whether the volume is invariant exactly under all planes found.
std::array<bool, 3> mirrorAxes(const VoxelGrid& S, std::size_t solid, bool& exact) {
    exact = true;
    std::array<bool, 3> sym{false, false, false};
    const int nx = S.nx(), ny = S.ny(), nz = S.nz();
    const std::size_t limit = std::size_t(1e-3 * double(solid));
    auto rowDiff = [&](const std::uint8_t* a, const std::uint8_t* b, bool reversed) {
        std::size_t n = 0;
        if (!reversed && std::memcmp(a, b, std::size_t(nx)) == 0) return n;
        for (int i = 0; i < nx; ++i) n += a[i] != b[reversed ? nx - 1 - i : i];
        return n;
    };
    for (int a = 0; a < 3; ++a) {
        std::size_t diff = 0;
        for (int k = 0; k < nz && diff <= limit; ++k)
            for (int j = 0; j < ny; ++j) {
                const int jm = a == 1 ? ny - 1 - j : j, km = a == 2 ? nz - 1 - k : k;
                diff += rowDiff(&S(0, j, k), &S(0, jm, km), a == 0);
            }
        sym[a] = diff <= limit;
        exact = exact && (!sym[a] || diff == 0);
    }
    return sym;
}

/// Candidate or chosen sphere with its mirror images: the orbit under the detected mirror planes.
struct Orbit {
    Vec3 c;
    double r;
    std::array<bool, 3> onPlane{false, false, false};
    bool broken = false;  ///< placed alone: its images did not fit the sphere budget
    bool bounded = false; ///< radius already reduced to what the constraints (clipping, planes) allow
};

class Symmetry {
public:
    Symmetry(const GridSpec& g, std::array<bool, 3> axes) : axes_(axes) {
        for (int a = 0; a < 3; ++a) mid_[a] = 0.5 * (g.dims[a] - 1);
    }
    int planes() const { return int(axes_[0]) + int(axes_[1]) + int(axes_[2]); }
    const std::array<bool, 3>& axes() const { return axes_; }
    /// Snaps coordinates within half a voxel of a plane onto it (on a grid of even size the voxels next to
    /// the plane are half a voxel off it); those stay on it.
    Orbit make(const Vec3& c, double r) const {
        Orbit o{c, r};
        for (int a = 0; a < 3; ++a) {
            if (axes_[a] && std::abs(c[a] - mid_[a]) <= 0.5 + 1e-9) {
                o.c[a] = mid_[a];
                o.onPlane[a] = true;
            }
        }
        return o;
    }
    std::vector<Ball> images(const Orbit& o) const {
        std::vector<Ball> out{{o.c, o.r}};
        if (o.broken) return out;
        for (int a = 0; a < 3; ++a) {
            if (!axes_[a] || o.onPlane[a]) continue;
            const std::size_t n = out.size();
            for (std::size_t i = 0; i < n; ++i) {
                Ball b = out[i];
                b.c[a] = 2.0 * mid_[a] - b.c[a];
                out.push_back(b);
            }
        }
        return out;
    }
    /// The representative with every symmetric coordinate in the lower half, so that an orbit has one key.
    Vec3 canonical(Vec3 c) const {
        for (int a = 0; a < 3; ++a)
            if (axes_[a] && c[a] > mid_[a]) c[a] = 2.0 * mid_[a] - c[a];
        return c;
    }

private:
    std::array<bool, 3> axes_;
    Vec3 mid_;
};

struct Targets {
    int budget; // max spheres, or INT_MAX
    double eta, dice;
    bool met(const Coverage& c) const {
        return (eta > 0 && c.eta() <= eta) || (dice > 0 && c.dice() <= dice);
    }
    bool hasQuality() const { return eta > 0 || dice > 0; }
};

/// MSS paper, sections 3.3-3.4 as published.
std::vector<Ball> runPaper(const VoxelGrid& S, const ScalarGrid& E, const GenerateOptions& opt, Metrics& m,
                           const BoundVox& bound) {
    const double h = S.spec.h;
    const double rMinVox = opt.rMin / h;
    const std::size_t budget = opt.nSpheres > 0 ? std::size_t(opt.nSpheres) : SIZE_MAX;
    std::vector<Ball> balls;
    auto accept = [&](std::vector<Maximum>& cands) {
        // largest first (a budget takes the largest values), ties in voxel order: deterministic
        std::stable_sort(cands.begin(), cands.end(),
                         [](const Maximum& a, const Maximum& b) { return a.value > b.value; });
        std::size_t added = 0;
        for (const Maximum& c : cands) {
            if (balls.size() >= budget) break;
            if (c.voxelValue < rMinVox)
                continue; // section 3.5: minimal radius (voxelValue holds the radius here)
            bool near = false;
            for (const Ball& b : balls)
                near = near || (b.c - c.position).norm() < opt.deltaMin; // δmin, section 3.4
            if (near) continue;
            double r = c.voxelValue;
            if (bound) r = std::min(r, bound(c.position)); // clipped (section 3.5)
            if (r < std::max(rMinVox, 1e-3)) continue;
            balls.push_back({c.position, r});
            ++added;
        }
        return added;
    };
    // Initial representation S~0: spheres at the sub-voxel maxima of E, radius eq. 24.
    std::vector<Maximum> cands;
    for (const auto& v : localMaxima(E, 0.0f)) {
        Maximum mx = refineMaximum(E, v);
        mx.voxelValue = mx.value; // radius
        cands.push_back(mx);
    }
    accept(cands);
    const Targets t{opt.nSpheres > 0 ? opt.nSpheres : INT32_MAX, opt.eta, opt.dice};
    ScalarGrid Et, Estar(S.spec, 0.0f);
    for (m.iterations = 0; m.iterations < opt.maxIterations; ++m.iterations) {
        if (balls.size() >= budget) break;
        SphereSet world;
        for (const Ball& b : balls) world.add(S.spec.toWorld(b.c), b.r * h);
        const VoxelGrid St = voxelizeSpheres(world, S.spec); // step i
        const Mismatch mm = mismatch(S, St);
        if ((t.eta > 0 && mm.eta <= t.eta) || (t.dice > 0 && mm.dice <= t.dice)) break;
        distanceTransform(St, Et);                 // step ii
        for (std::size_t q = 0; q < S.size(); ++q) // step iii, eq. 25, on the target's voxels
            Estar.data[q] = S.data[q] ? 2.0f * E.data[q] - Et.data[q] : 0.0f;
        cands.clear();
        for (const auto& v : localMaxima(Estar, 0.0f)) {
            Maximum mx = refineMaximum(Estar, v);
            mx.voxelValue = interpolateAxes(E, v, mx.position); // step iv: radius from E
            cands.push_back(mx);
        }
        if (accept(cands) == 0) break;
    }
    return balls;
}

/// Optimised selection: see the comment at generate() below.
std::vector<Ball> runOptimized(const VoxelGrid& S, const ScalarGrid& E, const GenerateOptions& opt,
                               const BoundVox& bound, Metrics& m, double& secondsRefine,
                               const std::vector<Orbit>& start = {}, std::vector<Orbit>* orbitsOut = nullptr,
                               long long* mismatchOut = nullptr) {
    const double h = S.spec.h;
    const double rMinVox = std::max(0.5, opt.rMin / h);
    const auto tStart = Clock::now();
    auto debug = [&](const char* what) {
        if (std::getenv("MSS_DEBUG")) std::fprintf(stderr, "%8.4f %s\n", secondsSince(tStart), what);
    };
    Coverage cov(S);
    debug("coverage");
    bool exactSymmetry = false;
    std::array<bool, 3> axes{false, false, false};
    if (opt.keepSymmetry) axes = mirrorAxes(S, cov.solid(), exactSymmetry);
    // a constraint plane is mirrored onto itself only if it is parallel to the mirror's normal; any other
    // breaks that symmetry (an oblique cut through a symmetric grain would leave no orbit on its side)
    for (const Plane& p : opt.planes)
        for (int a = 0; a < 3; ++a)
            if (std::abs(p.normal[a]) > 1e-12 * p.normal.norm()) axes[a] = false;
    const Symmetry sym(S.spec, axes);
    m.symmetryPlanes = sym.planes();
    if (exactSymmetry) cov.setMirrorPlanes(sym.axes());
    debug("symmetry");
    const Targets t{opt.nSpheres > 0 ? opt.nSpheres : INT32_MAX, opt.eta, opt.dice};

    // Candidates: MSS's sub-voxel maxima of E (eq. 23-24) and the medial ridge of E, where no face neighbour
    // is more than half a voxel higher (on a slope of the distance field one neighbour is ~1 higher).
    std::vector<Orbit> cands;
    std::set<std::array<long long, 3>> seen;
    // the largest radius the constraints allow for all images of an orbit
    auto orbitBound = [&](const Orbit& o) {
        double b = std::numeric_limits<double>::infinity();
        if (bound)
            for (const Ball& x : sym.images(o)) b = std::min(b, bound(x.c));
        return b;
    };
    auto addCandidate = [&](const Vec3& c, double r) {
        if (r < rMinVox) return;
        Orbit o = sym.make(c, r); // constraints applied when the greedy first looks at it (bounded)
        const Vec3 key = sym.canonical(o.c) * 8.0;
        if (!seen.insert({std::llround(key.x()), std::llround(key.y()), std::llround(key.z())}).second)
            return;
        cands.push_back(o);
    };
    // A ball of radius E reaches the centre of the nearest background voxel; the surface lies about half a
    // voxel nearer, so candidates start at E - 0.5 + kRadiusSlack and the refinement tunes each radius.
    constexpr double kRadiusSlack = 0.5;
    for (const auto& v : localMaxima(E, 0.0f)) {
        const Maximum mx = refineMaximum(E, v);
        addCandidate(mx.position, mx.value - 0.5 + kRadiusSlack);
    }
    debug("maxima");
    const auto& d = S.spec.dims;
    std::vector<std::vector<std::array<int, 3>>> ridgeSlices(std::size_t(std::max(d[2], 1)));
#pragma omp parallel for schedule(dynamic, 4)
    for (int k = 1; k < d[2] - 1; ++k)
        for (int j = 1; j < d[1] - 1; ++j)
            for (int i = 1; i < d[0] - 1; ++i) {
                const float e = E(i, j, k);
                if (e < 1.0f) continue;
                const float up = std::max({E(i - 1, j, k), E(i + 1, j, k), E(i, j - 1, k), E(i, j + 1, k),
                                           E(i, j, k - 1), E(i, j, k + 1)}) -
                                 e;
                if (up < 0.5f) ridgeSlices[std::size_t(k)].push_back({i, j, k});
            }
    std::vector<std::array<int, 3>> ridge; // in voxel order, whatever the threads
    for (const auto& slice : ridgeSlices) ridge.insert(ridge.end(), slice.begin(), slice.end());
    constexpr std::size_t kMaxRidge = 10000;
    const std::size_t stride = std::max<std::size_t>(1, (ridge.size() + kMaxRidge - 1) / kMaxRidge);
    for (std::size_t q = 0; q < ridge.size(); q += stride) {
        const auto& v = ridge[q];
        addCandidate(Vec3(v[0], v[1], v[2]), E(v[0], v[1], v[2]) - 0.5 + kRadiusSlack);
    }

    debug("candidates");
    // Lazy greedy: a max-heap of (mismatch removed per sphere, candidate), re-evaluated when stale.
    std::vector<Orbit> chosen;
    // Gain of an orbit's images added together. While the target is exactly mirror symmetric and every placed
    // orbit is whole, the coverage is symmetric too: images apart from each other gain the same, so one is
    // counted (the ellipsoid's orbits have up to 8 images).
    auto orbitGain = [&](const Orbit& o) {
        const std::vector<Ball> imgs = sym.images(o);
        const bool mirrored =
            exactSymmetry && imgs.size() > 1 &&
            std::none_of(chosen.begin(), chosen.end(), [](const Orbit& c) { return c.broken; });
        return cov.gain(imgs, mirrored);
    };
    std::vector<char> used(cands.size(), 0);
    std::size_t evaluations = 0;
    // Heap keys: first an upper bound (a ball fully inside), then the last evaluated gain per sphere, kept
    // between greedy rounds so that a later round starts from good estimates.
    std::vector<double> key(cands.size());
    for (std::size_t q = 0; q < cands.size(); ++q) key[q] = 4.18879 * std::pow(cands[q].r, 3) + 10.0;
    // With mirror planes, orbits are placed whole first; spheres alone only fill what whole orbits cannot.
    bool allowBreak = sym.planes() == 0;
    std::size_t placed = 0;
    for (Orbit o : start) { // a warm start: spheres found without the constraints, cut down to them
        o.r = std::min(o.r, orbitBound(o));
        o.bounded = true;
        if (o.r < rMinVox || sym.images(o).size() > std::size_t(t.budget) - placed) continue;
        for (const Ball& b : sym.images(o)) cov.add(b);
        placed += sym.images(o).size();
        chosen.push_back(o);
    }
    auto greedy = [&]() {
        using Entry = std::pair<double, long long>; // (key, -index): ties go to the lower index
        std::priority_queue<Entry> heap;
        std::vector<std::size_t> stamp(cands.size(), SIZE_MAX);
        for (std::size_t q = 0; q < cands.size(); ++q)
            if (!used[q]) heap.push({key[q], -static_cast<long long>(q)});
        // Stale entries are re-evaluated in batches of kBatch, in parallel; the batch size does not depend on
        // the thread count, so neither does the result.
        constexpr int kBatch = 8;
        std::vector<long long> batch;
        std::vector<double> gains;
        while (!heap.empty() && placed < std::size_t(t.budget) && !t.met(cov)) {
            const auto [topKey, negIdx] = heap.top();
            const std::size_t q = static_cast<std::size_t>(-negIdx);
            if (sym.images(cands[q]).size() > std::size_t(t.budget) - placed && !cands[q].broken) {
                if (!allowBreak) { // strict: an orbit that does not fit is not placed
                    heap.pop();
                    continue;
                }
                cands[q].broken = true; // keep orbits whole while the budget allows, then place spheres alone
                stamp[q] = SIZE_MAX;
            }
            if (stamp[q] == placed) { // fresh: the best there is
                heap.pop();
                if (topKey <= 0.0) break; // nothing left that lowers the mismatch
                for (const Ball& b : sym.images(cands[q])) cov.add(b);
                placed += sym.images(cands[q]).size();
                chosen.push_back(cands[q]);
                used[q] = 1;
                continue;
            }
            batch.clear();
            while (!heap.empty() && int(batch.size()) < kBatch) {
                const std::size_t p = static_cast<std::size_t>(-heap.top().second);
                if (stamp[p] == placed) break;
                if (!cands[p].bounded) { // the constraints, looked up only for candidates the greedy reaches
                    cands[p].bounded = true;
                    cands[p].r = std::min(cands[p].r, orbitBound(cands[p]));
                    if (cands[p].r < rMinVox) {
                        heap.pop();
                        used[p] = 1;
                        continue;
                    }
                }
                if (sym.images(cands[p]).size() > std::size_t(t.budget) - placed) {
                    if (!allowBreak) break;
                    cands[p].broken = true;
                }
                batch.push_back(heap.top().second);
                heap.pop();
            }
            gains.assign(batch.size(), 0.0);
#pragma omp parallel for schedule(dynamic, 1)
            for (int e = 0; e < int(batch.size()); ++e) {
                const Orbit& o = cands[std::size_t(-batch[e])];
                gains[e] = double(orbitGain(o)) / double(sym.images(o).size());
            }
            evaluations += batch.size();
            for (std::size_t e = 0; e < batch.size(); ++e) {
                stamp[std::size_t(-batch[e])] = placed;
                key[std::size_t(-batch[e])] = gains[e];
                heap.push({gains[e], batch[e]});
            }
        }
    };

    // Local refinement: move each orbit's centre and radius while that lowers the mismatch (coordinate
    // descent on the exact voxel objective, steps from one voxel down to 1/8). An orbit is revisited in a
    // later sweep only if it or an orbit overlapping it moved in the last one.
    auto overlaps = [&](const Orbit& a, const Orbit& b) {
        for (const Ball& x : sym.images(a))
            for (const Ball& y : sym.images(b))
                if ((x.c - y.c).norm() <= x.r + y.r + 1.0) return true;
        return false;
    };
    static const bool kSkip = !std::getenv("MSS_NOSKIP");
    auto trilinear = [&](const Vec3& p) {
        const int i = std::clamp(floorInt(p.x()), 0, d[0] - 2), j = std::clamp(floorInt(p.y()), 0, d[1] - 2),
                  k = std::clamp(floorInt(p.z()), 0, d[2] - 2);
        const double fx = p.x() - i, fy = p.y() - j, fz = p.z() - k;
        double v = 0.0;
        for (int c = 0; c < 8; ++c) {
            const int di = c & 1, dj = (c >> 1) & 1, dk = (c >> 2) & 1;
            v += (di ? fx : 1 - fx) * (dj ? fy : 1 - fy) * (dk ? fz : 1 - fz) * E(i + di, j + dj, k + dk);
        }
        return v;
    };
    // With @p touched, only orbits overlapping one of them start out as candidates for moving.
    auto refine = [&](const std::vector<Orbit>* touched = nullptr, int sweeps = 3) {
        std::vector<char> moved(chosen.size(), 1);
        if (touched)
            for (std::size_t q = 0; q < chosen.size(); ++q)
                moved[q] = std::any_of(touched->begin(), touched->end(),
                                       [&](const Orbit& t) { return overlaps(chosen[q], t); });
        for (int sweep = 0; sweep < sweeps; ++sweep) {
            bool improved = false;
            std::vector<char> movedNow(chosen.size(), 0);
            for (std::size_t oi = 0; oi < chosen.size(); ++oi) {
                Orbit& o = chosen[oi];
                if (sweep > 0 && kSkip) {
                    bool stale = true;
                    for (std::size_t oj = 0; oj < chosen.size() && stale; ++oj)
                        if (moved[oj] && (oj == oi || overlaps(o, chosen[oj]))) stale = false;
                    if (stale) continue;
                }
                for (const Ball& b : sym.images(o)) cov.remove(b);
                long long best = orbitGain(o);
                const long long start = best;
                for (double step : {0.5, 0.25}) {
                    int lastAxis = -1; // the move just taken: its reverse leads back, no need to look
                    double lastSign = 0.0;
                    for (int rep = 0; rep < 6; ++rep) {
                        // the moves: centre +- step along each free axis, radius +- step; evaluated in
                        // parallel
                        std::vector<Orbit> trials;
                        std::vector<std::pair<int, double>> moves;
                        for (int a = 0; a < 4; ++a) {
                            if (a < 3 && o.onPlane[a]) continue;
                            for (double sgn : {-1.0, 1.0}) {
                                if (a == lastAxis && sgn == -lastSign) continue;
                                Orbit trial = o;
                                if (a < 3)
                                    trial.c[a] += sgn * step;
                                else
                                    trial.r += sgn * step;
                                if (a < 3 && (trial.c[a] < 1.0 || trial.c[a] > d[a] - 2.0)) continue;
                                const double limit = orbitBound(trial);
                                if (a < 3 && limit > trial.r && limit < 1e300) {
                                    Orbit touching = trial; // under a constraint: grow to touch as well
                                    touching.r = limit;
                                    trials.push_back(touching);
                                    moves.emplace_back(a, sgn);
                                }
                                if (a < 3) {
                                    // slide: keep the clearance from the surface (radius changed by the
                                    // change of E, trilinear). Moving a ball along a surface needs its radius
                                    // and centre to change together; one coordinate at a time stalls there
                                    // (ellipsoid, 40 spheres: D 0.0027 without this move, 0.00098 with it).
                                    Orbit slide = trial;
                                    slide.r = std::min(limit, o.r + trilinear(slide.c) - trilinear(o.c));
                                    if (std::abs(slide.r - trial.r) > 1e-3 && slide.r >= rMinVox &&
                                        std::abs(slide.r - limit) > 1e-9) {
                                        trials.push_back(slide);
                                        moves.emplace_back(a, sgn);
                                    }
                                }
                                trial.r = std::min(trial.r, limit);
                                if (trial.r < rMinVox) continue;
                                trials.push_back(trial);
                                moves.emplace_back(a, sgn);
                            }
                        }
                        std::vector<long long> g(trials.size());
#pragma omp parallel for schedule(dynamic, 1)
                        for (int e = 0; e < int(trials.size()); ++e) g[e] = orbitGain(trials[e]);
                        int pick = -1;
                        for (int e = 0; e < int(trials.size()); ++e)
                            if (g[e] > best) {
                                best = g[e];
                                pick = e;
                            }
                        if (pick < 0) break;
                        o = trials[pick];
                        lastAxis = moves[pick].first;
                        lastSign = moves[pick].second;
                    }
                }
                for (const Ball& b : sym.images(o)) cov.add(b);
                movedNow[oi] = best > start;
                improved = improved || best > start;
            }
            moved.swap(movedNow);
            if (!improved) break;
        }
    };

    // Problem (ii): drop orbits whose removal still meets the quality target, smallest contribution first.
    auto prune = [&]() {
        if (!t.hasQuality() || !t.met(cov)) return false;
        bool any = false;
        for (std::size_t q = chosen.size(); q-- > 0;) {
            const auto imgs = sym.images(chosen[q]);
            for (const Ball& b : imgs) cov.remove(b);
            if (t.met(cov)) {
                placed -= imgs.size();
                chosen.erase(chosen.begin() + static_cast<std::ptrdiff_t>(q));
                any = true;
            } else {
                for (const Ball& b : imgs) cov.add(b);
            }
        }
        return any;
    };

    for (m.iterations = 0; m.iterations < opt.maxIterations; ++m.iterations) {
        const std::size_t before = placed;
        const auto t0 = Clock::now();
        greedy();
        m.secondsSelect += secondsSince(t0);
        const auto t1 = Clock::now();
        refine();
        const bool pruned = prune();
        if (pruned) refine();
        secondsRefine += secondsSince(t1);
        if (placed >= std::size_t(t.budget) || t.met(cov)) { // done (a warm start may begin so)
            ++m.iterations;
            break;
        }
        if (placed == before && !pruned) break; // nothing new: converged
    }
    debug("main loop");
    // Symmetry repair: whole orbits can leave the budget short by one (say 10 = 1 sphere on all planes + 4
    // pairs + 1 free). Try trading a sphere that lies on all planes for a whole orbit; keep the trade when it
    // fills more of the budget with at most 5% more mismatch. Then fill what is left with spheres alone.
    for (int attempt = 0; attempt < 4 && sym.planes() > 0 && placed < std::size_t(t.budget) && !t.met(cov);
         ++attempt) {
        std::ptrdiff_t centre = -1;
        for (std::size_t q = 0; q < chosen.size(); ++q)
            if (sym.images(chosen[q]).size() == 1) centre = std::ptrdiff_t(q);
        if (centre < 0) break;
        const std::vector<Orbit> saved = chosen;
        const std::size_t savedPlaced = placed;
        const long long before = cov.mismatch();
        std::vector<Orbit> touched{chosen[std::size_t(centre)]};
        for (const Ball& b : sym.images(chosen[std::size_t(centre)])) cov.remove(b);
        placed -= 1;
        chosen.erase(chosen.begin() + centre);
        const std::size_t kept = chosen.size();
        debug("repair: removed");
        greedy();
        debug("repair: greedy");
        touched.insert(touched.end(), chosen.begin() + std::ptrdiff_t(kept), chosen.end());
        refine(&touched, 2);
        debug("repair: refine");
        if (placed > savedPlaced && double(cov.mismatch()) <= 1.05 * double(before)) continue;
        for (const Orbit& o : chosen)
            for (const Ball& b : sym.images(o)) cov.remove(b);
        chosen = saved;
        placed = savedPlaced;
        for (const Orbit& o : chosen)
            for (const Ball& b : sym.images(o)) cov.add(b);
        break;
    }
    if (!allowBreak && placed < std::size_t(t.budget) && !t.met(cov)) {
        allowBreak = true;
        const std::size_t before = placed, kept = chosen.size();
        greedy();
        const std::vector<Orbit> touched(chosen.begin() + std::ptrdiff_t(kept), chosen.end());
        if (placed > before) refine(&touched);
    }

    debug("repair");
    if (std::getenv("MSS_DEBUG"))
        std::fprintf(stderr, "candidates %zu ridge %zu evaluations %zu\n", cands.size(), ridge.size(),
                     evaluations);
    if (orbitsOut) *orbitsOut = chosen;
    if (mismatchOut) *mismatchOut = cov.mismatch();
    std::vector<Ball> out;
    for (const Orbit& o : chosen)
        for (const Ball& b : sym.images(o)) out.push_back(b);
    return out;
}

/// @p meshBound: the mesh's constraint in world units (clipping to the mesh, planes), or empty: then clipping
/// and planes apply to the voxel volume S.
Result generateOnGrid(const VoxelGrid& grain, const GenerateOptions& opt, Metrics m, Clock::time_point start,
                      std::function<double(const Vec3&)> meshBound = {}) {
    if (opt.threads > 0) {
#ifdef _OPENMP
        omp_set_num_threads(opt.threads);
#endif
    }
    if (countSolid(grain) == 0)
        throw std::invalid_argument("generate: the voxelised solid is empty (resolution too coarse?)");
    // Constraint planes cut the target as well: the spheres are fitted to, and scored against, the part of
    // the grain on the allowed side of every plane (voxel centres), so that a fragment gets its own D and a
    // quality target it can meet.
    VoxelGrid fragment;
    if (!opt.planes.empty()) {
        fragment = cutVoxelsByPlanes(grain, opt.planes);
        if (countSolid(fragment) == 0)
            throw std::invalid_argument(
                "generate: no part of the solid lies on the allowed side of the planes");
    }
    const VoxelGrid& S = opt.planes.empty() ? grain : fragment;
    auto t0 = Clock::now();
    const ScalarGrid E = distanceTransform(S); // eq. 8
    m.secondsEdt = secondsSince(t0);
    const double h = S.spec.h;
    std::function<double(const Vec3&)> bound = meshBound;
    ScalarGrid grainEdt; // the whole grain's, for the voxel clearance when planes cut it
    if (!bound && opt.clip && !opt.planes.empty()) grainEdt = distanceTransform(grain);
    if (!bound && (opt.clip || !opt.planes.empty())) {
        // voxel volume: stay in the union of the solid voxels' cubes, the exact clearance (voxelClearance)
        const ScalarGrid& Eg = opt.planes.empty() ? E : grainEdt;
        bound = [&grain, &Eg, &opt, h](const Vec3& c) {
            double b = std::numeric_limits<double>::infinity();
            for (const Plane& p : opt.planes) b = std::min(b, planeDistance(p, c));
            if (!opt.clip || b < 0) return b;
            const double e = voxelClearance(grain, Eg, grain.spec.toVoxel(c));
            return e < 0 ? -1.0 : std::min(b, e * h);
        };
    }
    BoundVox boundVox;
    // the optimiser asks again and again at the same points (moves back and forth): remember the answers
    struct KeyHash {
        std::size_t operator()(const std::array<long long, 3>& k) const {
            return std::hash<long long>()(k[0] * 73856093LL ^ k[1] * 19349663LL ^ k[2] * 83492791LL);
        }
    };
    std::unordered_map<std::array<long long, 3>, double, KeyHash> cache;
    if (bound && (opt.refill || !opt.clip))
        boundVox = [&bound, &S, &cache, h](const Vec3& v) {
            const std::array<long long, 3> key{std::llround(v.x() * 65536.0), std::llround(v.y() * 65536.0),
                                               std::llround(v.z() * 65536.0)};
            auto it = cache.find(key);
            if (it != cache.end()) return it->second;
            const double b = bound(S.spec.toWorld(v)) / h;
            cache.emplace(key, b);
            return b;
        };
    std::vector<Ball> balls;
    double secondsRefine = 0.0;
    t0 = Clock::now();
    if (opt.method == Method::Paper) {
        balls = runPaper(S, E, opt, m, boundVox);
        m.secondsSelect = secondsSince(t0);
    } else {
        if (boundVox) {
            // Under constraints (clipping with refill, planes) the spheres are chosen twice, and the set with
            // the lower mismatch on the generation grid kept: from nothing under the constraint, and from the
            // unconstrained optimum cut down to the constraint and then refilled (greedy for the spheres
            // lost, refinement of all under the constraint: the paper's "clip, then continue"). Neither start
            // wins always (clipped, independent grid: ellipsoid 10 spheres 0.0104 cold / 0.0081 warm;
            // octahedron 40: 0.130 / 0.101; ellipsoid 40: 0.00134 / 0.00139; cube 40: 0.0753 / 0.0768).
            Metrics warmM = m, coldM = m;
            std::vector<Orbit> free;
            runOptimized(S, E, opt, BoundVox{}, warmM, secondsRefine, {}, &free);
            long long warmMismatch = 0, coldMismatch = 0;
            std::vector<Ball> warm =
                runOptimized(S, E, opt, boundVox, warmM, secondsRefine, free, nullptr, &warmMismatch);
            std::vector<Ball> cold =
                runOptimized(S, E, opt, boundVox, coldM, secondsRefine, {}, nullptr, &coldMismatch);
            const double select = warmM.secondsSelect + coldM.secondsSelect;
            // with a quality target (problem (ii)) fewer spheres win first, else less mismatch
            const auto w = std::make_pair(double(warmMismatch), double(warm.size()));
            const auto c = std::make_pair(double(coldMismatch), double(cold.size()));
            const bool useWarm = opt.eta > 0 || opt.dice > 0
                                     ? std::make_pair(w.second, w.first) <= std::make_pair(c.second, c.first)
                                     : w <= c;
            m = useWarm ? warmM : coldM;
            balls = useWarm ? std::move(warm) : std::move(cold);
            m.secondsSelect = select;
        } else {
            balls = runOptimized(S, E, opt, boundVox, m, secondsRefine);
        }
    }
    m.secondsRefine = secondsRefine;
    Result r;
    r.grid = S.spec;
    const double rMin = std::max(opt.rMin, 1e-9 * h);
    for (const Ball& b : balls) {
        const Vec3 c = S.spec.toWorld(b.c);
        double radius = b.r * h;
        if (bound) { // final clipping in world units: the guarantee does not rest on the voxel maths
            const double limit = bound(c);
            if (limit < radius) {
                ++m.clipped;
                radius = limit;
            }
        }
        if (radius >= rMin) r.spheres.add(c, radius);
    }
    if (r.spheres.size() == 0) { // a criterion left nothing: say which, never return an empty set silently
        const double inscribed = E.data.empty() ? 0.0 : h * *std::max_element(E.data.begin(), E.data.end());
        std::ostringstream os;
        if (opt.rMin > 0.0 && opt.rMin > inscribed)
            os << "generate: rMin " << opt.rMin << " exceeds the largest inscribed radius " << inscribed
               << " of the grain: no sphere can be placed";
        else
            os << "generate: no sphere is left" << (opt.rMin > 0.0 ? " at or above rMin" : "")
               << (opt.clip || !opt.planes.empty() ? " under the clipping constraint" : "")
               << " (largest inscribed radius " << inscribed << ")";
        throw std::invalid_argument(os.str());
    }
    const Mismatch mm = mismatch(S, voxelizeSpheres(r.spheres, S.spec));
    m.spheres = r.spheres.size();
    m.eta = mm.eta;
    m.dice = mm.dice;
    m.solidVoxels = mm.target;
    m.sphereVoxels = mm.approx;
    m.secondsTotal = secondsSince(start);
    r.metrics = m;
    return r;
}

} // namespace

void validateOptions(const GenerateOptions& o) {
    auto bad = [](const std::string& what, double v) {
        std::ostringstream os;
        os << "generate: " << what << ", got " << v;
        throw std::invalid_argument(os.str());
    };
    if (o.nSpheres < 0) bad("sphere count must be >= 1 (or 0 for no limit)", o.nSpheres);
    if (!(o.eta >= 0.0) || !(o.eta < 1.0)) bad("eta must be in [0, 1)", o.eta);
    if (!(o.dice >= 0.0) || !(o.dice < 1.0)) bad("dice must be in [0, 1)", o.dice);
    if (!(o.rMin >= 0.0) || !std::isfinite(o.rMin)) bad("rMin must be >= 0", o.rMin);
    if (o.maxIterations < 1) bad("maxIterations must be >= 1", o.maxIterations);
    if (!(o.deltaMin >= 0.0) || !std::isfinite(o.deltaMin)) bad("deltaMin must be >= 0", o.deltaMin);
    if (o.threads < 0) bad("threads must be >= 0", o.threads);
    for (const Plane& p : o.planes) validatePlane(p, "generate");
    if (o.nSpheres == 0 && o.eta == 0.0 && o.dice == 0.0 && o.rMin == 0.0)
        throw std::invalid_argument(
            "generate: give at least one termination criterion (sphere count, eta, dice or rMin)");
}

Mismatch mismatch(const VoxelGrid& target, const VoxelGrid& approx) {
    if (target.spec.dims != approx.spec.dims) throw std::invalid_argument("mismatch: grids differ in size");
    Mismatch m;
    for (std::size_t q = 0; q < target.size(); ++q) {
        const bool a = target.data[q] != 0, b = approx.data[q] != 0;
        m.target += a;
        m.approx += b;
        m.both += a && b;
    }
    const std::size_t diff = m.target + m.approx - 2 * m.both;
    m.eta = m.target ? double(diff) / double(m.target) : 0.0;                          // eq. 7
    m.dice = (m.target + m.approx) ? double(diff) / double(m.target + m.approx) : 0.0; // eq. 27
    return m;
}

// Departures from the paper in Method::Optimized, and why:
// - Under a sphere budget MSS takes maxima by value, and a discretised ridge (an elongated grain) gives
// dozens
//   of near-equal maxima next to each other: the budget goes to near-duplicates. Instead each candidate is
//   scored by the exact mismatch it removes given the spheres already placed (a greedy set cover with a
//   penalty for covering background), lazily re-evaluated.
// - The candidates are MSS's maxima of E plus a sampling of the medial ridge of E (every voxel where E has no
//   face neighbour more than half a voxel higher, thinned to at most 40,000), since the maxima alone are
//   often fewer than the budget and poorly placed for it. E* = 2E - Ẽ (eq. 25) is not needed: the exact gain
//   already measures what a candidate adds beyond the current union.
// - Centres and radii are then tuned by coordinate descent on the voxel mismatch (moves: a centre coordinate,
//   the radius, or a centre coordinate with the radius following E, so a ball can slide along the surface);
//   radii may exceed E by the discretisation the paper accepts (section 3.5), unless clipping is asked for
//   (GenerateOptions::clip).
// - Mirror planes of the voxelised grain through the grid centre are detected; candidates are placed with
//   their mirror images so the sphere set keeps the grain's symmetry (paper section 4.2 values this).
Result generate(const VoxelGrid& volume, const GenerateOptions& options) {
    validateOptions(options);
    const auto start = Clock::now();
    Metrics m;
    const VoxelGrid S = padVoxels(volume, 2); // eq. 6
    return generateOnGrid(S, options, m, start);
}

Result generate(const TriangleMesh& mesh, const Resolution& resolution, const GenerateOptions& options,
                int supersample) {
    validateOptions(options);
    const auto start = Clock::now();
    Metrics m;
    auto t0 = Clock::now();
    const VoxelGrid S = voxelizeMesh(mesh, resolution, supersample, &m.warnings);
    m.secondsVoxelize = secondsSince(t0);
    if (countSolid(S) == 0)
        throw std::invalid_argument(
            "generate: the mesh voxelises to no solid voxel (open mesh or too coarse a "
            "resolution?)");
    if (!options.clip && options.planes.empty()) return generateOnGrid(S, options, m, start);
    // Clipping (paper section 3.5, with the exact distance to the surface instead of the nearest vertex): a
    // sphere's radius is at most the distance from its centre to the nearest point of any triangle (CGAL AABB
    // tree), and a centre outside the solid is not allowed. Inside: the voxel centre nearest to c when the
    // surface is farther from c than that centre (same side), else the generalised winding number.
    std::unique_ptr<MeshQuery> query;
    VoxelGrid centres;
    if (options.clip) {
        query = std::make_unique<MeshQuery>(mesh);
        if (supersample != 1) centres = voxelizeMesh(mesh, S.spec, 1);
    }
    const VoxelGrid& inside = supersample != 1 ? centres : S;
    auto bound = [&](const Vec3& c) {
        double b = std::numeric_limits<double>::infinity();
        for (const Plane& p : options.planes) b = std::min(b, planeDistance(p, c));
        if (!query || b < 0) return b;
        const double dist = query->distance(c);
        const auto v = S.spec.voxelOf(c);
        bool in;
        if (S.spec.contains(v[0], v[1], v[2]) && dist > (c - S.spec.voxelCenter(v[0], v[1], v[2])).norm())
            in = inside(v[0], v[1], v[2]) != 0;
        else
            in = query->inside(c);
        return in ? std::min(b, dist) : -1.0;
    };
    return generateOnGrid(S, options, m, start, bound);
}

} // namespace mss
