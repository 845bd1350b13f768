#include "mss/compare.hpp"
#include "mss/core/edt.hpp"
#include "mss/core/mesh_query.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>
#include <stdexcept>

namespace mss {

namespace {

constexpr double kPi = 3.14159265358979323846;

/// Unit vectors spread evenly over the sphere (Fibonacci spiral).
std::vector<Vec3> spherePoints(int n) {
    std::vector<Vec3> out;
    const double golden = kPi * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < n; ++i) {
        const double z = 1.0 - (2.0 * i + 1.0) / n, rho = std::sqrt(std::max(0.0, 1.0 - z * z));
        out.emplace_back(rho * std::cos(golden * i), rho * std::sin(golden * i), z);
    }
    return out;
}

/// Share of the spheres' volume inside the box [lo, hi], from 8^3 samples per sphere.
double insideBoxShare(const SphereSet& s, const Vec3& lo, const Vec3& hi) {
    double inside = 0.0, total = 0.0;
    for (std::size_t q = 0; q < s.size(); ++q) {
        const double r = s.radii[q], w = r * r * r;
        int in = 0, all = 0;
        for (int k = 0; k < 8; ++k)
            for (int j = 0; j < 8; ++j)
                for (int i = 0; i < 8; ++i) {
                    const Vec3 u((i + 0.5) / 4 - 1, (j + 0.5) / 4 - 1, (k + 0.5) / 4 - 1);
                    if (u.squaredNorm() > 1) continue;
                    const Vec3 p = s.centers[q] + r * u;
                    ++all;
                    in += (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all();
                }
        inside += w * in / std::max(all, 1);
        total += w;
    }
    return total > 0 ? inside / total : 0.0;
}

void sphereBox(const SphereSet& s, Vec3& lo, Vec3& hi) {
    lo = Vec3::Constant(1e300);
    hi = Vec3::Constant(-1e300);
    for (std::size_t i = 0; i < s.size(); ++i) {
        lo = lo.cwiseMin(s.centers[i] - Vec3::Constant(s.radii[i]));
        hi = hi.cwiseMax(s.centers[i] + Vec3::Constant(s.radii[i]));
    }
}

/// The four proper rotations taking the spheres' principal axes onto the grain's (signs of the axes).
std::vector<RigidTransform> principalCandidates(const MassProperties& grain, const MassProperties& union_) {
    Vec3 mg, mu;
    Eigen::Matrix3d Vg, Vu;
    grain.principal(mg, Vg);
    union_.principal(mu, Vu);
    std::vector<RigidTransform> out;
    for (int signs = 0; signs < 8; ++signs) {
        const Vec3 d((signs & 1) ? -1 : 1, (signs & 2) ? -1 : 1, (signs & 4) ? -1 : 1);
        const Eigen::Matrix3d R = Vg * d.asDiagonal() * Vu.transpose();
        if (R.determinant() < 0) continue;
        RigidTransform t;
        t.rotation = R;
        t.translation = grain.centroid - R * union_.centroid;
        out.push_back(t);
    }
    return out;
}

/// Registers @p spheres to the grain as @p mode says; @p score gives D for the principal axes' sign choice.
RigidTransform alignment(Align mode, const SphereSet& spheres, const MassProperties& grain, const Vec3& lo,
                         const Vec3& hi, const std::function<double(const SphereSet&)>& dice) {
    RigidTransform t;
    if (mode == Align::None) return t;
    if (mode == Align::BoundingBox) {
        Vec3 slo, shi;
        sphereBox(spheres, slo, shi);
        t.translation = 0.5 * (lo + hi) - 0.5 * (slo + shi);
        return t;
    }
    const MassProperties u = sphereUnionMassProperties(spheres, 200);
    if (mode == Align::Centroid) {
        t.translation = grain.centroid - u.centroid;
        return t;
    }
    double best = 2.0;
    for (const RigidTransform& c : principalCandidates(grain, u)) {
        const double d = dice(transformSpheres(spheres, c));
        if (d < best) {
            best = d;
            t = c;
        }
    }
    return t;
}

/// The figures common to both kinds of target, once the spheres sit in the grain's frame.
void massFigures(Comparison& c, const SphereSet& s, const MassProperties& grain, const Vec3& lo,
                 const Vec3& hi) {
    const MassProperties u = sphereUnionMassProperties(s, 200);
    c.spheres = s.size();
    c.smallestRadius = *std::min_element(s.radii.begin(), s.radii.end());
    c.massError = (u.volume - grain.volume) / grain.volume;
    c.centroidError = (u.centroid - grain.centroid).norm() / (hi - lo).norm();
    c.inertiaError = (u.inertia - grain.inertia).norm() / grain.inertia.norm();
}

/// Each sphere's largest protrusion beyond the mesh, from o.protrusionSamples points of its surface: the
/// dear part of a comparison (two tree queries a point where a ball is not wholly inside), so estimated
/// first, in parallel, by chunks for the progress line and a stop between them.
/// The protrusions' estimated work, checked before anything else of a comparison with a mesh runs. Measured
/// on a 2-core machine, both threads, spheres scattered over the grain's box (most sticking out, whose points
/// each cost a distance query): 2.1 us a point on the ellipsoid, 3.7-4.8 us on the femur (larger spheres,
/// farther points: more of the tree visited). Taken as 5 us, the high side: a generator's own spheres, mostly
/// inside, cost far less.
Work protrusionWork(const SphereSet& s, const CompareOptions& o) {
    const int points = std::max(o.protrusionSamples, 1);
    std::ostringstream what;
    what << "the protrusions of " << s.size() << " spheres, " << points << " points each";
    const Work work{what.str(), 5.0e-6 * double(points) * double(s.size())};
    checkWork("compare", work, o.maxWork, "compare fewer spheres");
    return work;
}

void meshProtrusions(Comparison& c, const SphereSet& s, const MeshQuery& q, const CompareOptions& o) {
    const std::vector<Vec3> dirs = spherePoints(std::max(o.protrusionSamples, 1));
    Progress progress("compare", protrusionWork(s, o).seconds);
    c.sphereProtrusion.assign(s.size(), 0.0);
    constexpr std::size_t kChunk = 4096;
    for (std::size_t from = 0; from < s.size(); from += kChunk) {
        progress.update(double(from) / double(s.size()), "protrusions");
        const long long to = static_cast<long long>(std::min(s.size(), from + kChunk));
#pragma omp parallel for schedule(dynamic, 16)
        for (long long i = static_cast<long long>(from); i < to; ++i) {
            const Vec3& x = s.centers[std::size_t(i)];
            const double r = s.radii[std::size_t(i)];
            if (q.inside(x) && q.distance(x) >= r) continue; // the whole ball is inside
            double most = 0.0;
            for (const Vec3& d : dirs) {
                const Vec3 p = x + r * d;
                if (!q.inside(p)) most = std::max(most, q.distance(p));
            }
            c.sphereProtrusion[std::size_t(i)] = most;
        }
    }
    for (double e : c.sphereProtrusion) c.protrusion = std::max(c.protrusion, e);
}

/// The registration a set gets: only a set in another frame (under half its volume inside the grain's
/// bounding box) is registered; one in the grain's frame (a generator's own output) is scored as written,
/// since re-registering it would score another placement than its generator made (ours: D 0.0278 -> 0.0305).
Align alignFor(const Comparison& c, const CompareOptions& o) {
    return c.insideBox >= 0.5 ? Align::None : o.align;
}

void checkFrame(const Comparison& c, const CompareOptions& o) {
    if (!o.checkFrame || o.align != Align::None || c.insideBox >= 0.5) return;
    std::ostringstream os;
    if (std::isfinite(c.insideBox))
        os << "compare: only " << std::round(1000.0 * c.insideBox) / 10.0 << "% of the spheres' volume lies";
    else // "-nan%" said nothing
        os << "compare: the spheres' volume could not be located (coordinates too large to sample), none of "
              "it";
    os << " inside the grain's bounding box: the file is in another frame? "
          "register it with the option align (bbox, centroid or principal)";
    throw std::invalid_argument(os.str());
}

} // namespace

Align parseAlign(const std::string& name) {
    if (name == "none") return Align::None;
    if (name == "centroid") return Align::Centroid;
    if (name == "bbox") return Align::BoundingBox;
    if (name == "principal") return Align::Principal;
    throw std::invalid_argument("align must be none, centroid, bbox or principal, got '" + name + "'");
}

SphereSet transformSpheres(const SphereSet& s, const RigidTransform& t) {
    SphereSet out = s;
    for (Vec3& c : out.centers) c = t.rotation * c + t.translation;
    return out;
}

Comparison compareSpheres(const TriangleMesh& target, const SphereSet& spheres, const CompareOptions& o) {
    validateMesh(target, "compare");
    validateSpheres(spheres, "compare");
    protrusionWork(spheres, o); // before the scoring: the protrusions are the dear part
    const TriangleMesh part = o.planes.empty() ? TriangleMesh() : clipMeshByPlanes(target, o.planes);
    if (!o.planes.empty() && part.triangles.empty())
        throw std::invalid_argument("compare: no part of the grain lies on the allowed side of the planes");
    const TriangleMesh& grainMesh = o.planes.empty() ? target : part;
    const MeshInfo info = analyzeMesh(grainMesh);
    const MassProperties grain = meshMassProperties(grainMesh);
    Comparison c;
    c.insideBox = insideBoxShare(spheres, info.lower, info.upper);
    checkFrame(c, o);
    auto dice = [&](const SphereSet& s) {
        return scoreSpheres(target, s, o.resolution, o.offset, o.supersample, o.planes).dice;
    };
    c.transform = alignment(alignFor(c, o), spheres, grain, info.lower, info.upper, dice);
    const SphereSet s = transformSpheres(spheres, c.transform);
    c.score = scoreSpheres(target, s, o.resolution, o.offset, o.supersample, o.planes);
    if (o.exact) c.exact = scoreSpheresExact(target, s, o.samples, o.seed, o.planes, o.maxWork);
    massFigures(c, s, grain, info.lower, info.upper);
    meshProtrusions(c, s, MeshQuery(grainMesh), o);
    return c;
}

Comparison compareSpheres(const VoxelGrid& target, const SphereSet& spheres, const CompareOptions& o) {
    validateSpheres(spheres, "compare");
    const VoxelGrid part = o.planes.empty() ? VoxelGrid() : cutVoxelsByPlanes(target, o.planes);
    const VoxelGrid& grainVoxels = o.planes.empty() ? target : part;
    if (countSolid(grainVoxels) == 0)
        throw std::invalid_argument("compare: the target volume has no solid voxel on the allowed side");
    const MassProperties grain = voxelMassProperties(grainVoxels);
    const GridSpec& g = target.spec;
    Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
    for (int k = 0; k < g.dims[2]; ++k)
        for (int j = 0; j < g.dims[1]; ++j)
            for (int i = 0; i < g.dims[0]; ++i)
                if (grainVoxels(i, j, k)) {
                    lo = lo.cwiseMin(g.voxelCenter(i, j, k) - Vec3::Constant(0.5 * g.h));
                    hi = hi.cwiseMax(g.voxelCenter(i, j, k) + Vec3::Constant(0.5 * g.h));
                }
    Comparison c;
    c.insideBox = insideBoxShare(spheres, lo, hi);
    checkFrame(c, o);
    auto dice = [&](const SphereSet& s) { return scoreSpheres(target, s, o.planes).dice; };
    c.transform = alignment(alignFor(c, o), spheres, grain, lo, hi, dice);
    const SphereSet s = transformSpheres(spheres, c.transform);
    c.score = scoreSpheres(target, s, o.planes);
    if (o.exact) c.exact = scoreSpheresExact(target, s, o.samples, o.seed, o.planes, o.maxWork);
    massFigures(c, s, grain, lo, hi);
    // distance of each background voxel to the nearest solid voxel centre: the EDT of the complement
    VoxelGrid background(g, 0);
    for (std::size_t q = 0; q < background.size(); ++q) background.data[q] = grainVoxels.data[q] ? 0 : 1;
    const ScalarGrid away = distanceTransform(background);
    const std::vector<Vec3> dirs = spherePoints(std::max(o.protrusionSamples, 1));
    c.sphereProtrusion.assign(s.size(), 0.0);
    for (std::size_t i = 0; i < s.size(); ++i)
        for (const Vec3& d : dirs) {
            const Vec3 v = g.toVoxel(s.centers[i] + s.radii[i] * d);
            const std::array<int, 3> n{int(std::lround(v.x())), int(std::lround(v.y())),
                                       int(std::lround(v.z()))};
            double e;
            if (g.contains(n[0], n[1], n[2])) {
                if (grainVoxels(n[0], n[1], n[2])) continue;
                e = away(n[0], n[1], n[2]);
            } else { // beyond the volume: at least as far as its border
                const Vec3 clamped(std::clamp(v.x(), 0.0, g.dims[0] - 1.0),
                                   std::clamp(v.y(), 0.0, g.dims[1] - 1.0),
                                   std::clamp(v.z(), 0.0, g.dims[2] - 1.0));
                e = (v - clamped).norm() + away(int(clamped.x()), int(clamped.y()), int(clamped.z()));
            }
            c.sphereProtrusion[i] = std::max(c.sphereProtrusion[i], (e - 0.5) * g.h);
            c.protrusion = std::max(c.protrusion, c.sphereProtrusion[i]);
        }
    return c;
}

} // namespace mss
