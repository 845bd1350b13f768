// Mass properties of solids: meshes, voxel volumes, unions of spheres.
#pragma once

#include "mss/grid.hpp"
#include "mss/mesh.hpp"
#include "mss/spheres.hpp"

#include <Eigen/Core>

namespace mss {

/// Volume, centroid and inertia tensor of a solid of unit density (multiply by the density for mass and
/// inertia).
struct MassProperties {
    double volume = 0.0;
    Vec3 centroid = Vec3::Zero();
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero(); ///< about the centroid, world axes, per unit density

    /// Principal moments (ascending) and axes (columns, a right-handed rotation matrix) of the inertia
    /// tensor.
    void principal(Vec3& moments, Eigen::Matrix3d& axes) const;
};

/// Exact mass properties of a closed triangle mesh by the divergence theorem (Eberly, "Polyhedral Mass
/// Properties (Revisited)", 2002: surface integrals of the monomials up to degree 2). O(T). An inside-out
/// mesh gives the same result. @throws std::invalid_argument on an empty mesh or zero volume.
MassProperties meshMassProperties(const TriangleMesh& mesh);

/// Exact mass properties of a voxel volume: the union of its solid voxels as cubes of edge h.
/// @throws std::invalid_argument if there is no solid voxel.
MassProperties voxelMassProperties(const VoxelGrid& volume);

/// Mass properties of the union of spheres (overlaps counted once), integrated on a grid of @p resolution
/// voxels along the shortest edge of the union's bounding box (voxel centres, each voxel a cube). Error
/// O(h / R) in the volume. @throws std::invalid_argument on bad spheres or resolution.
MassProperties sphereUnionMassProperties(const SphereSet& spheres, int resolution = 200);

/// The volume of the union of spheres (overlaps counted once) to near machine precision: the divergence
/// theorem over each sphere's exposed surface, the arcs its neighbours cover in closed form along each
/// latitude and Gauss-Legendre across them (core/union_volume.cpp). O(n k^3) for k neighbours a sphere (k^2
/// intervals of k caps), after an O(n log n + pairs) sweep. @throws std::invalid_argument on bad spheres.
double sphereUnionVolume(const SphereSet& spheres);

} // namespace mss
