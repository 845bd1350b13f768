// Comparing sphere sets from any generator with a grain: frames, alignment, the figures of one table row.
#pragma once

#include "mss/mass.hpp"
#include "mss/score.hpp"
#include "mss/work.hpp"

#include <string>

namespace mss {

/// How a sphere set is registered to the grain before it is scored.
enum class Align {
    None,        ///< as written
    Centroid,    ///< the union's centre of mass onto the grain's
    BoundingBox, ///< the centre of the spheres' bounding box onto the grain's
    Principal,   ///< centroids and principal axes; of the four proper sign choices the one of least D
};
/// "none", "centroid", "bbox", "principal". @throws std::invalid_argument naming the choices.
Align parseAlign(const std::string& name);

/// x -> rotation x + translation.
struct RigidTransform {
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
    Vec3 translation = Vec3::Zero();
};
SphereSet transformSpheres(const SphereSet& s, const RigidTransform& t);

struct CompareOptions {
    int resolution = 100; ///< scoring grid of a mesh: voxels along its shortest edge
    double offset = 0.37; ///< its shift, in voxels
    int supersample = 1;
    std::vector<Plane> planes; ///< the target is the grain's part on their allowed side
    /// Registration of a set in another frame (under half its volume inside the grain's bounding box); a set
    /// in the grain's frame is scored as written whatever this says.
    Align align = Align::None;
    /// Without alignment: refuse a set most of whose volume lies outside the grain's bounding box (another
    /// frame). Off: score it as written all the same ("--align none").
    bool checkFrame = true;
    int protrusionSamples = 400;      ///< points per sphere surface for the largest protrusion
    bool exact = false;               ///< also score on the exact shapes (scoreSpheresExact)
    std::size_t samples = 1000000;    ///< its Monte Carlo points
    std::uint64_t seed = 1;           ///< and their seed
    double maxWork = kDefaultMaxWork; ///< seconds: refuse heavier requests before they start (work.hpp)
};

/// One row of a comparison: the score (eq. 7, 27) and what a DEM user checks besides.
struct Comparison {
    Score score;
    std::size_t spheres = 0;
    double protrusion = 0.0; ///< largest distance of a sphere's surface point outside the grain (world)
    std::vector<double> sphereProtrusion; ///< the same for each sphere
    double smallestRadius = 0.0;          ///< world units
    double massError = 0.0;               ///< (V_union - V) / V
    double centroidError = 0.0;           ///< |c_union - c| / the grain's bounding-box diagonal
    double inertiaError = 0.0;            ///< ||I_union - I|| / ||I|| (Frobenius, about each one's centroid)
    double insideBox = 0.0;   ///< share of the spheres' volume inside the grain's bounding box, as given
    RigidTransform transform; ///< applied before scoring (identity without alignment)
    ExactScore exact;         ///< with CompareOptions::exact (else samples 0)
};

/// Compares a sphere set with a mesh. Without alignment, a set most of whose volume (over half) lies outside
/// the grain's bounding box is refused with a message that suggests --align: it is in another frame.
/// Protrusion: sampled points (Fibonacci spiral, @p protrusionSamples per sphere) outside the mesh (winding
/// number), their exact distance to it; spheres inside by their clearance are skipped.
/// @throws std::invalid_argument on bad input or a set in another frame.
Comparison compareSpheres(const TriangleMesh& target, const SphereSet& spheres, const CompareOptions& o);

/// The same against a voxel volume (the union of its solid voxels' cubes); protrusion to within half a voxel
/// (distance of outside sample points to the nearest solid voxel centre, less half a voxel).
Comparison compareSpheres(const VoxelGrid& target, const SphereSet& spheres, const CompareOptions& o);

} // namespace mss
