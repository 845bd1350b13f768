// Distance and inside queries against a mesh and a voxel volume: the clearance that bounds radii (paper
// section 3.5, with exact distances), and the mesh checks of mss info.
#pragma once

#include "mss/mesh.hpp"
#include "mss/planes.hpp"

#include <memory>

namespace mss {

/// Clearance of a point in a voxel volume: the exact distance from @p c (continuous voxel coordinates of
/// @p solid's grid) to the nearest background voxel's cube [b - 1/2, b + 1/2]^3, cells outside the grid
/// counting as background; -1 when the voxel holding @p c is background. A ball of that radius around @p c
/// stays in the union of the solid voxels' cubes (voxel accuracy). @p edt: the distance
/// transform of
/// @p solid (eq. 8, distance to the nearest background centre), which confines the search to a shell: every
/// background centre is at least E(v) - |c - v| from c, and the nearest cube within E(v) + |c - v|, so only
/// centres between those radii (the outer one widened by the half diagonal) are looked at: O(E^2) voxels.
double voxelClearance(const VoxelGrid& solid, const ScalarGrid& edt, const Vec3& c);

/// Distance and inside queries against a triangle mesh.
///
/// distance(): exact Euclidean distance to the nearest point of any triangle, by branch and bound over a box
/// hierarchy of the triangles, the previous query's nearest triangle (per thread) as the first bound
/// (O(log T) typical; on a medial surface, where much of a smooth surface is nearly equidistant, more).
/// winding(): the generalised winding number (Jacobson, Kavan and Sorkine-Hornung, "Robust inside-outside
/// segmentation using generalized winding numbers", SIGGRAPH 2013), the sum of the triangles' signed solid
/// angles over 4 pi (Van Oosterom and Strackee 1983), evaluated with the hierarchical dipole approximation of
/// Barill et al. ("Fast winding numbers for soups and clouds", SIGGRAPH 2018) for far clusters: 1 inside a
/// closed mesh, 0 outside, and a smooth value across the holes of an open one. inside() thresholds |winding|
/// at 1/2, so inside-out meshes work too.
class MeshQuery {
public:
    explicit MeshQuery(const TriangleMesh& mesh);
    ~MeshQuery();
    MeshQuery(const MeshQuery&) = delete;
    MeshQuery& operator=(const MeshQuery&) = delete;

    double distance(const Vec3& p) const;
    /// Whether every point of the surface is farther than @p t from @p p (distance(p) > t), decided without
    /// the distance itself: the branch and bound prunes at t and stops at the first nearer triangle. Far
    /// cheaper than distance() where t lies well below it: from deep inside a smooth surface, the exact
    /// query must visit every part of it that is nearly as near (the ellipsoid's axis: a ring of triangles).
    bool fartherThan(const Vec3& p, double t) const;
    double winding(const Vec3& p) const;
    bool inside(const Vec3& p) const { return std::abs(winding(p)) >= 0.5; }
    /// Exact winding number, O(T): for tests of the approximation.
    double windingExact(const Vec3& p) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// Number of pairs of triangles that intersect without sharing a vertex (self-intersections), through an AABB
/// tree: O(T log T) typical. Stops counting at @p limit. Triangles piled on each other (a face repeated
/// thousands of times) make every query meet them all: past 20,000,000 candidate pairs it throws
/// std::invalid_argument saying so, rather than run for hours.
std::size_t countSelfIntersections(const TriangleMesh& mesh, std::size_t limit = 1000000);

} // namespace mss
