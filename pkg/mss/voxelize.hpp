// Voxelisation of meshes and sphere unions (MSS paper section 2.2, eq. 5-6).
#pragma once

#include "mss/grid.hpp"
#include "mss/mesh.hpp"
#include "mss/spheres.hpp"
#include "mss/work.hpp"

namespace mss {

/// Default memory limit for grids: 8 GiB (configurable per call).
constexpr std::size_t kDefaultMemoryLimit = std::size_t(8) << 30;

/// How fine a grid to lay over a solid. Give exactly one of voxelSize or resolution.
struct Resolution {
    double voxelSize = 0.0; ///< voxel edge h in world units (> 0), or 0 to use resolution
    int resolution = 0;     ///< voxel count along the shortest bounding-box edge (the paper uses 205), or 0
    int padding = 2;        ///< background layers around the solid; 2 is the double zero hull of eq. 6
    std::size_t memoryLimit = kDefaultMemoryLimit; ///< refuse grids whose working memory would exceed this
};

/// Grid covering the box [lower, upper] with @p res.padding empty layers, centred on the box so that a
/// mirror-symmetric solid gets a mirror-symmetric grid. @throws std::invalid_argument on a bad resolution, a
/// box that is degenerate or non-finite, or a grid over the memory limit (naming the memory it would need).
GridSpec gridForBox(const Vec3& lower, const Vec3& upper, const Resolution& res, const char* where);

/// Binary voxelisation of a closed mesh (paper eq. 5): a voxel is solid when more than half of its
/// @p supersample^3 sample points (a regular sub-lattice; 1 = voxel centre) lie inside the mesh.
/// Inside is decided per sample by the winding number along +x rays (nonzero rule, so inside-out meshes and
/// overlapping closed shells work); a mesh whose triangles are not consistently oriented uses the parity
/// rule. Ray/edge ties are broken by a symbolic perturbation, so rays through shared edges and vertices are
/// counted once (watertight). O(T + N) for T triangles and N voxels; parallel over z slices.
/// A mesh that is not closed (boundary or non-manifold edges) would fool any ray count: there each run
/// between two crossings of a ray is inside when the generalised winding number at its middle is >= 1/2
/// (MeshQuery), and a line saying so is added to @p warnings.
VoxelGrid voxelizeMesh(const TriangleMesh& mesh, const GridSpec& grid, int supersample = 1,
                       std::vector<std::string>* warnings = nullptr);

/// Grid from @p res around the mesh bounding box, then voxelizeMesh. Checks the mesh first. Refused before
/// the rays are cast (std::invalid_argument, naming why): crossings that would not fit @p res.memoryLimit (a
/// triangle soup), and for an open mesh winding-number queries estimated over @p maxWork seconds (work.hpp).
VoxelGrid voxelizeMesh(const TriangleMesh& mesh, const Resolution& res, int supersample = 1,
                       std::vector<std::string>* warnings = nullptr, double maxWork = kDefaultMaxWork);

/// Voxelises the union of spheres (eq. 1) on @p grid: a voxel is set when its centre lies in a sphere
/// (distance <= radius). O(sum of sphere volumes in voxels); parallel over z slices.
VoxelGrid voxelizeSpheres(const SphereSet& spheres, const GridSpec& grid);

/// A user's binary volume made ready for MSS: cropped to its solid voxels and padded with @p padding empty
/// layers (eq. 6), keeping world positions. @throws std::invalid_argument if it has no solid voxel.
VoxelGrid padVoxels(const VoxelGrid& volume, int padding = 2);

/// A labelled voxel volume (a segmented CT): a label per voxel, 0 the background, x fastest.
struct LabelGrid {
    GridSpec spec;
    std::vector<std::int64_t> labels;
};

/// A point of a grain's surface its spheres must reach, with the normal into the grain (where a neighbour
/// touches it in a labelled volume: GenerateOptions::contacts).
struct ContactPoint {
    Vec3 point = Vec3::Zero();
    Vec3 inward = Vec3::UnitZ();
};

/// Two labels in contact: grains whose voxels share faces (a contact gap of 0) or, with a gap tolerance g,
/// whose voxel cubes come within g voxels of each other (real segmentations separate touching grains by a
/// line of background voxels: a marker watershed's lines, the labels of a thresholded scan). The patch is
/// the voxel pairs within the tolerance; the point is the midpoint of a pair at the least gap nearest the
/// centroid of those (on a shared face, or the middle of a separating line); the normal is the mean of the
/// patch's offsets from @p a into @p b. The same for both grains, so that each can reach the same point.
struct LabelContact {
    std::int64_t a = 0, b = 0; ///< a < b
    std::size_t faces = 0;     ///< voxel pairs within the tolerance (shared faces with a tolerance of 0)
    double gap = 0.0;          ///< the least gap between the two grains' voxel cubes, voxels (0: touching)
    Vec3 point = Vec3::Zero();
    Vec3 normal = Vec3::UnitZ();
};

/// The largest contact gap findContacts takes, voxels: its stencil grows as the cube of the gap.
constexpr double kMaxContactGap = 8.0;

/// Every pair of labels in contact, ordered by (a, b): sharing a voxel face (@p gap = 0) or with voxel cubes
/// within @p gap voxels (the default, one voxel, covers watershed lines and labelled binary scans). Visits
/// the boundary voxels only, each against a stencil of O(gap^3) offsets: O(voxels + boundary gap^3).
/// @throws std::invalid_argument for labels that do not fill the grid or a gap outside [0, kMaxContactGap]
std::vector<LabelContact> findContacts(const LabelGrid& volume, double gap = 1.0);

/// findContacts for a volume that does not fit in memory, read in slabs along x: count() every slab, then
/// locate() the same slabs, then contacts(). A slab's layer 0 is the volume's layer @p x0; it owns its
/// layers first .. first + own - 1 and holds margin() more on each side of them where the volume has them
/// (its first slab none before, its last none after). The answer is findContacts' on the whole volume.
class ContactFinder {
public:
    /// @p volume: the whole volume's grid (its dims, voxel edge and origin); @p gap: the tolerance, voxels
    explicit ContactFinder(const GridSpec& volume, double gap = 1.0);
    /// The layers a slab needs beyond those it owns, on each side.
    int margin() const;
    void count(const LabelGrid& slab, long long x0, int first, int own);
    void locate(const LabelGrid& slab, long long x0, int first, int own);
    std::vector<LabelContact> contacts() const;

private:
    struct Pairs;
    GridSpec volume_;
    std::shared_ptr<Pairs> pairs_;
};

/// The contact points of @p label among @p contacts, each with the normal into it.
std::vector<ContactPoint> contactPointsOf(const std::vector<LabelContact>& contacts, std::int64_t label);

} // namespace mss
