#include "mss/generation/engine/polish.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace mss::engine {

using mss::detail::ceilInt;
using mss::detail::floorInt;

namespace {

/// A ball of an orbit, and the sign that maps a change of its centre back to the orbit's (-1 on the axes
/// of the planes it is mirrored in).
struct Image {
    Ball b;
    std::size_t orbit;
    std::array<double, 3> sign;
};

std::vector<Image> imagesOf(const Symmetry& sym, const std::vector<Orbit>& orbits) {
    std::vector<Image> out;
    for (std::size_t q = 0; q < orbits.size(); ++q)
        for (const Ball& b : sym.images(orbits[q])) {
            Image im{b, q, {1.0, 1.0, 1.0}};
            for (int a = 0; a < 3; ++a)
                if (b.c[a] != orbits[q].c[a]) im.sign[std::size_t(a)] = -1.0;
            out.push_back(im);
        }
    return out;
}

/// Beyond this many tau from a sphere's surface a voxel counts as inside (u = 1) or outside (u = 0) it:
/// sigmoid(4) = 0.982.
constexpr double kBand = 4.0;

/// sigmoid(z) for |z| < kBand from a table (1/256 apart, linear between): the passes' exponentials were a
/// sixth of a polish.
float sigmoid(float z) {
    constexpr int kPerUnit = 256, kN = 2 * int(kBand) * kPerUnit + 1;
    static const std::array<float, kN + 1> table = [] {
        std::array<float, kN + 1> t{};
        for (int i = 0; i <= kN; ++i)
            t[std::size_t(i)] = float(1.0 / (1.0 + std::exp(-(double(i) / kPerUnit - kBand))));
        return t;
    }();
    const float x = std::clamp((z + float(kBand)) * kPerUnit, 0.0f, float(kN - 1));
    const int i = int(x);
    const float f = x - float(i);
    return table[std::size_t(i)] + f * (table[std::size_t(i) + 1] - table[std::size_t(i)]);
}

/// The smoothed union on the voxels near the balls: per voxel the product of (1 - u_i) over the balls whose
/// band holds it, and the count of balls it lies deep inside (then U = 1 and no gradient flows there).
class SmoothUnion {
public:
    /// On the grid of @p S coarsened by @p factor (a coarse voxel's weight: 2 x its solid share - 1).
    SmoothUnion(const VoxelGrid& S, int factor) : f_(factor) {
        for (int a = 0; a < 3; ++a) d_[std::size_t(a)] = (S.spec.dims[std::size_t(a)] + f_ - 1) / f_;
        const std::size_t n = std::size_t(d_[0]) * std::size_t(d_[1]) * std::size_t(d_[2]);
        w_.assign(n, 0.0f);
        q_.assign(n, 1.0f);
        sat_.assign(n, 0);
        const auto& fd = S.spec.dims;
        // a coarse slice's fine slices by one thread, each x's coarse column looked up (a division a voxel
        // was most of this set-up's time)
        std::vector<int> coarseX(static_cast<std::size_t>(fd[0]));
        for (int i = 0; i < fd[0]; ++i) coarseX[std::size_t(i)] = i / f_;
#pragma omp parallel for schedule(static)
        for (int kc = 0; kc < d_[2]; ++kc) {
            const std::size_t plane = static_cast<std::size_t>(d_[0]) * static_cast<std::size_t>(d_[1]);
            std::vector<int> solid(plane, 0), all(plane, 0);
            for (int k = kc * f_; k < std::min(fd[2], (kc + 1) * f_); ++k)
                for (int j = 0; j < fd[1]; ++j) {
                    const std::size_t row = std::size_t(d_[0]) * std::size_t(j / f_);
                    const std::uint8_t* v = &S(0, j, k);
                    for (int i = 0; i < fd[0]; ++i) {
                        const std::size_t p = row + std::size_t(coarseX[std::size_t(i)]);
                        ++all[p];
                        solid[p] += v[i] ? 1 : 0;
                    }
                }
            const std::size_t at = index(0, 0, kc);
            for (std::size_t p = 0; p < plane; ++p)
                w_[at + p] = float(2.0 * solid[p] / std::max(1, all[p]) - 1.0);
        }
    }

