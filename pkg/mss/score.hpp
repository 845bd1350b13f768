// Scoring any sphere set against a target on a grid of its own (MSS paper section 4.1).
#pragma once

#include "mss/grid.hpp"
#include "mss/mesh.hpp"
#include "mss/planes.hpp"
#include "mss/spheres.hpp"

namespace mss {

/// How well a sphere set matches a target, on one scoring grid.
struct Score {
    double dice = 0.0;        ///< Dice mismatch, eq. 27
    double eta = 0.0;         ///< relative mismatch, eq. 7
    double volumeRatio = 0.0; ///< |S~| / |S|
    double coverage = 0.0;    ///< |S ∩ S~| / |S|
    double outside = 0.0;     ///< |S~ \ S| / |S~|: fraction of the spheres' volume outside the target
    std::size_t targetVoxels = 0, sphereVoxels = 0;
    GridSpec grid;
};

/// Scores spheres against a mesh on a grid of @p resolution voxels along the mesh's shortest bounding-box
/// edge, covering the mesh and the spheres, shifted by @p offset voxels along each axis from the centred
/// placement so that a result is not scored on the very voxel centres it was fitted to. @p supersample as in
/// voxelizeMesh. @p planes: the target is its part on their allowed side (a fragment, as generate makes it).
Score scoreSpheres(const TriangleMesh& target, const SphereSet& spheres, int resolution = 100,
                   double offset = 0.37, int supersample = 1, const std::vector<Plane>& planes = {});

/// Scores spheres against a binary volume on the volume's own grid (extended to hold the spheres).
Score scoreSpheres(const VoxelGrid& target, const SphereSet& spheres, const std::vector<Plane>& planes = {});

/// Relative mismatch eq. 7 and Dice mismatch eq. 27 of two volumes on the same grid.
struct Mismatch {
    double eta = 0.0, dice = 0.0;
    std::size_t target = 0, approx = 0, both = 0;
};
Mismatch mismatch(const VoxelGrid& target, const VoxelGrid& approx);
/// The same as mismatch(target, voxelizeSpheres(spheres, target.spec)), without the grid of the spheres: per
/// row, the union of their runs (forBallRows, as voxelizeSpheres) against the target. O(rows of the balls +
/// covered voxels), no memory per voxel.
Mismatch mismatch(const VoxelGrid& target, const SphereSet& spheres);

} // namespace mss
