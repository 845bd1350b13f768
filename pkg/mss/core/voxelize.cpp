#include "mss/voxelize.hpp"
#include "mss/core/ball_rows.hpp"
#include "mss/core/mesh_query.hpp"
#include "mss/work.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <stdexcept>

namespace mss {

GridSpec gridForBox(const Vec3& lower, const Vec3& upper, const Resolution& res, const char* where) {
    const std::string w = where;
    if (!lower.allFinite() || !upper.allFinite())
        throw std::invalid_argument(w + ": bounding box is not finite");
    const bool hasSize = res.voxelSize != 0.0, hasRes = res.resolution != 0;
    if (hasSize == hasRes) {
        std::ostringstream os;
        os << w << ": give exactly one of a voxel size > 0 and a resolution >= 1, got voxel size "
           << res.voxelSize << " and resolution " << res.resolution;
        throw std::invalid_argument(os.str());
    }
    if (hasSize && !(res.voxelSize > 0.0 && std::isfinite(res.voxelSize))) {
        std::ostringstream os;
        os << w << ": voxel size must be > 0 and finite, got " << res.voxelSize;
        throw std::invalid_argument(os.str());
    }
    if (hasRes && res.resolution < 1)
        throw std::invalid_argument(w + ": resolution must be >= 1 voxel along the shortest edge, got " +
                                    std::to_string(res.resolution));
    if (res.padding < 0) throw std::invalid_argument(w + ": padding must be >= 0");
    const Vec3 extent = upper - lower;
    const double shortest = extent.minCoeff();
    if (!(shortest > 0.0)) {
        std::ostringstream os;
        os << w << ": the solid is flat (bounding box " << extent.x() << " x " << extent.y() << " x "
           << extent.z() << "); it has no volume to fill";
        throw std::invalid_argument(os.str());
    }
    GridSpec g;
    g.h = hasSize ? res.voxelSize : shortest / res.resolution;
    if (!(g.h > 0.0) || !std::isfinite(g.h)) throw std::invalid_argument(w + ": voxel size underflows");
    auto dimsFor = [&](double h) {
        std::array<long long, 3> d{};
        for (int a = 0; a < 3; ++a) {
            const double cells = std::min(4e9, std::ceil(extent[a] / h - 1e-9));
            d[a] = std::max(1LL, static_cast<long long>(cells)) + 2LL * res.padding;
        }
        return d;
    };
    auto bytesFor = [&](double h) {
        const auto d = dimsFor(h);
        return static_cast<long double>(d[0]) * d[1] * d[2] * kBytesPerVoxelGenerate;
    };
    const std::array<long long, 3> dims = dimsFor(g.h);
    if (bytesFor(g.h) > static_cast<long double>(res.memoryLimit) ||
        static_cast<long double>(dims[0]) * dims[1] * dims[2] > 2147483647.0L) {
        // the memory guard: refuse before allocating, and say what would fit
        std::ostringstream os;
        os.precision(4);
        os << w << ": a grid of " << dims[0] << "x" << dims[1] << "x" << dims[2] << " voxels would need "
           << static_cast<double>(bytesFor(g.h) / 1073741824.0L) << " GiB";
        if (bytesFor(g.h) > static_cast<long double>(res.memoryLimit))
            os << ", over the limit of " << static_cast<double>(res.memoryLimit) / 1073741824.0 << " GiB";
        else // what stops it is the count, not the memory ("931 GiB, over the limit of 1.02e+03 GiB" said)
            os << " and has over 2^31 - 1 voxels, more than a grid can index";
        long long lo = 0, hi = hasRes ? res.resolution : static_cast<long long>(std::ceil(shortest / g.h));
        while (lo < hi) { // largest resolution that fits
            const long long mid = (lo + hi + 1) / 2;
            const double h = shortest / double(mid);
            const auto d = dimsFor(h);
            if (bytesFor(h) <= static_cast<long double>(res.memoryLimit) &&
                static_cast<long double>(d[0]) * d[1] * d[2] <= 2147483647.0L)
                lo = mid;
            else
                hi = mid - 1;
        }
        if (lo >= 1) os << "; resolution " << lo << " (voxel size " << shortest / double(lo) << ") would fit";
        throw std::invalid_argument(os.str());
    }
    for (int a = 0; a < 3; ++a) g.dims[a] = static_cast<int>(dims[a]);
    const Vec3 center = 0.5 * (lower + upper);
    g.origin = center - 0.5 * g.h * Vec3(g.dims[0] - 1, g.dims[1] - 1, g.dims[2] - 1);
    return g;
}

namespace {

struct Hit {
    std::uint32_t column;
    float x; // crossing position along x, voxel units
    int sign;
};

/// Edge function of sample p against edge a->b in the (y, z) plane, with Simulation of Simplicity:
/// p is taken as p + (eps, eps^2), so an exact zero is resolved the same way by every triangle sharing the
/// edge (antisymmetric in a, b) and at shared vertices. Computed from the lexicographically smaller end so
/// that the value is exactly antisymmetric in floating point.
inline double edgeFunction(double ay, double az, double by, double bz, double py, double pz) {
    bool swapped = (ay > by) || (ay == by && az > bz);
    if (swapped) {
        std::swap(ay, by);
        std::swap(az, bz);
    }
    double w = (by - ay) * (pz - az) - (bz - az) * (py - ay);
    if (w == 0.0) {
        // d/d eps of w for p + (eps, eps^2): -(bz - az), then (by - ay)
        w = (bz != az) ? -(bz - az) : (by - ay);
    }
    return swapped ? -w : w;
}

/// The crossings of the x-rays through every sub-sample (J, K) of the (y, z) plane with the triangles
/// (voxel coordinates @p v of the mesh's vertices), sorted by column; @p start: each column's first hit.
/// O(triangles + rays crossed). The triangles in 16 parts on the threads (about 1.8x faster on 2); within a
/// column the hits are sorted later by position, and hits equal in column, position and sign are alike, so
/// the result does not depend on the parts or the threads.
std::vector<Hit> rayHits(const TriangleMesh& mesh, const std::vector<Vec3>& v, int s, int NY, int NZ,
                         std::vector<std::uint32_t>& start) {
    const std::size_t nColumns = static_cast<std::size_t>(NY) * NZ;
    auto subCoord = [s](long long J) { return (J + 0.5) / s - 0.5; };
    constexpr int kParts = 16;
    const std::size_t nt = mesh.triangles.size();
    std::vector<std::vector<Hit>> parts(kParts);
#pragma omp parallel for schedule(dynamic, 1) if (nt >= 4096)
    for (int part = 0; part < kParts; ++part) {
        std::vector<Hit>& hits = parts[std::size_t(part)];
        hits.reserve((nColumns * 2 + 1024) / kParts);
        const std::size_t t0 = nt * std::size_t(part) / kParts, t1 = nt * std::size_t(part + 1) / kParts;
        for (std::size_t q = t0; q < t1; ++q) {
            const auto& t = mesh.triangles[q];
            const Vec3 &a = v[t[0]], &b = v[t[1]], &c = v[t[2]];
            const double det = (b.y() - a.y()) * (c.z() - a.z()) - (b.z() - a.z()) * (c.y() - a.y());
            if (det == 0.0) continue; // parallel to the rays: never crossed
            const double ylo = std::min({a.y(), b.y(), c.y()}), yhi = std::max({a.y(), b.y(), c.y()});
            const double zlo = std::min({a.z(), b.z(), c.z()}), zhi = std::max({a.z(), b.z(), c.z()});
            const long long J0 = std::max(0LL, static_cast<long long>(std::ceil((ylo + 0.5) * s - 0.5)));
            const long long J1 =
                std::min<long long>(NY - 1, static_cast<long long>(std::floor((yhi + 0.5) * s - 0.5)));
            const long long K0 = std::max(0LL, static_cast<long long>(std::ceil((zlo + 0.5) * s - 0.5)));
            const long long K1 =
                std::min<long long>(NZ - 1, static_cast<long long>(std::floor((zhi + 0.5) * s - 0.5)));
            const int sign = det > 0 ? -1 : 1; // outward normal along -x: the ray enters
            for (long long K = K0; K <= K1; ++K) {
                const double pz = subCoord(K);
                for (long long J = J0; J <= J1; ++J) {
                    const double py = subCoord(J);
                    // barycentric weights (up to the common factor det) from the edges opposite each corner
                    double wa = edgeFunction(b.y(), b.z(), c.y(), c.z(), py, pz);
                    double wb = edgeFunction(c.y(), c.z(), a.y(), a.z(), py, pz);
                    double wc = edgeFunction(a.y(), a.z(), b.y(), b.z(), py, pz);
                    const bool inside = det > 0 ? (wa > 0 && wb > 0 && wc > 0) : (wa < 0 && wb < 0 && wc < 0);
                    if (!inside) continue;
                    const double x = (wa * a.x() + wb * b.x() + wc * c.x()) / (wa + wb + wc);
                    hits.push_back({static_cast<std::uint32_t>(J + static_cast<long long>(NY) * K),
                                    static_cast<float>(x), sign});
                }
            }
        }
    }
    // counting sort by column
    start.assign(nColumns + 1, 0);
    std::size_t total = 0;
    for (const auto& hits : parts) {
        total += hits.size();
        for (const Hit& h : hits) ++start[h.column + 1];
    }
    for (std::size_t c = 0; c < nColumns; ++c) start[c + 1] += start[c];
    std::vector<Hit> sorted(total);
    {
        std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
        for (const auto& hits : parts)
            for (const Hit& h : hits) sorted[fill[h.column]++] = h;
    }
    return sorted;
}

/// An upper bound on the crossings rayHits finds: the sub-sample columns in each triangle's (y, z) box (about
/// twice the count for a surface's triangles). O(triangles), so that a triangle soup, whose every triangle
/// spans the grid, is refused before gigabytes of crossings are stored.
double crossingBound(const TriangleMesh& mesh, const std::vector<Vec3>& v, int s, int NY, int NZ) {
    double bound = 0.0;
    for (const auto& t : mesh.triangles) {
        const Vec3 &a = v[t[0]], &b = v[t[1]], &c = v[t[2]];
        const double ylo = std::min({a.y(), b.y(), c.y()}), yhi = std::max({a.y(), b.y(), c.y()});
        const double zlo = std::min({a.z(), b.z(), c.z()}), zhi = std::max({a.z(), b.z(), c.z()});
        const double J0 = std::max(0.0, std::ceil((ylo + 0.5) * s - 0.5));
        const double J1 = std::min(double(NY - 1), std::floor((yhi + 0.5) * s - 0.5));
        const double K0 = std::max(0.0, std::ceil((zlo + 0.5) * s - 0.5));
        const double K1 = std::min(double(NZ - 1), std::floor((zhi + 0.5) * s - 0.5));
        if (J1 >= J0 && K1 >= K0) bound += (J1 - J0 + 1.0) * (K1 - K0 + 1.0);
    }
    return bound;
}

/// voxelizeMesh of a valid @p mesh whose analyzeMesh() is @p info.
VoxelGrid voxelizeAnalysed(const TriangleMesh& mesh, const MeshInfo& info, const GridSpec& grid,
                           int supersample, std::vector<std::string>* warnings,
                           std::size_t memoryLimit = kDefaultMemoryLimit, double maxWork = kDefaultMaxWork) {
    if (supersample < 1 || supersample > 8)
        throw std::invalid_argument("voxelizeMesh: supersample must be 1..8, got " +
                                    std::to_string(supersample));
    if (!(grid.h > 0.0) || grid.size() == 0) throw std::invalid_argument("voxelizeMesh: empty grid");
    if (info.degenerateTriangles == info.triangles)
        throw std::invalid_argument("voxelizeMesh: all " + std::to_string(info.triangles) +
                                    " triangles are degenerate (zero area): the mesh encloses nothing");
    const bool parity = !info.consistentlyOriented;
    std::unique_ptr<MeshQuery> winding;
    if (!info.closed) {
        winding = std::make_unique<MeshQuery>(mesh);
        if (warnings)
            warnings->push_back("the mesh is not closed (" + std::to_string(info.boundaryEdges) +
                                " boundary edges, " + std::to_string(info.nonManifoldEdges) +
                                " non-manifold edges): inside decided by the generalised winding number");
    } else if (parity && warnings) {
        warnings->push_back("the triangles are not consistently oriented (" +
                            std::to_string(info.inconsistentEdges) +
                            " edges): inside decided by the parity of crossings");
    }
    const int s = supersample;
    const int NY = grid.dims[1] * s, NZ = grid.dims[2] * s;
    // sub-sample coordinate of sub-index J: (J + 0.5) / s - 0.5 (voxel units); inverse below
    auto subCoord = [s](long long J) { return (J + 0.5) / s - 0.5; };

    std::vector<Vec3> v(mesh.vertices.size());
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = grid.toVoxel(mesh.vertices[i]);

    // the crossings are held twice (by triangle, then by column), 12 bytes each
    const double bound = crossingBound(mesh, v, s, NY, NZ);
    const double bytes = 2.0 * sizeof(Hit) * bound;
    if (bytes > static_cast<double>(memoryLimit)) {
        std::ostringstream os;
        os.precision(3);
        os << "voxelizeMesh: the grid's rays along x may cross the " << mesh.triangles.size()
           << " triangles up to " << bound << " times (" << bytes / 1073741824.0
           << " GiB to hold the crossings), over the memory limit of " << double(memoryLimit) / 1073741824.0
           << " GiB: the triangles overlap far more than a surface's do (a triangle soup? `mss info` counts "
              "its "
              "self-intersections); repair the mesh, or choose a coarser resolution";
        throw std::invalid_argument(os.str());
    }
    if (winding) { // a winding number at each run between two crossings: a tree query each (exactScoreWork's)
        std::ostringstream what;
        what.precision(3);
        what << "an open mesh's inside by the winding number of its " << mesh.triangles.size()
             << " triangles at up to " << bound << " crossings of the grid's rays";
        checkWork("voxelizeMesh", {what.str(), bound * 1.0e-6 * (1.0 + double(mesh.triangles.size()) / 1e5)},
                  maxWork, "close the mesh (`mss info` shows its holes) or choose a coarser resolution");
    }
    std::vector<std::uint32_t> start;
    std::vector<Hit> sorted = rayHits(mesh, v, s, NY, NZ, start);

    VoxelGrid out(grid, 0);
    const int nx = grid.dims[0], ny = grid.dims[1], nz = grid.dims[2];
    const int threshold = s * s * s / 2; // solid when more than half of the samples are inside (eq. 5)
#pragma omp parallel
    {
        std::vector<std::uint16_t> count(static_cast<std::size_t>(nx) * ny);
#pragma omp for schedule(dynamic, 1)
        for (int k = 0; k < nz; ++k) {
            std::fill(count.begin(), count.end(), 0);
            for (int cz = 0; cz < s; ++cz) {
                const long long K = static_cast<long long>(k) * s + cz;
                for (int j = 0; j < ny; ++j) {
                    for (int cy = 0; cy < s; ++cy) {
                        const std::size_t col =
                            static_cast<std::size_t>(j * s + cy) + static_cast<std::size_t>(NY) * K;
                        Hit* b = sorted.data() + start[col];
                        Hit* e = sorted.data() + start[col + 1];
                        if (b == e) continue;
                        std::sort(b, e, [](const Hit& p, const Hit& q) {
                            return p.x < q.x || (p.x == q.x && p.sign < q.sign);
                        });
                        std::uint16_t* row = count.data() + static_cast<std::size_t>(j) * nx;
                        auto fill = [&](double x0,
                                        double x1) { // samples X with x0 <= (X + 0.5)/s - 0.5 <= x1
                            long long X0 = static_cast<long long>(std::ceil((x0 + 0.5) * s - 0.5));
                            long long X1 = static_cast<long long>(std::floor((x1 + 0.5) * s - 0.5));
                            X0 = std::max(0LL, X0);
                            X1 = std::min<long long>(static_cast<long long>(nx) * s - 1, X1);
                            for (long long X = X0; X <= X1; ++X) ++row[X / s];
                        };
                        if (winding) { // open mesh: each run between crossings by its winding number
                            const double py = subCoord(j * s + cy), pz = subCoord(K);
                            for (Hit* h = b; h + 1 != e; ++h) {
                                const double xm = 0.5 * (double(h->x) + double((h + 1)->x));
                                if (winding->inside(grid.toWorld(Vec3(xm, py, pz)))) fill(h->x, (h + 1)->x);
                            }
                            continue;
                        }
                        int winding = 0;
                        for (Hit* h = b; h != e; ++h) {
                            const int before = winding;
                            winding = parity ? (winding ^ 1) : winding + h->sign;
                            if (before != 0 || winding == 0 || h + 1 == e) continue;
                            // entering an inside run at h: find where it ends
                            Hit* q = h + 1;
                            int w2 = winding;
                            for (; q != e; ++q) {
                                w2 = parity ? (w2 ^ 1) : w2 + q->sign;
                                if (w2 == 0) break;
                            }
                            if (q == e) break; // unclosed run (open mesh): ignore the rest
                            fill(h->x, q->x);
                            winding = 0;
                            h = q;
                        }
                    }
                }
            }
            std::uint8_t* slice = out.data.data() + static_cast<std::size_t>(k) * nx * ny;
            for (std::size_t i = 0; i < count.size(); ++i) slice[i] = count[i] > threshold ? 1 : 0;
        }
    }
    return out;
}
} // namespace

VoxelGrid voxelizeMesh(const TriangleMesh& mesh, const GridSpec& grid, int supersample,
                       std::vector<std::string>* warnings) {
    validateMesh(mesh, "voxelizeMesh");
    return voxelizeAnalysed(mesh, analyzeMesh(mesh), grid, supersample, warnings);
}

VoxelGrid voxelizeMesh(const TriangleMesh& mesh, const Resolution& res, int supersample,
                       std::vector<std::string>* warnings, double maxWork) {
    validateMesh(mesh, "voxelizeMesh");
    const MeshInfo info = analyzeMesh(mesh); // once: it walks every edge
    return voxelizeAnalysed(mesh, info, gridForBox(info.lower, info.upper, res, "voxelizeMesh"), supersample,
                            warnings, res.memoryLimit, maxWork);
}

VoxelGrid voxelizeSpheres(const SphereSet& spheres, const GridSpec& grid) {
    validateSpheres(spheres, "voxelizeSpheres");
    VoxelGrid out(grid, 0);
    std::vector<Vec3> c(spheres.size());
    std::vector<double> r(spheres.size());
    for (std::size_t i = 0; i < c.size(); ++i) {
        c[i] = grid.toVoxel(spheres.centers[i]);
        r[i] = spheres.radii[i] / grid.h;
    }
    // spheres wholly outside the grid are dropped here, before any index maths (that stays within int range)
    std::vector<char> meets(c.size(), 1);
    for (std::size_t s = 0; s < c.size(); ++s)
        for (int a = 0; a < 3; ++a)
            if (!(c[s][a] + r[s] >= 0.0 && c[s][a] - r[s] <= grid.dims[a] - 1.0)) meets[s] = 0;
#pragma omp parallel for schedule(dynamic, 1)
    for (int k = 0; k < grid.dims[2]; ++k)
        for (std::size_t s = 0; s < c.size(); ++s)
            if (meets[s])
                detail::forBallRows(c[s], r[s], grid.dims, k, k, [&](int j, int kk, int i0, int i1) {
                    std::uint8_t* row = &out(0, j, kk);
                    std::fill(row + i0, row + i1 + 1, std::uint8_t(1));
                });
    return out;
}

VoxelGrid padVoxels(const VoxelGrid& volume, int padding) {
    if (padding < 0) throw std::invalid_argument("padVoxels: padding must be >= 0");
    if (volume.data.size() != volume.spec.size() || volume.spec.size() == 0)
        throw std::invalid_argument("padVoxels: the volume is empty");
    if (!(volume.spec.h > 0.0) || !std::isfinite(volume.spec.h))
        throw std::invalid_argument("padVoxels: voxel size must be > 0 and finite");
    if (!volume.spec.origin.allFinite()) throw std::invalid_argument("padVoxels: origin is not finite");
    std::array<int, 3> lo{volume.nx(), volume.ny(), volume.nz()}, hi{-1, -1, -1};
    for (int k = 0; k < volume.nz(); ++k)
        for (int j = 0; j < volume.ny(); ++j)
            for (int i = 0; i < volume.nx(); ++i) {
                if (!volume(i, j, k)) continue;
                lo = {std::min(lo[0], i), std::min(lo[1], j), std::min(lo[2], k)};
                hi = {std::max(hi[0], i), std::max(hi[1], j), std::max(hi[2], k)};
            }
    if (hi[0] < 0) throw std::invalid_argument("padVoxels: the volume has no solid voxel");
    GridSpec g;
    g.h = volume.spec.h;
    std::array<long long, 3> dims{};
    for (int a = 0; a < 3; ++a) dims[a] = hi[a] - lo[a] + 1 + 2LL * padding;
    checkGridSize("padVoxels", dims, 1, std::size_t(1) << 40);
    for (int a = 0; a < 3; ++a) g.dims[a] = static_cast<int>(dims[a]);
    g.origin = volume.spec.toWorld(Vec3(lo[0] - padding, lo[1] - padding, lo[2] - padding));
    VoxelGrid out(g, 0);
    for (int k = lo[2]; k <= hi[2]; ++k)
        for (int j = lo[1]; j <= hi[1]; ++j)
            for (int i = lo[0]; i <= hi[0]; ++i)
                out(i - lo[0] + padding, j - lo[1] + padding, k - lo[2] + padding) = volume(i, j, k) ? 1 : 0;
    return out;
}

} // namespace mss
