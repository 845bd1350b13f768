#include "mss/generation/engine/refine.hpp"
#include "mss/work.hpp"

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

/// A trial position of an orbit, and the move (axis 0-2 centre, 3 radius; sign) that leads there.
struct Move {
    Orbit o;
    int axis;
    double sign;
};

/// The trials of moving @p o by @p step along axis @p a < 3 in direction @p sgn (the move itself, under a
/// constraint also grown to touch it, and sliding along the surface), or for @p a = 3 of its radius by
/// sgn * step, appended to @p out: all about one centre.
void movesAlong(const Selection& s, const Orbit& o, double step, int a, double sgn, std::vector<Move>& out) {
    const auto& d = s.S.spec.dims;
    Orbit trial = o;
    if (a < 3)
        trial.c[a] += sgn * step;
    else
        trial.r += sgn * step;
    if (a < 3 && (trial.c[a] < 1.0 || trial.c[a] > d[a] - 2.0)) return;
    const double limit = s.orbitBound(trial);
    if (a < 3 && limit > trial.r && limit < 1e300) {
        Orbit touching = trial; // under a constraint: grow to touch as well
        touching.r = limit;
        out.push_back({touching, a, sgn});
    }
    if (a < 3) {
        // slide: keep the clearance from the surface (radius changed by the change of E, trilinear). Moving a
        // ball along a surface needs its radius and centre to change together; one coordinate at a time
        // stalls there (ellipsoid, 40 spheres: D 0.0027 without this move, 0.00098 with it).
        Orbit slide = trial;
        slide.r = std::min(limit, o.r + trilinear(s.E, slide.c) - trilinear(s.E, o.c));
        if (std::abs(slide.r - trial.r) > 1e-3 && slide.r >= s.rMinVox && std::abs(slide.r - limit) > 1e-9)
            out.push_back({slide, a, sgn});
    }
    trial.r = std::min(trial.r, limit);
    if (trial.r < s.rMinVox) return;
    // the radius up where the orbit already touches the bound is the orbit itself, which cannot gain more
    // than it does (femur 70: 619 of 1725 radius trials; the task then evaluates the radius down alone)
    if (a == 3 && trial.r == o.r) return;
    out.push_back({trial, a, sgn});
}

/// Tunes one orbit (taken out of the coverage) by steps of 1/2 voxel (unless @p quarterOnly), then, if @p
/// fine, of 1/4 voxel; @p best: its gain, raised. Each step tries the moves from the orbit: its centre +-
/// step along each free axis, its radius +- step; not the reverse of the move just taken (it leads back); the
/// best that gains more is taken, the first in that order on a tie. The moves about one centre (a direction's
/// three; the radius down and up) are one task: its constraint looked up (exact queries cost ~4 us each; the
/// bound caches) and its trials evaluated in one pass over their rows (Coverage::gains), the tasks in
/// parallel.
void tune(const Selection& s, Orbit& o, long long& best, bool fine, bool quarterOnly) {
    struct Task {
        int axis;
        std::array<double, 2> signs; // 0: none
        std::vector<Move> trials;
        std::array<long long, Coverage::kMaxRadii> gains;
    };
    std::vector<Task> tasks;
    tasks.reserve(7);
    for (double step : {0.5, 0.25}) {
        if (step < 0.5 && !fine) break;
        if (step == 0.5 && quarterOnly) continue;
        int lastAxis = -1;
        double lastSign = 0.0;
        for (int rep = 0; rep < 6; ++rep) {
            tasks.clear();
            for (int a = 0; a < 4; ++a) {
                if (a < 3 && o.onPlane[a]) continue;
                for (double sgn : {-1.0, 1.0}) {
                    if (a == lastAxis && sgn == -lastSign) continue;
                    if (a == 3 && !tasks.empty() && tasks.back().axis == 3)
                        tasks.back().signs[1] = sgn; // the radius down and up: one centre, one task
                    else
                        tasks.push_back({a, {sgn, 0.0}, {}, {}});
                }
            }
#pragma omp parallel for schedule(dynamic, 1)
            for (int q = 0; q < int(tasks.size()); ++q) {
                Task& t = tasks[std::size_t(q)];
                for (double sgn : t.signs)
                    if (sgn != 0.0) movesAlong(s, o, step, t.axis, sgn, t.trials);
                if (t.trials.empty()) continue;
                std::array<Orbit, Coverage::kMaxRadii> os;
                for (std::size_t e = 0; e < t.trials.size(); ++e) os[e] = t.trials[e].o;
                s.orbitGains(os.data(), int(t.trials.size()), t.gains.data());
            }
            const Move* pick = nullptr;
            for (const Task& t : tasks)
                for (std::size_t e = 0; e < t.trials.size(); ++e)
                    if (t.gains[e] > best) {
                        best = t.gains[e];
                        pick = &t.trials[e];
                    }
            if (!pick) break;
            o = pick->o;
            lastAxis = pick->axis;
            lastSign = pick->sign;
        }
    }
}

} // namespace

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

void refine(Selection& s, const std::vector<Orbit>* touched, int sweeps, bool coarseFirst) {
    std::vector<Orbit>& chosen = s.chosen;
    std::vector<char> moved(chosen.size(), 1);
    if (touched)
        for (std::size_t q = 0; q < chosen.size(); ++q)
            moved[q] = std::any_of(touched->begin(), touched->end(),
                                   [&](const Orbit& t) { return overlaps(s.sym, chosen[q], t); });
    const std::vector<char> eligible = moved; // what the first sweep (and a last fine one) consider
    bool anyMoved = false;
    for (int sweep = 0; sweep < sweeps; ++sweep) {
        // coarse first: the sweeps before the last take half-voxel steps only; the last one takes half- then
        // quarter-voxel steps and considers every orbit the first one did (see refine.hpp)
        const bool fine = !coarseFirst || sweep == sweeps - 1, last = coarseFirst && fine;
        bool improved = false;
        std::vector<char> movedNow(chosen.size(), 0);
        for (std::size_t oi = 0; oi < chosen.size(); ++oi) {
            // a sweep over tens of thousands of spheres takes seconds: Ctrl-C is heard within one (checked
            // before the orbit is taken out, so a stop leaves the coverage whole)
            if (oi % 64 == 0) tick("refining");
            Orbit& o = chosen[oi];
            if ((sweep == 0 || last) && !eligible[oi]) continue; // far from what changed
            if (sweep > 0 && !last) {
                bool stale = true;
                for (std::size_t oj = 0; oj < chosen.size() && stale; ++oj)
                    if (moved[oj] && (oj == oi || overlaps(s.sym, o, chosen[oj]))) stale = false;
                if (stale) continue;
            }
            // its gain where it stands: what taking it out added to the mismatch (orbitGain() exactly, since
            // gains are the exact change of the mismatch; one evaluation a tune less, and a serial one)
            const long long before = s.cov.mismatch();
            s.cov.remove(s.sym.images(o));
            long long best = s.cov.mismatch() - before;
            const long long start = best;
            // while nothing has moved, the coverage is what the coarse sweeps saw: the half-voxel steps they
            // found no gain in find none again (a set refined before: the growth to a quality target, prune)
            tune(s, o, best, fine, last && !anyMoved);
            s.cov.add(s.sym.images(o));
            movedNow[oi] = best > start;
            improved = improved || best > start;
            anyMoved = anyMoved || best > start;
        }
        moved.swap(movedNow);
        if (last || (!coarseFirst && !improved)) break;
        if (!improved) sweep = sweeps - 2; // the half-voxel steps have converged: on to the last sweep
    }
}

} // namespace mss::engine
