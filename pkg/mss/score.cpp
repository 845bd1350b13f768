#include "mss/score.hpp"
#include "mss/generate.hpp"
#include "mss/voxelize.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace mss {

namespace {
Score fromMismatch(const Mismatch& m, const GridSpec& g) {
    Score s;
    s.dice = m.dice;
    s.eta = m.eta;
    s.targetVoxels = m.target;
    s.sphereVoxels = m.approx;
    s.volumeRatio = m.target ? double(m.approx) / double(m.target) : 0.0;
    s.coverage = m.target ? double(m.both) / double(m.target) : 0.0;
    s.outside = m.approx ? double(m.approx - m.both) / double(m.approx) : 0.0;
    s.grid = g;
    return s;
}
} // namespace

Score scoreSpheres(const TriangleMesh& target, const SphereSet& spheres, int resolution, double offset,
                   int supersample, const std::vector<Plane>& planes) {
    validateMesh(target, "scoreSpheres");
    validateSpheres(spheres, "scoreSpheres");
    if (resolution < 1)
        throw std::invalid_argument("scoreSpheres: resolution must be >= 1, got " +
                                    std::to_string(resolution));
    // a grid shifted by 1e300 voxels scored D 0 (nothing on it): the offset is a fraction of a voxel
    if (!(offset >= 0.0) || !(offset < 1.0)) {
        std::ostringstream os;
        os << "scoreSpheres: offset must be in [0, 1) voxel, got " << offset;
        throw std::invalid_argument(os.str());
    }
    const MeshInfo info = analyzeMesh(target);
    Vec3 lo = info.lower, hi = info.upper;
    for (std::size_t i = 0; i < spheres.size(); ++i) {
        lo = lo.cwiseMin(spheres.centers[i] - Vec3::Constant(spheres.radii[i]));
        hi = hi.cwiseMax(spheres.centers[i] + Vec3::Constant(spheres.radii[i]));
    }
    Resolution res;
    res.voxelSize = (info.upper - info.lower).minCoeff() / resolution;
    if (!(res.voxelSize > 0.0)) throw std::invalid_argument("scoreSpheres: the target mesh is flat");
    GridSpec g = gridForBox(lo, hi, res, "scoreSpheres");
    g.origin += Vec3::Constant(offset * g.h);
    VoxelGrid S = voxelizeMesh(target, g, supersample);
    if (!planes.empty()) S = cutVoxelsByPlanes(S, planes);
    const VoxelGrid St = voxelizeSpheres(spheres, g);
    return fromMismatch(mismatch(S, St), g);
}

Score scoreSpheres(const VoxelGrid& target, const SphereSet& spheres, const std::vector<Plane>& planes) {
    validateSpheres(spheres, "scoreSpheres");
    if (target.size() == 0 || target.size() != target.spec.size())
        throw std::invalid_argument("scoreSpheres: the target volume is empty");
    // extend the volume's grid by whole voxels so that it holds every sphere
    const GridSpec& t = target.spec;
    std::array<int, 3> lo{0, 0, 0}, hi{t.dims[0] - 1, t.dims[1] - 1, t.dims[2] - 1};
    for (std::size_t i = 0; i < spheres.size(); ++i) {
        const Vec3 a = t.toVoxel(spheres.centers[i] - Vec3::Constant(spheres.radii[i]));
        const Vec3 b = t.toVoxel(spheres.centers[i] + Vec3::Constant(spheres.radii[i]));
        for (int d = 0; d < 3; ++d) {
            lo[d] = std::min(lo[d], int(std::floor(a[d])) - 1);
            hi[d] = std::max(hi[d], int(std::ceil(b[d])) + 1);
        }
    }
    GridSpec g;
    g.h = t.h;
    g.origin = t.toWorld(Vec3(lo[0], lo[1], lo[2]));
    std::array<long long, 3> dims{};
    for (int d = 0; d < 3; ++d) dims[d] = hi[d] - lo[d] + 1;
    checkGridSize("scoreSpheres", dims, 2, kDefaultMemoryLimit);
    for (int d = 0; d < 3; ++d) g.dims[d] = int(dims[d]);
    VoxelGrid S(g, 0);
    for (int k = 0; k < t.dims[2]; ++k)
        for (int j = 0; j < t.dims[1]; ++j)
            for (int i = 0; i < t.dims[0]; ++i) S(i - lo[0], j - lo[1], k - lo[2]) = target(i, j, k) ? 1 : 0;
    if (!planes.empty()) S = cutVoxelsByPlanes(S, planes);
    return fromMismatch(mismatch(S, voxelizeSpheres(spheres, g)), g);
}

} // namespace mss
