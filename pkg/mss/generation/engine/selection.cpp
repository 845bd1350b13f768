#include "mss/generation/engine/selection.hpp"
#include "mss/generation/engine/candidates.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <queue>

namespace mss::engine {

namespace {
Symmetry detectSymmetry(const VoxelGrid& S, std::size_t solid, const Request& opt, bool& exact,
                        SharedCandidates* shared) {
    if (shared && shared->filled) {
        exact = shared->exactSymmetry;
        return Symmetry(S.spec, shared->axes);
    }
    std::array<bool, 3> axes{false, false, false};
    if (opt.keepSymmetry) axes = mirrorAxes(S, solid, exact);
    // a constraint plane is mirrored onto itself only if it is parallel to the mirror's normal; any other
    // breaks that symmetry (an oblique cut through a symmetric grain would leave no orbit on its side)
    for (const Plane& p : opt.planes)
        for (int a = 0; a < 3; ++a)
            if (std::abs(p.normal[a]) > 1e-12 * p.normal.norm()) axes[a] = false;
    return Symmetry(S.spec, axes);
}
} // namespace

Selection::Selection(const VoxelGrid& S_, const ScalarGrid& E_, const Request& opt_, const BoundVox& bound_,
                     SharedCandidates* shared)
    : S(S_), E(E_), opt(opt_), bound(bound_), rMinVox(std::max(0.5, opt_.rMin / S_.spec.h)),
      cov(S_, opt_.nSpheres > 0 ? std::size_t(opt_.nSpheres) : 65535),
      sym(detectSymmetry(S_, cov.solid(), opt_, exactSymmetry, shared)), t{opt_.nSpheres > 0 ? opt_.nSpheres
                                                                                             : INT32_MAX,
                                                                           opt_.eta, opt_.dice} {
    if (exactSymmetry) cov.setMirrorPlanes(sym.axes());
    if (shared && shared->filled) {
        cands = shared->cands;
        ridge = shared->ridge;
    } else {
        cands = candidateOrbits(E, sym, rMinVox, &ridge);
        if (shared) {
            shared->cands = cands;
            shared->ridge = ridge;
            shared->axes = sym.axes();
            shared->exactSymmetry = exactSymmetry;
            shared->filled = true;
        }
    }
    used.assign(cands.size(), 0);
    // heap keys: first an upper bound (a ball fully inside), later the last evaluated gain per sphere, kept
    // between greedy rounds so that a later round starts from good estimates
    key.resize(cands.size());
    for (std::size_t q = 0; q < cands.size(); ++q) key[q] = 4.18879 * std::pow(cands[q].r, 3) + 10.0;
    // with mirror planes, orbits are placed whole first; spheres alone only fill what whole orbits cannot
    allowBreak = sym.planes() == 0;
}

double Selection::orbitBound(const Orbit& o) const {
    double b = std::numeric_limits<double>::infinity();
    if (bound)
        for (const Ball& x : sym.images(o)) b = std::min(b, bound(x.c));
    return b;
}

double Selection::clampToBound(const Orbit& o) const {
    double r = o.r;
    if (bound)
        for (const Ball& x : sym.images(o)) r = bound.clamp(x.c, r);
    return r;
}

// While the target is exactly mirror symmetric and every placed orbit is whole, the coverage is symmetric
// too: images apart from each other gain the same, so one is counted (the ellipsoid's orbits have up to 8).
long long Selection::orbitGain(const Orbit& o) const {
    const std::vector<Ball> imgs = sym.images(o);
    const bool mirrored = exactSymmetry && imgs.size() > 1 &&
                          std::none_of(chosen.begin(), chosen.end(), [](const Orbit& c) { return c.broken; });
    return cov.gain(imgs, mirrored);
}

void Selection::orbitGains(const Orbit* os, int n, long long* out) const {
    if (n <= Coverage::kMaxRadii && sym.images(os[0]).size() == 1) {
        double radii[Coverage::kMaxRadii];
        for (int m = 0; m < n; ++m) radii[m] = os[m].r;
        cov.gains(sym.images(os[0])[0].c, radii, n, out);
        return;
    }
    for (int m = 0; m < n; ++m) out[m] = orbitGain(os[m]);
}

void Selection::place(const Orbit& o) {
    cov.add(sym.images(o));
    placed += sym.images(o).size();
    chosen.push_back(o);
}

void Selection::warmStart(const std::vector<Orbit>& start) {
    for (Orbit o : start) {
        o.r = clampToBound(o);
        o.bounded = true;
        if (o.r < rMinVox || sym.images(o).size() > std::size_t(t.budget) - placed) continue;
        place(o);
    }
}

void Selection::takeBatch(GreedyHeap& heap, const std::vector<std::size_t>& stamp,
                          std::vector<std::size_t>& lensStamp, std::vector<long long>& batch,
                          std::vector<double>& gains) {
    // The batch: the stale entries from the top, as the serial rule takes them (a candidate's constraint
    // looked up when it is first reached; one that leaves no radius of at least rMin dropped). The
    // constraints and the gains are computed together in one parallel loop, on the assumption that
    // nothing is dropped (a constraint of at least rMin wherever a centre is inside: the default bound of
    // a voxel); where something is, the serial rule takes it from there, with the same batch.
    batch.clear();
    std::vector<char> breaks;       // whether the entry's orbit does not fit whole and is broken up
    std::size_t stopper = SIZE_MAX; // the entry the batch stopped at (an orbit that does not fit whole)
    while (!heap.empty() && batch.size() < kBatch) {
        const std::size_t p = static_cast<std::size_t>(-heap.top().second);
        if (stamp[p] == placed) break;
        if (lensStamp[p] != placed) { // its key lowered to the lens bound first, where that is lower
            lensStamp[p] = placed;
            const double bound = lensBound(cands[p]);
            if (bound < heap.top().first) {
                const auto entry = heap.top();
                heap.pop();
                heap.push({bound, entry.second});
                continue;
            }
        }
        const bool tooMany = sym.images(cands[p]).size() > std::size_t(t.budget) - placed;
        if (tooMany && !allowBreak) {
            stopper = p;
            break;
        }
        batch.push_back(heap.top().second);
        breaks.push_back(tooMany);
        heap.pop();
    }
    gains.assign(batch.size(), 0.0);
    std::vector<char> dropped(batch.size() + 1, 0);
    auto constrain = [&](std::size_t p) { // false: dropped
        if (cands[p].bounded) return true;
        cands[p].bounded = true;
        cands[p].r = clampToBound(cands[p]);
        return cands[p].r >= rMinVox;
    };
#pragma omp parallel for schedule(dynamic, 1)
    for (int e = 0; e <= int(batch.size()); ++e) {
        if (e == int(batch.size())) { // the stopper's constraint, looked up before the serial rule stops
            if (stopper != SIZE_MAX) dropped[std::size_t(e)] = !constrain(stopper);
            continue;
        }
        const std::size_t p = std::size_t(-batch[std::size_t(e)]);
        if (!constrain(p)) {
            dropped[std::size_t(e)] = 1;
            continue;
        }
        if (breaks[std::size_t(e)]) cands[p].broken = true;
        gains[std::size_t(e)] = double(orbitGain(cands[p])) / double(sym.images(cands[p]).size());
    }
    if (std::any_of(dropped.begin(), dropped.end(), [](char d) { return d != 0; })) {
        std::vector<long long> kept;
        std::vector<double> keptGains;
        for (std::size_t e = 0; e < batch.size(); ++e) {
            if (dropped[e]) {
                used[std::size_t(-batch[e])] = 1;
                continue;
            }
            kept.push_back(batch[e]);
            keptGains.push_back(gains[e]);
        }
        const bool more = stopper != SIZE_MAX ? dropped[batch.size()] != 0 : batch.size() == kBatch;
        if (stopper != SIZE_MAX && dropped[batch.size()]) {
            heap.pop();
            used[stopper] = 1;
        }
        batch.swap(kept);
        gains.swap(keptGains);
        const std::size_t firstNew = batch.size();
        while (more && !heap.empty() && batch.size() < kBatch) { // the serial rule
            const std::size_t p = static_cast<std::size_t>(-heap.top().second);
            if (stamp[p] == placed) break;
            if (!constrain(p)) {
                heap.pop();
                used[p] = 1;
                continue;
            }
            if (sym.images(cands[p]).size() > std::size_t(t.budget) - placed) {
                if (!allowBreak) break;
                cands[p].broken = true;
            }
            batch.push_back(heap.top().second);
            heap.pop();
        }
        gains.resize(batch.size(), 0.0);
#pragma omp parallel for schedule(dynamic, 1)
        for (int e = int(firstNew); e < int(batch.size()); ++e) {
            const Orbit& o = cands[std::size_t(-batch[std::size_t(e)])];
            gains[std::size_t(e)] = double(orbitGain(o)) / double(sym.images(o).size());
        }
    }
}

double Selection::lensBound(const Orbit& o) const {
    constexpr double kBall = 4.18879; // 4 pi / 3
    constexpr double kPi = 3.14159265358979323846;
    const double a = o.r;
    const double whole = kBall * a * a * a + 10.0; // the first key: the ball's volume, a little widened
    if (sym.images(o).size() != 1) return whole;
    double lens = 0.0;
    for (const Orbit& c : chosen)
        for (const Ball& b : sym.images(c)) {
            const double d = (b.c - o.c).norm(), r = b.r;
            if (d >= a + r) continue;
            double v;
            if (d <= std::abs(a - r)) { // one inside the other
                const double m = std::min(a, r);
                v = kBall * m * m * m;
            } else { // the lens of two spheres
                const double t = a + r - d;
                v = kPi * t * t * (d * d + 2.0 * d * (a + r) - 3.0 * (a - r) * (a - r)) / (12.0 * d);
            }
            lens = std::max(lens, v);
        }
    // 0.9: the voxels of a lens are its volume only to within its surface's rounding
    return whole - 0.9 * lens;
}

void Selection::greedy() {
    // Stale entries are re-evaluated in batches of kBatch, in parallel; the batch size does not depend on
    // the thread count, so neither does the result.
    GreedyHeap heap;
    std::vector<std::size_t> stamp(cands.size(), SIZE_MAX), lensStamp(cands.size(), SIZE_MAX);
    for (std::size_t q = 0; q < cands.size(); ++q)
        if (!used[q]) heap.push({key[q], -static_cast<long long>(q)});
    std::vector<long long> batch;
    std::vector<double> gains;
    while (!heap.empty() && placed < std::size_t(t.budget) && !met()) {
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
            place(cands[q]);
            used[q] = 1;
            continue;
        }
        takeBatch(heap, stamp, lensStamp, batch, gains);
        evaluations += batch.size();
        for (std::size_t e = 0; e < batch.size(); ++e) {
            stamp[std::size_t(-batch[e])] = placed;
            key[std::size_t(-batch[e])] = gains[e];
            heap.push({gains[e], batch[e]});
        }
    }
}

bool Selection::prune() {
    if (!t.hasQuality() || !met()) return false;
    bool any = false;
    for (std::size_t q = chosen.size(); q-- > 0;) {
        const auto imgs = sym.images(chosen[q]);
        cov.remove(imgs);
        if (met()) {
            placed -= imgs.size();
            chosen.erase(chosen.begin() + static_cast<std::ptrdiff_t>(q));
            any = true;
        } else {
            cov.add(imgs);
        }
    }
    return any;
}

} // namespace mss::engine
