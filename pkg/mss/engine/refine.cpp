#include "mss/engine/refine.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>

namespace mss::engine {

using mss::detail::floorInt;

namespace {

bool overlaps(const Symmetry& sym, const Orbit& a, const Orbit& b) {
    for (const Ball& x : sym.images(a))
        for (const Ball& y : sym.images(b))
            if ((x.c - y.c).norm() <= x.r + y.r + 1.0) return true;
    return false;
}

/// E at a point, trilinear between voxel centres.
double trilinear(const ScalarGrid& E, const Vec3& p) {
    const auto& d = E.spec.dims;
    const int i = std::clamp(floorInt(p.x()), 0, d[0] - 2), j = std::clamp(floorInt(p.y()), 0, d[1] - 2),
              k = std::clamp(floorInt(p.z()), 0, d[2] - 2);
    const double fx = p.x() - i, fy = p.y() - j, fz = p.z() - k;
    double v = 0.0;
    for (int c = 0; c < 8; ++c) {
        const int di = c & 1, dj = (c >> 1) & 1, dk = (c >> 2) & 1;
        v += (di ? fx : 1 - fx) * (dj ? fy : 1 - fy) * (dk ? fz : 1 - fz) * E(i + di, j + dj, k + dk);
    }
    return v;
}

/// A trial position of an orbit, and the move (axis 0-2 centre, 3 radius; sign) that leads there.
struct Move {
    Orbit o;
    int axis;
    double sign;
};

/// The moves from @p o by @p step: centre +- step along each free axis, radius +- step; not the reverse of
/// the move just taken (it leads back).
std::vector<Move> trialMoves(const Selection& s, const Orbit& o, double step, int lastAxis, double lastSign) {
    const auto& d = s.S.spec.dims;
    std::vector<Move> trials;
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
            const double limit = s.orbitBound(trial);
            if (a < 3 && limit > trial.r && limit < 1e300) {
                Orbit touching = trial; // under a constraint: grow to touch as well
                touching.r = limit;
                trials.push_back({touching, a, sgn});
            }
            if (a < 3) {
                // slide: keep the clearance from the surface (radius changed by the change of E, trilinear).
                // Moving a ball along a surface needs its radius and centre to change together; one
                // coordinate at a time stalls there (ellipsoid, 40 spheres: D 0.0027 without this move,
                // 0.00098 with it).
                Orbit slide = trial;
                slide.r = std::min(limit, o.r + trilinear(s.E, slide.c) - trilinear(s.E, o.c));
                if (std::abs(slide.r - trial.r) > 1e-3 && slide.r >= s.rMinVox &&
                    std::abs(slide.r - limit) > 1e-9)
                    trials.push_back({slide, a, sgn});
            }
            trial.r = std::min(trial.r, limit);
            if (trial.r < s.rMinVox) continue;
            trials.push_back({trial, a, sgn});
        }
    }
    return trials;
}

/// Looks up, in parallel, the constraint at the centres trialMoves() will ask for (the bound caches its
/// answers; which are looked up first changes no result). Exact clearance queries cost ~4 us each (femur 70:
/// 5700 of them, 3400 asked serially before).
void warmTrialBounds(const Selection& s, const Orbit& o, double step, int lastAxis, double lastSign) {
    if (!s.bound) return;
    const auto& d = s.S.spec.dims;
    std::array<Orbit, 6> centres;
    int n = 0;
    for (int a = 0; a < 3; ++a) {
        if (o.onPlane[a]) continue;
        for (double sgn : {-1.0, 1.0}) {
            if (a == lastAxis && sgn == -lastSign) continue;
            Orbit trial = o;
            trial.c[a] += sgn * step;
            if (trial.c[a] < 1.0 || trial.c[a] > d[a] - 2.0) continue;
            centres[std::size_t(n++)] = trial;
        }
    }
    if (n < 2) return;
#pragma omp parallel for schedule(static, 1)
    for (int e = 0; e < n; ++e) s.orbitBound(centres[std::size_t(e)]);
}

/// Tunes one orbit (taken out of the coverage) by steps of 1/2 then 1/4 voxel; @p best: its gain, raised.
void tune(const Selection& s, Orbit& o, long long& best) {
    for (double step : {0.5, 0.25}) {
        int lastAxis = -1;
        double lastSign = 0.0;
        for (int rep = 0; rep < 6; ++rep) {
            warmTrialBounds(s, o, step, lastAxis, lastSign);
            const std::vector<Move> trials = trialMoves(s, o, step, lastAxis, lastSign);
            // trials about one centre (the move, touching, sliding; the radius up and down) are evaluated
            // together, in one pass over their rows
            std::vector<int> groups; // first trial of each group, then the end
            for (int e = 0; e < int(trials.size()); ++e)
                if (e == 0 || trials[e].o.c != trials[e - 1].o.c ||
                    e - groups.back() == Coverage::kMaxRadii)
                    groups.push_back(e);
            groups.push_back(int(trials.size()));
            std::vector<long long> g(trials.size()), g1(trials.size());
            std::vector<Orbit> os(trials.size());
            for (std::size_t e = 0; e < trials.size(); ++e) os[e] = trials[e].o;
            const int nGroups = int(groups.size()) - 1;
#pragma omp parallel for schedule(dynamic, 1)
            for (int q = 0; q < 2 * nGroups; ++q) {
                const int gq = q / 2;
                auto& dst = q % 2 ? g1 : g;
                s.orbitGains(&os[std::size_t(groups[gq])], groups[gq + 1] - groups[gq],
                             &dst[std::size_t(groups[gq])], q % 2);
            }
            for (std::size_t e = 0; e < g.size(); ++e) g[e] += g1[e];
            int pick = -1;
            for (int e = 0; e < int(trials.size()); ++e)
                if (g[e] > best) {
                    best = g[e];
                    pick = e;
                }
            if (pick < 0) break;
            o = trials[pick].o;
            lastAxis = trials[pick].axis;
            lastSign = trials[pick].sign;
        }
    }
}

} // namespace

void refine(Selection& s, const std::vector<Orbit>* touched, int sweeps) {
    static const bool kSkip = !std::getenv("MSS_NOSKIP");
    std::vector<Orbit>& chosen = s.chosen;
    std::vector<char> moved(chosen.size(), 1);
    if (touched)
        for (std::size_t q = 0; q < chosen.size(); ++q)
            moved[q] = std::any_of(touched->begin(), touched->end(),
                                   [&](const Orbit& t) { return overlaps(s.sym, chosen[q], t); });
    for (int sweep = 0; sweep < sweeps; ++sweep) {
        bool improved = false;
        std::vector<char> movedNow(chosen.size(), 0);
        for (std::size_t oi = 0; oi < chosen.size(); ++oi) {
            Orbit& o = chosen[oi];
            if (sweep == 0 && touched && !moved[oi]) continue; // far from what changed
            if (sweep > 0 && kSkip) {
                bool stale = true;
                for (std::size_t oj = 0; oj < chosen.size() && stale; ++oj)
                    if (moved[oj] && (oj == oi || overlaps(s.sym, o, chosen[oj]))) stale = false;
                if (stale) continue;
            }
            for (const Ball& b : s.sym.images(o)) s.cov.remove(b);
            long long best = s.orbitGain(o);
            const long long start = best;
            tune(s, o, best);
            for (const Ball& b : s.sym.images(o)) s.cov.add(b);
            movedNow[oi] = best > start;
            improved = improved || best > start;
        }
        moved.swap(movedNow);
        if (!improved) break;
    }
}

} // namespace mss::engine
