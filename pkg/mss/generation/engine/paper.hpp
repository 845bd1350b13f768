// The MSS paper's procedure as published (sections 3.3-3.5): Method::Paper.
#pragma once

#include "mss/generation/engine/ball.hpp"
#include "mss/generation/engine/request.hpp"
#include "mss/grid.hpp"

#include <vector>

namespace mss::engine {

/// MSS paper, sections 3.3-3.4 as published: spheres at the sub-voxel maxima of E (eq. 23-24), then per
/// iteration at the maxima of E* = 2E - E~ (eq. 25) with radius from E, the minimal distance rule (section
/// 3.4) and the termination criteria (section 3.5). Under a sphere budget the largest values go first.
/// @p bound: the constraint on radii (voxel units), or empty. Cost per iteration: one EDT of the grid.
std::vector<Ball> runPaper(const VoxelGrid& S, const ScalarGrid& E, const Request& opt, Report& m,
                           const BoundVox& bound);

} // namespace mss::engine
