// Local refinement of the optimised method: coordinate descent on the exact voxel mismatch.
#pragma once

#include "mss/generation/engine/selection.hpp"

#include <vector>

namespace mss::engine {

/// @p E at the point @p p (voxel coordinates), trilinear between voxel centres.
double trilinear(const ScalarGrid& E, const Vec3& p);

/// Moves each chosen orbit's centre and radius while that lowers the mismatch (coordinate descent on the
/// exact voxel objective, eq. 2, steps of 1/2 and 1/4 voxel; moves: a centre coordinate, the radius, a centre
/// coordinate with the radius following E (a slide along the surface), and under a constraint a centre
/// coordinate with the radius grown to touch it). A sweep after the first revisits an orbit only if it or an
/// orbit overlapping it moved in the sweep before. Coarse first: the sweeps before the last take half-voxel
/// steps only; when they stop moving anything (or at sweeps - 1), a last sweep takes half- then quarter-voxel
/// steps from every orbit the first one considered. The main loop takes two such sweeps where no mirror plane
/// is kept (femur 70: against three sweeps of both steps, D about 1% higher with 38% fewer rows evaluated,
/// about 5% faster). Otherwise every sweep
/// takes both steps, and the sweeps
/// end when one moves nothing: where mirror planes are kept (a different order of moves turned the symmetry
/// repair's trades the other way: ellipsoid 10 at resolution 40 / 50, D 0.0050 / 0.0060 -> 0.0070 / 0.0091),
/// and for trades judged on their refined mismatch. Departure from the paper, which takes radii from E (eq.
/// 24): radii may exceed E by the discretisation the paper accepts (section 3.5) unless clipping is asked
/// for.
/// @param touched if given, only orbits overlapping one of these start out as candidates for moving
/// @param sweeps at most this many sweeps over the chosen orbits
/// @param coarseFirst half-voxel steps only in the sweeps before the last
void refine(Selection& s, const std::vector<Orbit>* touched = nullptr, int sweeps = 3,
            bool coarseFirst = true);

} // namespace mss::engine