    /// d F / d (centre, radius) of each image, F = sum_p g(p) U(p), g = +1 on the target and -1 off it (the
    /// exact mismatch is |S| - F as tau -> 0).
    void gradient(const std::vector<Image>& fine, double tauFine, std::vector<std::array<double, 4>>& out) {
        const auto& d = d_;
        const double tau = tauFine / f_;
        std::vector<Image> imgs = fine; // in coarse voxels: fine voxel i lies at (i - (f - 1) / 2) / f
        for (Image& im : imgs) {
            im.b.c = (im.b.c - Vec3::Constant(0.5 * (f_ - 1))) / double(f_);
            im.b.r /= f_;
        }
        const double reach = kBand * tau;
        // the counts first (the voxels deep inside a ball: fills, no arithmetic), then the products only
        // where no ball holds the voxel deep inside (with many overlapping spheres most of a band is inside
        // another sphere: femur 70 ...); slice by slice, each slice's voxels written by one thread
#pragma omp parallel for schedule(static)
        for (int k = 0; k < d[2]; ++k) {
            for (const Image& im : imgs)
                rows(im.b, reach, k, [&](std::size_t at, int, int, int h0, int h1, double, double) {
                    for (int i = h0; i <= h1; ++i) ++sat_[at + std::size_t(i)];
                });
            for (const Image& im : imgs)
                rows(im.b, reach, k,
                     [&](std::size_t at, int i0, int i1, int h0, int h1, double dy, double dz) {
                         const double yz = dy * dy + dz * dz;
                         for (int i = i0; i <= i1; ++i) {
                             if (i == h0) i = h1 + 1; // the hole (empty: h0 > h1, never met)
                             if (i > i1) break;
                             const std::size_t p = at + std::size_t(i);
                             if (sat_[p]) continue;
                             const double dx = i - im.b.c.x();
                             const float z = float((im.b.r - std::sqrt(dx * dx + yz)) / tau);
                             if (z >= float(kBand))
                                 sat_[p] = 1;
                             else if (z > -float(kBand))
                                 q_[p] *= sigmoid(-z); // 1 - u
                         }
                     });
        }
        out.assign(imgs.size(), {0.0, 0.0, 0.0, 0.0});
        // dU / dz_i = Q sigmoid(z_i) (Q the whole product, 1 - u_i included), z_i = (r_i - |p - c_i|) / tau
#pragma omp parallel for schedule(dynamic, 1)
        for (int n = 0; n < int(imgs.size()); ++n) {
            const Ball& b = imgs[std::size_t(n)].b;
            std::array<double, 4> g{0.0, 0.0, 0.0, 0.0};
            for (int k = std::max(0, ceilInt(b.c.z() - b.r - reach));
                 k <= std::min(d[2] - 1, floorInt(b.c.z() + b.r + reach)); ++k)
                rows(b, reach, k, [&](std::size_t at, int i0, int i1, int h0, int h1, double dy, double dz) {
                    const double yz = dy * dy + dz * dz;
                    for (int i = i0; i <= i1; ++i) {
                        if (i == h0) i = h1 + 1;
                        if (i > i1) break;
                        const std::size_t p = at + std::size_t(i);
                        if (sat_[p]) continue;
                        const double dx = i - b.c.x(), dist = std::sqrt(dx * dx + yz);
                        const double z = (b.r - dist) / tau;
                        if (z >= kBand || z <= -kBand) continue;
                        const double w = double(w_[p] * q_[p] * sigmoid(float(z))) / tau / f_;
                        g[3] += w;
                        if (dist > 1e-12) {
                            // d |p - c| / d c = -(p - c) / |p - c|, and z falls with it
                            g[0] += w * dx / dist;
                            g[1] += w * dy / dist;
                            g[2] += w * dz / dist;
                        }
                    }
                });
            out[std::size_t(n)] = g; // per fine voxel: d/dc = (d/dc') / f, counted in coarse voxels
        }
        // back to U = 0 everywhere
#pragma omp parallel for schedule(static)
        for (int k = 0; k < d[2]; ++k)
            for (const Image& im : imgs)
                rows(im.b, reach, k, [&](std::size_t at, int i0, int i1, int, int, double, double) {
                    std::fill(q_.begin() + std::ptrdiff_t(at) + i0, q_.begin() + std::ptrdiff_t(at) + i1 + 1,
                              1.0f);
                    std::fill(sat_.begin() + std::ptrdiff_t(at) + i0,
                              sat_.begin() + std::ptrdiff_t(at) + i1 + 1, std::uint16_t(0));
                });
    }

private:
    /// The rows of slice @p k within @p reach of ball @p b's surface: f(start of the row, i0, i1, h0, h1,
    /// dy, dz) with [i0, i1] the voxels within r + reach of the centre and [h0, h1] (maybe empty) those
    /// within r - reach, which the band does not hold.
    template <class F> void rows(const Ball& b, double reach, int k, F&& f) const {
        const auto& d = d_;
        const double dz = k - b.c.z(), ro = b.r + reach, ri = b.r - reach;
        const double oz = ro * ro - dz * dz;
        if (oz < 0) return;
        const double iz = ri > 0 ? ri * ri - dz * dz : -1.0;
        const double ry = std::sqrt(oz);
        const int j0 = std::max(0, ceilInt(b.c.y() - ry)), j1 = std::min(d[1] - 1, floorInt(b.c.y() + ry));
        for (int j = j0; j <= j1; ++j) {
            const double dy = j - b.c.y(), ox = oz - dy * dy;
            if (ox < 0) continue;
            const double rx = std::sqrt(ox);
            const int i0 = std::max(0, ceilInt(b.c.x() - rx)),
                      i1 = std::min(d[0] - 1, floorInt(b.c.x() + rx));
            if (i0 > i1) continue;
            int h0 = 1, h1 = 0;
            const double ix = iz - dy * dy;
            if (ix > 0) {
                const double hx = std::sqrt(ix);
                h0 = std::max(i0, ceilInt(b.c.x() - hx));
                h1 = std::min(i1, floorInt(b.c.x() + hx));
            }
            f(index(0, j, k), i0, i1, h0, h1, dy, dz);
        }
    }

