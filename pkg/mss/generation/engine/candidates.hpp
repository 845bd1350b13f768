// Candidate spheres of the optimised method: MSS's sub-voxel maxima of E and a sampling of E's medial ridge.
#pragma once

#include "mss/generation/engine/symmetry.hpp"

#include <vector>

namespace mss::engine {

/// Candidate orbits, in a deterministic order: first the sub-voxel maxima of E (paper eq. 23-24), then the
/// medial ridge of E (voxels where no face neighbour is more than half a voxel higher; on a slope of the
/// distance field one neighbour is about one voxel higher), thinned to at most 10,000 evenly along the
/// voxel order. Each is an orbit under @p sym, one per canonical position (on a 1/8-voxel key); radii below
/// @p rMinVox are dropped. Departure from the paper: the ridge candidates, which let the greedy choose
/// spheres the paper's iteration would reach only through E* (eq. 25). O(voxels).
/// @param ridgeCount if given, receives the ridge's size before thinning
std::vector<Orbit> candidateOrbits(const ScalarGrid& E, const Symmetry& sym, double rMinVox,
                                   std::size_t* ridgeCount = nullptr);

} // namespace mss::engine
