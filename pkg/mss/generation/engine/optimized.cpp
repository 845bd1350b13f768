#include "mss/generation/engine/optimized.hpp"
#include "mss/generation/engine/polish.hpp"
#include "mss/generation/engine/refine.hpp"
#include "mss/work.hpp"

namespace mss::engine {

namespace {

void unplaceAll(Selection& s) {
    for (const Orbit& o : s.chosen) s.cov.remove(s.sym.images(o));
}

/// Symmetry repair: whole orbits can leave the budget short by one (say 10 = 1 sphere on all planes + 4 pairs
/// + 1 free). Tries trading a sphere that lies on all planes for a whole orbit; keeps the trade when it fills
/// more of the budget with at most 5% more mismatch. @p tune: the orbits near the trade are refined before
/// it is judged (after the main loop); without, it is judged as the greedy leaves it (after the first greedy
/// round, before any refinement, which then tunes the trade with everything else).
void repairSymmetry(Selection& s, bool tune) {
    for (int attempt = 0; attempt < 4 && s.sym.planes() > 0 && !s.full() && !s.met(); ++attempt) {
        std::ptrdiff_t centre = -1;
        for (std::size_t q = 0; q < s.chosen.size(); ++q)
            if (s.sym.images(s.chosen[q]).size() == 1) centre = std::ptrdiff_t(q);
        if (centre < 0) break;
        const std::vector<Orbit> saved = s.chosen;
        const std::size_t savedPlaced = s.placed;
        const long long before = s.cov.mismatch();
        std::vector<Orbit> touched{s.chosen[std::size_t(centre)]};
        s.cov.remove(s.sym.images(s.chosen[std::size_t(centre)]));
        s.placed -= 1;
        s.chosen.erase(s.chosen.begin() + centre);
        const std::size_t kept = s.chosen.size();
        s.greedy();
        touched.insert(touched.end(), s.chosen.begin() + std::ptrdiff_t(kept), s.chosen.end());
        if (tune) refine(s, &touched, 2, false);
        if (s.placed > savedPlaced && double(s.cov.mismatch()) <= 1.05 * double(before)) continue;
        unplaceAll(s);
        s.chosen = saved;
        s.placed = savedPlaced;
        for (const Orbit& o : s.chosen) s.cov.add(s.sym.images(o));
        break;
    }
}

/// Problem (ii), the fewest spheres for a quality target: a greedy run to the target overshoots (femur,
/// D <= 0.04: 57 spheres where a run at 46 reaches it), because refinement lowers the mismatch of a set by a
/// third and the greedy stops before it. So the budget grows from a few spheres by 30% at a time; after each
/// step the new orbits and their neighbours are refined by one sweep, and the target is checked on the
/// refined set (the main loop then refines the whole set).
void growToTarget(Selection& s, Report& m, double& secondsRefine) {
    const int cap = s.t.budget;
    // Growth per step and sweeps per step: 1.3 and one sweep give the same counts as 1.15 and two (femur D
    // 0.05 / 0.04 / 0.03: 35 / 44 / 60 spheres; cube, octahedron, torus, bunny and the CT grain at D 0.08 /
    // 0.05 / 0.03 within one sphere) at 0.7-0.8x the time: femur 1.53-1.54x a run at the final count,
    // against 2.05-2.25x. 1.5 changed the cube's counts by 3-4 spheres; 1.06 and 1.10 took up to 1.8x as
    // long as 1.15 for as many spheres.
    constexpr double kGrowth = 1.3;
    constexpr int kSweeps = 1;
    int budget = std::min(cap, 4);
    while (true) {
        tick("growing to " + std::to_string(budget) + " spheres");
        s.t.budget = budget;
        const std::size_t kept = s.chosen.size();
        auto t0 = Clock::now();
        s.greedy();
        m.secondsSelect += secondsSince(t0);
        t0 = Clock::now();
        const std::vector<Orbit> touched(s.chosen.begin() + std::ptrdiff_t(kept), s.chosen.end());
        refine(s, &touched, kSweeps, false);
        secondsRefine += secondsSince(t0);
        // stop at the target, the cap, or when nothing more could be placed (the main loop then goes on as
        // without growth); the growth is the first greedy round of the main loop, spread out, so it does not
        // count against maxIterations (a geometric budget ends in O(log) steps anyway)
        if (s.met() || budget >= cap || (s.chosen.size() == kept && s.placed < std::size_t(budget))) break;
        budget =
            int(std::min<long long>(cap, std::max<long long>(budget + 1, std::llround(budget * kGrowth))));
    }
    s.t.budget = cap;
}

/// What whole orbits could not fill: spheres alone.
void fillAlone(Selection& s) {
    if (s.allowBreak || s.full() || s.met()) return;
    s.allowBreak = true;
    const std::size_t before = s.placed, kept = s.chosen.size();
    s.greedy();
    const std::vector<Orbit> touched(s.chosen.begin() + std::ptrdiff_t(kept), s.chosen.end());
    if (s.placed > before)
        refine(s, &touched, 3, false); // grains with planes: the three sweeps of both steps
}

} // namespace

std::vector<Ball> runOptimized(const VoxelGrid& S, const ScalarGrid& E, const Request& opt,
                               const BoundVox& bound, Report& m, double& secondsRefine,
                               const std::vector<Orbit>& start, std::vector<Orbit>* orbitsOut,
                               long long* mismatchOut, SharedCandidates* shared) {
    Selection s(S, E, opt, bound, shared);
    m.symmetryPlanes = s.sym.planes();
    s.warmStart(start);
    m.iterations = 0;
    if (s.t.hasQuality() && start.empty()) growToTarget(s, m, secondsRefine);
    for (; m.iterations < opt.maxIterations; ++m.iterations) {
        tick("round " + std::to_string(m.iterations + 1) + ", " + std::to_string(s.placed) + " spheres");
        const std::size_t before = s.placed;
        const auto t0 = Clock::now();
        s.greedy();
        // The repair at once where the first greedy round leaves the budget short: the trade is then
        // refined with the rest, once. After the main loop it cost a refinement of its own and, since the
        // main loop had not filled the budget, a second round of it: here it is 10-30% faster and D is as low
        // or lower (ellipsoid 10: 9% lower). A trade refused here is tried again, refined, after the main
        // loop.
        if (m.iterations == 0) repairSymmetry(s, false);
        m.secondsSelect += secondsSince(t0);
        const auto t1 = Clock::now();
        // where no mirror plane is kept, a sweep of half-voxel steps, then one of half- and quarter-voxel
        // steps over every orbit (see refine.hpp); with planes, three sweeps of both: the repairs' trades are
        // judged on refined sets, and a different order of moves turned good trades down
        const bool coarseFirst = s.sym.planes() == 0;
        const int sweeps = coarseFirst ? 2 : 3;
        refine(s, nullptr, sweeps, coarseFirst);
        const bool pruned = s.prune();
        if (pruned) refine(s, nullptr, sweeps, coarseFirst);
        secondsRefine += secondsSince(t1);
        if (s.full() || s.met()) { // done (a warm start may begin so)
            ++m.iterations;
            break;
        }
        if (s.placed == before && !pruned) break; // nothing new: converged
    }
    repairSymmetry(s, true);
    fillAlone(s);
    // the joint polish on the final set (a warm start's free run is not final): it moves the set off the
    // refinement's local optimum, and one more refinement, on the exact mismatch, takes it further (femur 70
    // at resolution 103: mismatch 30072 -> 29258 polished -> 28238 refined; bunny 30: 59803 -> 55492 ->
    // 54548; a second polish and refinement gained 0.1% on the femur, 2.9% on the bunny, for as long again)
    if (opt.polish && !orbitsOut) {
        const auto t0 = Clock::now();
        if (const PolishReport p = polish(s); p.after < p.before) refine(s, nullptr, 2, true);
        secondsRefine += secondsSince(t0);
    }
    if (orbitsOut) *orbitsOut = s.chosen;
    if (mismatchOut) *mismatchOut = s.cov.mismatch();
    std::vector<Ball> out;
    for (const Orbit& o : s.chosen)
        for (const Ball& b : s.sym.images(o)) out.push_back(b);
    return out;
}

} // namespace mss::engine
