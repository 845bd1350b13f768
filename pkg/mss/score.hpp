// Scoring any sphere set against a target on a grid of its own (MSS paper section 4.1).
#pragma once

#include "mss/grid.hpp"
#include "mss/mesh.hpp"
#include "mss/planes.hpp"
#include "mss/spheres.hpp"
#include "mss/work.hpp"

#include <cstddef>
#include <cstdint>

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

/// The scores on the exact shapes, estimated by Monte Carlo, each with its standard error.
struct ExactScore {
    double dice = 0.0, diceError = 0.0;                 ///< eq. 27 on the exact sets
    double eta = 0.0, etaError = 0.0;                   ///< eq. 7
    double targetVolume = 0.0, targetVolumeError = 0.0; ///< world units^3
    double sphereVolume = 0.0, sphereVolumeError = 0.0; ///< the union's
    std::size_t samples = 0;
    std::uint64_t seed = 0;
};

/// Scores spheres against the exact grain, not a voxelisation of it: @p samples uniform points of a box that
/// holds both, the same points for the grain (the mesh's winding number; with @p planes, its part on their
/// allowed side) and the spheres. Point i depends on @p seed and i alone (SplitMix64), so a run gives the
/// same figures on any machine and any number of threads. The standard errors are the delta method's; for
/// D they fall as 1 / sqrt(samples). O(samples (log T + spheres per cell)).
/// @throws std::invalid_argument on bad input, samples outside [1000, 1e9], or an estimate over @p maxWork
/// seconds (mss/work.hpp); Interrupted on a stop request.
ExactScore scoreSpheresExact(const TriangleMesh& target, const SphereSet& spheres,
                             std::size_t samples = 1000000, std::uint64_t seed = 1,
                             const std::vector<Plane>& planes = {}, double maxWork = kDefaultMaxWork);

/// The same against a voxel volume, whose exact shape is the union of its solid voxels' cubes.
ExactScore scoreSpheresExact(const VoxelGrid& target, const SphereSet& spheres, std::size_t samples = 1000000,
                             std::uint64_t seed = 1, const std::vector<Plane>& planes = {},
                             double maxWork = kDefaultMaxWork);

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
