// The optimised method (Method::Optimized): candidates, greedy selection, refinement, pruning, symmetry
// repair.
#pragma once

#include "mss/generation/engine/selection.hpp"

#include <vector>

namespace mss::engine {

/// Chooses spheres for the target @p S with EDT @p E (see the comment at generate() in generate.cpp for how
/// and why this departs from the paper). @p bound: the constraint on radii (voxel units), or empty.
/// @param start a warm start (orbits found without the constraint), cut down to it
/// @param orbitsOut if given, receives the orbits chosen; @p mismatchOut the final voxel mismatch
/// @param secondsRefine time spent in refinement, added to
/// @param shared candidates shared by runs on the same grain and options (see Selection)
std::vector<Ball> runOptimized(const VoxelGrid& S, const ScalarGrid& E, const Request& opt,
                               const BoundVox& bound, Report& m, double& secondsRefine,
                               const std::vector<Orbit>& start = {}, std::vector<Orbit>* orbitsOut = nullptr,
                               long long* mismatchOut = nullptr, SharedCandidates* shared = nullptr);

} // namespace mss::engine
