// The MSS generator: a voxelised grain in, a sphere set out (MSS paper sections 3.3-3.5).
#pragma once

#include "mss/grid.hpp"
#include "mss/mesh.hpp"
#include "mss/planes.hpp"
#include "mss/score.hpp"
#include "mss/spheres.hpp"
#include "mss/voxelize.hpp"
#include "mss/work.hpp"

#include <optional>
#include <string>

namespace mss {

/// How spheres are chosen.
enum class Method {
    /// Default. MSS's candidates (sub-voxel maxima of E) plus a denser sampling of the medial ridge of E,
    /// chosen
    /// greedily by the mismatch each removes, then centres and radii tuned to lower the mismatch; mirror
    /// symmetries of the grain are detected and kept. See generate.cpp for where and why this departs from
    /// the paper.
    Optimized,
    /// The paper's procedure as published: maxima of E, then maxima of E* = 2E - Ẽ (eq. 25) per iteration,
    /// with
    /// the minimal distance rule; under a sphere budget the largest values go first.
    Paper,
};

/// What a generation is asked for; the ranges and the command-line and Python spellings are the option
/// table's (mss/options.hpp). Termination criteria (section 3.5), alone or combined: generation stops at the
/// first one met; at least one of nSpheres, eta, dice, rMin must be given.
struct GenerateOptions {
    int nSpheres = 0;  ///< at most this many spheres (problem (i), eq. 2); 0 = no limit
    double eta = 0.0;  ///< stop once the relative mismatch eq. 7 is <= eta (problem (ii), eq. 4); 0 = none
    double dice = 0.0; ///< stop once the Dice mismatch eq. 27 is <= dice; 0 = none
    double rMin = 0.0; ///< no sphere smaller than this radius, world units; 0 = none
    /// no sphere smaller than this many voxels of the generation grid (with rMin: the larger); 0 = none. A
    /// batch's grains share it whatever their grid.
    double rMinVoxels = 0.0;
    int maxIterations = 100; ///< cap on iterations (paper mode) or greedy rounds of refinement (optimized)
    double deltaMin = 1.0;   ///< minimal distance between sphere centres, voxels (paper section 3.4, δmin)
    Method method = Method::Optimized;
    bool keepSymmetry = true; ///< optimized: detect mirror planes of the voxelised grain and keep them
    bool polish = false;      ///< optimized: the joint polish of all centres and radii as the last stage
    int threads = 0;          ///< OpenMP threads; 0 = the default. The result does not depend on it.
    /// No sphere protrudes from the solid (paper section 3.5, exactly): a mesh's spheres get radii at most
    /// the exact distance from their centre to the surface, a sphere whose centre is outside is not placed; a
    /// voxel volume's spheres stay inside the union of its solid voxels (exact distance to the nearest
    /// background voxel cube, voxelClearance).
    bool clip = false;
    /// Largest protrusion of a sphere beyond the grain, world units: every radius is at most the exact
    /// distance from its centre to the mesh surface (voxels: to the nearest background voxel's cube) plus
    /// this, and no centre lies outside, so no point of a sphere is farther than this from the grain.
    /// Unset (the default): one voxel of the generation grid, the discretisation tolerance the paper accepts
    /// (section 3.5). 0 is the same as clip. +infinity: unbounded, radii grow past the grain wherever that
    /// lowers the voxel mismatch (the behaviour before this option; bumps of several voxels).
    std::optional<double> maxProtrusion;
    /// With clip or a finite maxProtrusion: choose and tune spheres under the constraint, so that coverage
    /// lost to clipping is regained (optimized: from nothing and from the free optimum cut down, the better
    /// kept; paper: the MSS iterations continue with the clipped spheres). Without: generate freely, then
    /// shrink the radii (and drop spheres whose centre is outside).
    bool refill = true;
    std::vector<Plane>
        planes; ///< planes no sphere may cross (system walls, a fragmentation plane), always applied
    /// Points of the grain's surface the spheres must hold, a twentieth of a voxel deep (the contacts of a
    /// labelled volume's grain with its neighbours, findContacts): where none does, the largest ball through
    /// the point from inside along its normal that protrudes at most half a voxel (and no more than the
    /// protrusion bound) is added.
    std::vector<ContactPoint> contacts;
    /// The grain's neighbours (a labelled volume's other grains near it, any grid: non-zero where one is),
    /// for neighbourProtrusion. Empty (no voxels): none.
    VoxelGrid neighbours;
    /// The share of the protrusion bound a sphere may reach into a neighbour: 0.5 keeps two neighbours'
    /// clumps from overlapping by more than the bound, at a cost in D where grains share much of their
    /// surface; 1: the bound as elsewhere.
    double neighbourProtrusion = 1.0;
    /// Seconds: a generation estimated to take longer is refused before it starts (mss/work.hpp).
    double maxWork = kDefaultMaxWork;
};

/// Figures of a generation, on the generation grid.
struct Metrics {
    std::size_t spheres = 0;
    double eta = 0.0;  ///< relative mismatch, eq. 7
    double dice = 0.0; ///< Dice mismatch, eq. 27
    int iterations = 0;
    std::size_t solidVoxels = 0;  ///< sum of S
    std::size_t sphereVoxels = 0; ///< sum of S~
    int symmetryPlanes = 0;       ///< mirror planes detected and kept (optimized mode)
    std::size_t clipped = 0;      ///< spheres whose radius the final clipping reduced
    /// Largest protrusion beyond the grain, world units, an upper bound: max over spheres of the radius minus
    /// the exact distance from the centre to the surface (mesh) or to the nearest background voxel's cube.
    double protrusion = 0.0;
    double protrusionLimit = 0.0; ///< the bound that applied (maxProtrusion resolved; +inf: unbounded)
    /// The smallest radius, world units: it sets a DEM time step (a linear contact's sqrt(m / k) ~ r sqrt(rho
    /// / E), YADE's PWaveTimeStep).
    double smallestRadius = 0.0;
    /// The largest inscribed radius (the EDT's maximum), world units: how thick the grain is.
    double inscribedRadius = 0.0;
    std::size_t contacts = 0;          ///< contact points asked (GenerateOptions::contacts)
    std::size_t contactsAdded = 0;     ///< spheres added to reach them
    std::size_t contactsMissed = 0;    ///< points no ball under the bounds could reach
    std::vector<std::string> warnings; ///< what was wrong with the input and how it was handled
    double secondsRead = 0.0, secondsVoxelize = 0.0, secondsEdt = 0.0, secondsSelect = 0.0,
           secondsRefine = 0.0, secondsTotal = 0.0;
};

/// The result: spheres in world units, the metrics, and the grid used.
struct Result {
    SphereSet spheres;
    Metrics metrics;
    GridSpec grid;
};

/// Generates spheres for a binary volume. The volume is cropped and padded to the double zero hull of eq. 6
/// automatically. @throws std::invalid_argument on empty input or bad options.
Result generate(const VoxelGrid& volume, const GenerateOptions& options);

/// Voxelises the mesh (section 2.2, with @p supersample^3 samples per voxel) and generates spheres.
Result generate(const TriangleMesh& mesh, const Resolution& resolution, const GenerateOptions& options,
                int supersample = 1);

/// The protrusion bound that applies on a grid of voxel edge @p h: 0 with clip, else maxProtrusion, else @p
/// h.
double protrusionLimit(const GenerateOptions& options, double h);

/// Checks options; throws std::invalid_argument naming the bad value.
void validateOptions(const GenerateOptions& options);

} // namespace mss
