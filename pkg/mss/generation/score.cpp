#include "mss/score.hpp"
#include "mss/core/ball_rows.hpp"
#include "mss/generate.hpp"
#include "mss/voxelize.hpp"

#include <cmath>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <vector>

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

Mismatch mismatch(const VoxelGrid& target, const VoxelGrid& approx) {
    if (target.spec.dims != approx.spec.dims) throw std::invalid_argument("mismatch: grids differ in size");
    Mismatch m;
    for (std::size_t q = 0; q < target.size(); ++q) {
        const bool a = target.data[q] != 0, b = approx.data[q] != 0;
        m.target += a;
        m.approx += b;
        m.both += a && b;
    }
    const std::size_t diff = m.target + m.approx - 2 * m.both;
    m.eta = m.target ? double(diff) / double(m.target) : 0.0;                          // eq. 7
    m.dice = (m.target + m.approx) ? double(diff) / double(m.target + m.approx) : 0.0; // eq. 27
    return m;
}

Mismatch mismatch(const VoxelGrid& target, const SphereSet& spheres) {
    if (target.data.size() != target.spec.size() || target.data.empty())
        throw std::invalid_argument("mismatch: the target's values do not fill its grid");
    validateSpheres(spheres, "mismatch");
    const GridSpec& g = target.spec;
    std::vector<Vec3> c(spheres.size());
    std::vector<double> r(spheres.size());
    std::vector<std::size_t> meets;
    for (std::size_t s = 0; s < c.size(); ++s) {
        c[s] = g.toVoxel(spheres.centers[s]);
        r[s] = spheres.radii[s] / g.h;
        bool in = true; // as voxelizeSpheres: spheres wholly outside the grid are dropped before index maths
        for (int a = 0; a < 3; ++a) in = in && c[s][a] + r[s] >= 0.0 && c[s][a] - r[s] <= g.dims[a] - 1.0;
        if (in) meets.push_back(s);
    }
    Mismatch m;
    m.target = countSolid(target);
    long long approx = 0, both = 0;
#pragma omp parallel reduction(+ : approx, both)
    {
        // one slice's cover by the spheres, a byte a voxel (a row cleared when the slice first meets it),
        // then counted a row at a time: sorting and merging each slice's runs was half of it, and this is
        // about 5x faster
        const std::size_t nx = std::size_t(g.dims[0]);
        std::vector<std::uint8_t> cover(nx * std::size_t(g.dims[1]));
        std::vector<int> rowSlice(std::size_t(g.dims[1]), -1); // the slice whose cover a row holds
#pragma omp for schedule(dynamic, 1)
        for (int k = 0; k < g.dims[2]; ++k) {
            int j0 = g.dims[1], j1 = -1;
            for (std::size_t s : meets)
                detail::forBallRows(c[s], r[s], g.dims, k, k, [&](int j, int, int i0, int i1) {
                    std::uint8_t* on = cover.data() + std::size_t(j) * nx;
                    if (rowSlice[std::size_t(j)] != k) {
                        std::fill_n(on, nx, std::uint8_t(0));
                        rowSlice[std::size_t(j)] = k;
                        j0 = std::min(j0, j);
                        j1 = std::max(j1, j);
                    }
                    std::fill(on + i0, on + i1 + 1, std::uint8_t(1));
                });
            for (int j = j0; j <= j1; ++j) {
                if (rowSlice[std::size_t(j)] != k) continue;
                const std::uint8_t* on = cover.data() + std::size_t(j) * nx;
                const std::uint8_t* row = &target(0, j, k);
                int rowApprox = 0, rowBoth = 0;
                for (std::size_t i = 0; i < nx; ++i) { // vectorised
                    rowApprox += on[i];
                    rowBoth += on[i] & (row[i] != 0);
                }
                approx += rowApprox;
                both += rowBoth;
            }
        }
    }
    m.approx = std::size_t(approx);
    m.both = std::size_t(both);
    const std::size_t diff = m.target + m.approx - 2 * m.both;
    m.eta = m.target ? double(diff) / double(m.target) : 0.0;                          // eq. 7
    m.dice = (m.target + m.approx) ? double(diff) / double(m.target + m.approx) : 0.0; // eq. 27
    return m;
}

} // namespace mss
