#pragma once
// Contacts of a labelled volume's grain inside the generation (GenerateOptions::contacts, neighbours,
// neighbourProtrusion): its neighbours' clearance, the bound with their share, the balls that reach a
// contact.

#include "mss/generate.hpp"
#include "mss/grid.hpp"

#include <functional>
#include <memory>

namespace mss {

/// The distance (world units) from a point to the nearest voxel cube of a grain's neighbours
/// (GenerateOptions::neighbours): the clearance of their complement, padded so that the grid's edge is no
/// neighbour; +inf off that grid.
class NeighbourClearance {
public:
    explicit NeighbourClearance(const VoxelGrid& neighbours);
    /// At least this far (world units), from the nearest voxel centre's distance transform alone.
    double lower(const Vec3& c) const;
    double operator()(const Vec3& c) const;

private:
    std::shared_ptr<VoxelGrid> free_;
    std::shared_ptr<ScalarGrid> edt_;
};

/// @p bound with the neighbours' share of the protrusion bound: r <= their clearance + share H. The exact
/// clearance only where the cheap lower bound cannot tell (most centres are far from every neighbour).
std::function<double(const Vec3&)> withNeighbours(std::function<double(const Vec3&)> bound,
                                                  const std::shared_ptr<NeighbourClearance>& n, double H,
                                                  double share);

/// GenerateOptions::contacts: each point where a neighbour touches the grain lies inside the spheres by a
/// twentieth of a voxel, so that two grains that touch in the volume overlap there in the assembly. Where no
/// sphere holds it, the largest ball through it from the grain's side is added: its centre a solid voxel's
/// (or a point on the patch's mean normal), its radius the distance to the point plus h / 20, under the
/// clearance plus the protrusion bound (the neighbours' share of it) and the planes, so that it makes no bump
/// beyond the bound; at least rMin and half a voxel, or the point is counted missed. @p S, @p E: the grain's
/// voxels and distance transform; @p clearance: its clearance (world units, signed).
void reachContacts(SphereSet& spheres, const GenerateOptions& opt, const VoxelGrid& S, const ScalarGrid& E,
                   const std::function<double(const Vec3&)>& clearance, double H,
                   const std::shared_ptr<NeighbourClearance>& neighbours, Metrics& m);

} // namespace mss
