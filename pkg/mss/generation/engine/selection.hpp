// The state of the optimised method (Method::Optimized) and its greedy selection.
#pragma once

#include "mss/generation/engine/coverage.hpp"
#include "mss/generation/engine/request.hpp"
#include "mss/generation/engine/symmetry.hpp"
#include "mss/grid.hpp"

#include <queue>
#include <utility>
#include <vector>

namespace mss::engine {

/// Candidates and symmetry found once for several runs of the optimised method on one grain (clipping runs
/// three).
struct SharedCandidates {
    bool filled = false;
    std::vector<Orbit> cands;
    std::size_t ridge = 0;
    std::array<bool, 3> axes{false, false, false};
    bool exactSymmetry = false;
};

/// What the optimised method works on, shared by its steps (candidates, greedy, refinement, pruning,
/// symmetry repair): the target and its coverage by the orbits chosen so far, the mirror symmetry, the
/// candidate orbits with their greedy keys, and the constraint on radii.
struct Selection {
    /// Detects the mirror symmetry of @p S (kept only for planes parallel to every constraint plane's normal)
    /// and takes the candidates of candidateOrbits(), or those in @p shared when it holds them (runs on the
    /// same S, E and options have the same candidates: the first run fills it, later runs copy them).
    Selection(const VoxelGrid& S, const ScalarGrid& E, const Request& opt, const BoundVox& bound,
              SharedCandidates* shared = nullptr);

    const VoxelGrid& S;
    const ScalarGrid& E;
    const Request& opt;
    const BoundVox bound; ///< a copy: a temporary may be passed (copies of a CachedBound share its cache)
    const double rMinVox; ///< smallest radius (voxels): rMin, and never under half a voxel
    Coverage cov;         ///< coverage of S by the chosen orbits' balls
    bool exactSymmetry = false; ///< S is exactly invariant under the mirror planes
    const Symmetry sym;
    Targets t;                 ///< termination; the budget may be raised step by step (problem (ii))
    std::vector<Orbit> cands;  ///< candidates (radius cut to the constraint once bounded)
    std::vector<double> key;   ///< greedy key per candidate: an upper bound, then its last gain per ball
    std::vector<char> used;    ///< candidate placed or dropped
    std::vector<Orbit> chosen; ///< the orbits placed
    std::size_t placed = 0;    ///< balls placed (orbits count with all their images)
    bool allowBreak;           ///< orbits may be broken up into spheres alone (always without symmetry)
    std::size_t evaluations = 0, ridge = 0;

    /// The largest radius the constraints allow for all images of an orbit (+inf without constraint).
    double orbitBound(const Orbit& o) const;
    /// The radius of @p o cut down to orbitBound(o) (BoundVox::clamp: cheaper where the bound does not bind).
    double clampToBound(const Orbit& o) const;
    /// Mismatch removed by adding all images of @p o to the coverage (exact, eq. 2 on voxels).
    long long orbitGain(const Orbit& o) const;
    /// orbitGain() of each of the @p n orbits @p os, which differ in radius only, into @p out: one pass over
    /// the rows of all (Coverage::gains) where each is a single ball.
    void orbitGains(const Orbit* os, int n, long long* out) const;
    bool met() const { return t.met(cov.eta(), cov.dice()); }
    bool full() const { return placed >= std::size_t(t.budget); }
    void place(const Orbit& o);
    /// Starts from @p start (spheres found without the constraints), each cut down to the constraints.
    void warmStart(const std::vector<Orbit>& start);
    /// Lazy greedy: places the candidate that removes most mismatch per ball until the budget or a quality
    /// target is met or nothing gains. Keys are re-evaluated in batches of 8 in parallel (independent of the
    /// thread count). O(candidates log candidates) heap work plus the gains evaluated.
    void greedy();
    /// Problem (ii): drops orbits whose removal still meets the quality target, last placed first.
    bool prune();
    /// A bound on the gain of a candidate of one ball @p o given the balls placed: the ball's voxels less
    /// those it shares with the placed ball it overlaps most, which are covered (a covered voxel gains
    /// nothing). Volumes stand for voxel counts, as in the first keys, so it is an estimate of that bound,
    /// not a guarantee (0.9 of the lens allows for its surface's rounding); a key below a candidate's gain
    /// delays its evaluation, it does not drop it. A stale key above it is lowered to it without an
    /// evaluation: most of a grain's candidates lie on the ridge beside a placed ball, and their first keys
    /// (the ball's volume) put every one of them through an exact evaluation (a fragment of 15 spheres at
    /// resolution 60: 3232 evaluations, 1718 with this bound; femur 70: 6394 and 4712; the same spheres on
    /// the 143 grains and fragments compared). Orbits of several balls keep their first key.
    double lensBound(const Orbit& o) const;

private:
    using GreedyHeap =
        std::priority_queue<std::pair<double, long long>>; ///< (key, -index): ties to the lower
    static constexpr std::size_t kBatch = 8;
    /// greedy(): the stale entries at the top of @p heap (@p stamp: the placements when each was evaluated;
    /// @p lensStamp: when its key was last set to lensBound) into @p batch, with their gains per ball.
    void takeBatch(GreedyHeap& heap, const std::vector<std::size_t>& stamp,
                   std::vector<std::size_t>& lensStamp, std::vector<long long>& batch,
                   std::vector<double>& gains);
};

} // namespace mss::engine
