// The joint polish of the optimised method: every centre and radius moved together, by gradient ascent on
// a smoothed coverage of the target.
#pragma once

#include "mss/generation/engine/selection.hpp"

namespace mss::engine {

/// What a polish did: its exact mismatch on the generation grid before and after (equal where it was turned
/// down), and the gradient steps taken.
struct PolishReport {
    long long before = 0, after = 0;
    int steps = 0;
};

/// Moves all chosen orbits together. The refinement (refine.hpp) moves one orbit at a time, each to a local
/// optimum of the exact mismatch given the others; a set where two spheres would both have to move to gain
/// (the inner ones inward, the outer ones outward) stops there. Here the objective is the mismatch of a
/// smoothed union, U = 1 - prod_i (1 - u_i) with u_i = sigmoid((r_i - |p - c_i|) / tau) at the voxel centres
/// p (the exact mismatch, eq. 2 on voxels, as tau -> 0), and its gradient moves every centre and radius at
/// once (Adam steps, tau lowered from 1 to 0.3 voxels). Radii stay within the constraint (orbitBound; where a
/// radius touches it, the radius's gradient moves the centre along the bound's own gradient, so a sphere may
/// move away from the surface to grow) and above rMin; coordinates on a mirror plane stay on it, so the
/// symmetry is kept. The set is taken only where the exact mismatch falls: the best of those seen after
/// each tau, else the set as it was.
PolishReport polish(Selection& s);

} // namespace mss::engine