    std::size_t index(int i, int j, int k) const {
        return std::size_t(i) + std::size_t(d_[0]) * (std::size_t(j) + std::size_t(d_[1]) * std::size_t(k));
    }

    int f_;
    std::array<int, 3> d_;
    std::vector<float> w_, q_;
    std::vector<std::uint16_t> sat_;
};

void setCoverage(Selection& s, const std::vector<Orbit>& from, const std::vector<Orbit>& to) {
    for (const Orbit& o : from) s.cov.remove(s.sym.images(o));
    for (const Orbit& o : to) s.cov.add(s.sym.images(o));
}

} // namespace

PolishReport polish(Selection& s) {
    PolishReport rep;
    rep.before = rep.after = s.cov.mismatch();
    if (s.chosen.empty()) return rep;
    const auto& d = s.S.spec.dims;
    // The smoothed union on a coarser grid where the spheres are large: the work per step is the volume of
    // the spheres' bands, and halving the grid divides it by about 8 at the same gains (femur 70 at
    // resolution 103, smallest radius 7.6 voxels: mismatch 30072 -> 29137 on the grid itself, 29258
    // coarsened by 2, in 0.26x the time; bunny 30: 55164 / 55086; a factor 3 there lost most of the
    // femur's gain, 29752). The exact mismatch that decides is always the generation grid's. The factor
    // follows the radius a tenth of the way up the sorted radii, not the smallest: one tip sphere of 1.9
    // voxels kept the ellipsoid 2:1:1 at 70 spheres (the others 30-52 voxels) on the full grid, at 8x the
    // generation's time.
    std::vector<double> radii;
    for (const Orbit& o : s.chosen) radii.push_back(o.r);
    std::nth_element(radii.begin(), radii.begin() + std::ptrdiff_t(radii.size() / 10), radii.end());
    const double low = radii[radii.size() / 10];
    const int factor = std::clamp(int(low / 5.0), 1, 3);
    SmoothUnion smooth(s.S, factor);
    std::vector<Orbit> now = s.chosen, best = s.chosen;
    long long bestMismatch = rep.before;
    // Adam per coordinate (a step of about the rate in every coordinate whatever the gradient's scale: the
    // gradient's size varies by orders of magnitude between a sphere deep in the union and one on the
    // surface); momentum and scale are kept across the levels of tau. A step normalised by the largest
    // gradient instead gained a third as much or nothing (femur 70: none; bunny 30: 57363 against 55164).
    constexpr std::array<double, 3> kTau{1.0, 0.6, 0.35}, kRate{0.25, 0.15, 0.08};
    constexpr int kSteps = 12;
    constexpr double b1 = 0.9, b2 = 0.999;
    std::vector<std::array<double, 4>> m(now.size(), {0, 0, 0, 0}), v(now.size(), {0, 0, 0, 0});
    std::vector<std::array<double, 4>> gi, go;
    int t = 0;
    // The exact bound at each orbit's centre where known (NaN: not yet). The bound is 1-Lipschitz (a distance
    // to the surface or a plane, plus a constant), so a radius at most the last bound less the distance
    // moved needs no query. Bounds as linear or piecewise-linear models between queries (a gradient asked
    // again after half a voxel or a voxel of travel) lost most of the femur's gain (70 spheres: 30072 ->
    // 31048 / 33666, against 29258): large spheres sit on the medial axis, where the bound has a ridge.
    std::vector<double> known(now.size(), std::nan(""));
    for (std::size_t level = 0; level < kTau.size(); ++level) {
        for (int step = 0; step < kSteps; ++step, ++t, ++rep.steps) {
            const std::vector<Image> imgs = imagesOf(s.sym, now);
            smooth.gradient(imgs, kTau[level], gi);
            go.assign(now.size(), {0.0, 0.0, 0.0, 0.0});
            for (std::size_t n = 0; n < imgs.size(); ++n) {
                auto& g = go[imgs[n].orbit];
                for (std::size_t a = 0; a < 3; ++a) g[a] += imgs[n].sign[a] * gi[n][a];
                g[3] += gi[n][3];
            }
            const double bc1 = 1 - std::pow(b1, t + 1), bc2 = 1 - std::pow(b2, t + 1);
#pragma omp parallel for schedule(dynamic, 1)
            for (int n = 0; n < int(now.size()); ++n) {
                const std::size_t q = std::size_t(n);
                Orbit& o = now[q];
                auto& g = go[q];
                // at the bound, growing means moving to where the bound is larger: the radius's gradient
                // along the bound's (central differences over a voxel)
                if (s.bound && g[3] > 0) {
                    if (std::isnan(known[q])) known[q] = s.orbitBound(o);
                    if (o.r >= known[q] - 1e-6)
                        for (int a = 0; a < 3; ++a) {
                            if (o.onPlane[std::size_t(a)]) continue;
                            Orbit lo = o, hi = o;
                            lo.c[a] -= 0.5;
                            hi.c[a] += 0.5;
                            g[std::size_t(a)] += g[3] * (s.orbitBound(hi) - s.orbitBound(lo));
                        }
                }
                for (std::size_t a = 0; a < 3; ++a)
                    if (o.onPlane[a]) g[a] = 0.0; // on a mirror plane it stays (the symmetry is kept)
                const Orbit was = o;
                for (std::size_t p = 0; p < 4; ++p) {
                    m[q][p] = b1 * m[q][p] + (1 - b1) * g[p];
                    v[q][p] = b2 * v[q][p] + (1 - b2) * g[p] * g[p];
                    const double delta = kRate[level] * (m[q][p] / bc1) / (std::sqrt(v[q][p] / bc2) + 1e-12);
                    if (p < 3)
                        o.c[int(p)] = std::clamp(o.c[int(p)] + delta, 1.0, d[p] - 2.0);
                    else
                        o.r += delta;
                }
                if (s.bound) {
                    const double moved = (o.c - was.c).norm(), wasKnown = known[q];
                    if (moved > 0) known[q] = std::nan("");
                    if (moved == 0 && !std::isnan(wasKnown)) {
                        o.r = std::min(o.r, wasKnown);
                    } else if (std::isnan(wasKnown) ||
                               o.r > wasKnown - moved) { // it may reach past the bound
                        const double limit = known[q] = s.orbitBound(o);
                        if (limit < s.rMinVox) { // no room for rMin here (a plane's wrong side): it stays
                            o.c = was.c;
                            known[q] = std::isnan(wasKnown) ? s.orbitBound(o) : wasKnown;
                            o.r = std::min(o.r, known[q]);
                        } else {
                            o.r = std::min(o.r, limit);
                        }
                    }
                }
                o.r = std::max(o.r, s.rMinVox);
            }
        }
        // the set judged is within the exact bound whatever the bound's regularity (the steps above rely on
        // its being 1-Lipschitz); an orbit left without room for rMin goes back to where it started
        if (s.bound)
            for (std::size_t q = 0; q < now.size(); ++q) {
                now[q].r = std::min(now[q].r, s.orbitBound(now[q]));
                if (now[q].r < s.rMinVox) now[q] = s.chosen[q];
                known[q] = std::nan("");
            }
        // judged on the exact mismatch after each level (the smoothed one is what the steps follow)
        setCoverage(s, s.chosen, now);
        s.chosen = now;
        if (s.cov.mismatch() < bestMismatch) {
            bestMismatch = s.cov.mismatch();
            best = now;
        }
    }
    setCoverage(s, s.chosen, best);
    s.chosen = best;
    rep.after = s.cov.mismatch();
    return rep;
}

} // namespace mss::engine
