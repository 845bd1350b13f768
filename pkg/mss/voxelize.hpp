// Voxelisation of meshes and sphere unions (MSS paper section 2.2, eq. 5-6).
#pragma once

#include "mss/grid.hpp"
#include "mss/mesh.hpp"
#include "mss/spheres.hpp"

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

/// Grid from @p res around the mesh bounding box, then voxelizeMesh. Checks the mesh first.
VoxelGrid voxelizeMesh(const TriangleMesh& mesh, const Resolution& res, int supersample = 1,
                       std::vector<std::string>* warnings = nullptr);

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

/// Two labels whose voxels share faces: how many, the one shared face nearest the centroid of them all (its
/// centre, on both grains' surfaces) and the mean normal of their faces from @p a into @p b. The same for
/// both grains, so that each can reach the same point.
struct LabelContact {
    std::int64_t a = 0, b = 0; ///< a < b
    std::size_t faces = 0;
    Vec3 point = Vec3::Zero();
    Vec3 normal = Vec3::UnitZ();
};

/// Every pair of labels in contact (sharing a voxel face), ordered by (a, b).
std::vector<LabelContact> findContacts(const LabelGrid& volume);

/// findContacts for a volume that does not fit in memory, read in slabs along x: count() every slab, then
/// locate() the same slabs, then contacts(). A slab holds layers x0 .. x0 + n - 1 of the volume; all but the
/// last slab end with one layer more than they own (@p own = n - 1), the first layer of the next. The answer
/// is findContacts' on the whole volume.
class ContactFinder {
public:
    /// @p volume: the whole volume's grid (its dims, voxel edge and origin)
    explicit ContactFinder(const GridSpec& volume);
    void count(const LabelGrid& slab, long long x0, int own);
    void locate(const LabelGrid& slab, long long x0, int own);
    std::vector<LabelContact> contacts() const;

private:
    struct Pairs;
    GridSpec volume_;
    std::shared_ptr<Pairs> pairs_;
};

/// The contact points of @p label among @p contacts, each with the normal into it.
std::vector<ContactPoint> contactPointsOf(const std::vector<LabelContact>& contacts, std::int64_t label);

} // namespace mss
