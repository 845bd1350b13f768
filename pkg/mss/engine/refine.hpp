// Local refinement of the optimised method: coordinate descent on the exact voxel mismatch.
#pragma once

#include "mss/engine/selection.hpp"

#include <vector>

namespace mss::engine {

/// Moves each chosen orbit's centre and radius while that lowers the mismatch (coordinate descent on the
/// exact voxel objective, eq. 2, steps of 1/2 and 1/4 voxel; moves: a centre coordinate, the radius, a centre
/// coordinate with the radius following E (a slide along the surface), and under a constraint a centre
/// coordinate with the radius grown to touch it). An orbit is revisited in a later sweep only if it or an
/// orbit overlapping it moved in the last one. Departure from the paper, which takes radii from E (eq. 24):
/// radii may exceed E by the discretisation the paper accepts (section 3.5) unless clipping is asked for.
/// @param touched if given, only orbits overlapping one of these start out as candidates for moving
/// @param sweeps at most this many sweeps over the chosen orbits
void refine(Selection& s, const std::vector<Orbit>* touched = nullptr, int sweeps = 3);

} // namespace mss::engine
