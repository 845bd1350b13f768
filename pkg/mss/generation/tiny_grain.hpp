#pragma once
// A grain of a few voxels that the choice leaves without a sphere (internal to the generation).

#include "mss/generate.hpp"
#include "mss/grid.hpp"

#include <functional>

namespace mss {

/// Where the choice left nothing on a grain of a few voxels (one voxel: a ball of radius E = 1 covers its six
/// neighbours too, so no ball lowers the mismatch), one sphere of the grain's volume at the solid voxel of
/// the largest E nearest its centroid, under the bound and at least rMin; nothing where those forbid it. A
/// batch's specimen holds such grains (watershed fragments), and a grain without spheres lost its contacts.
void oneSphereOfItsVolume(const VoxelGrid& S, const ScalarGrid& E,
                          const std::function<double(const Vec3&)>& bound, double rMin, SphereSet& out,
                          Metrics& m);

} // namespace mss
