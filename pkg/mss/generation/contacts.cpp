#include "mss/generation/contacts.hpp"

#include "mss/core/edt.hpp"
#include "mss/core/mesh_query.hpp"
#include "mss/planes.hpp"
#include "mss/voxelize.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mss {

NeighbourClearance::NeighbourClearance(const VoxelGrid& neighbours) {
    GridSpec s = neighbours.spec;
    for (int a = 0; a < 3; ++a) s.dims[std::size_t(a)] += 4;
    s.origin = neighbours.spec.origin - 2.0 * neighbours.spec.h * Vec3::Ones();
    free_ = std::make_shared<VoxelGrid>(s, 1);
    for (int k = 0; k < neighbours.spec.dims[2]; ++k)
        for (int j = 0; j < neighbours.spec.dims[1]; ++j)
            for (int i = 0; i < neighbours.spec.dims[0]; ++i)
                if (neighbours(i, j, k)) (*free_)(i + 2, j + 2, k + 2) = 0;
    edt_ = std::make_shared<ScalarGrid>(distanceTransform(*free_));
}

double NeighbourClearance::lower(const Vec3& c) const {
    const Vec3 v = free_->spec.toVoxel(c);
    const int i = int(std::lround(v.x())), j = int(std::lround(v.y())), k = int(std::lround(v.z()));
    if (!free_->spec.contains(i, j, k)) return std::numeric_limits<double>::infinity();
    const double d = (*edt_)(i, j, k) - (v - Vec3(i, j, k)).norm() - 0.8660254037844387; // half diagonal
    return std::max(0.0, d) * free_->spec.h;
}

double NeighbourClearance::operator()(const Vec3& c) const {
    const Vec3 v = free_->spec.toVoxel(c);
    for (int a = 0; a < 3; ++a)
        if (v[a] < 0 || v[a] > free_->spec.dims[std::size_t(a)] - 1)
            return std::numeric_limits<double>::infinity();
    return voxelClearance(*free_, *edt_, v) * free_->spec.h;
}

std::function<double(const Vec3&)> withNeighbours(std::function<double(const Vec3&)> bound,
                                                  const std::shared_ptr<NeighbourClearance>& n, double H,
                                                  double share) {
    if (!bound || !n || !std::isfinite(H)) return bound;
    return [bound, n, half = share * H](const Vec3& c) {
        const double b = bound(c);
        if (b < 0 || n->lower(c) + half >= b) return b;
        return std::min(b, (*n)(c) + half);
    };
}

namespace {

/// How far @p p lies beyond the solid voxel cubes of @p S (world units; 0 inside one), searched within
/// half the largest contact gap and a voxel; 0 where none is so near (a point of no gap: the bound holds).
double depthBeyond(const VoxelGrid& S, const Vec3& p) {
    const double h = S.spec.h, span = 0.5 * kMaxContactGap + 1.0;
    const Vec3 v = S.spec.toVoxel(p);
    double best = std::numeric_limits<double>::infinity();
    for (int k = std::max(0, int(std::floor(v.z() - span)));
         k <= std::min(S.spec.dims[2] - 1, int(std::ceil(v.z() + span))); ++k)
        for (int j = std::max(0, int(std::floor(v.y() - span)));
             j <= std::min(S.spec.dims[1] - 1, int(std::ceil(v.y() + span))); ++j)
            for (int i = std::max(0, int(std::floor(v.x() - span)));
                 i <= std::min(S.spec.dims[0] - 1, int(std::ceil(v.x() + span))); ++i) {
                if (!S(i, j, k)) continue;
                const Vec3 off = ((Vec3(i, j, k) - v).cwiseAbs() - Vec3::Constant(0.5)).cwiseMax(0.0);
                best = std::min(best, off.norm() * h);
            }
    return std::isfinite(best) ? best : 0.0;
}

} // namespace

void reachContacts(SphereSet& spheres, const GenerateOptions& opt, const VoxelGrid& S, const ScalarGrid& E,
                   const std::function<double(const Vec3&)>& clearance, double H,
                   const std::shared_ptr<NeighbourClearance>& neighbours, Metrics& m) {
    // held: the point lies a twentieth of a voxel inside a sphere, so that the two grains' spheres overlap
    // there (a DEM code's contact detection sees them, not a gap of a rounding error)
    const double h = S.spec.h, reach = 0.05 * h;
    // a contact ball is bound by rMin like every sphere: where only a smaller one holds the point (the
    // staircase of an oblique facet near a triple line), rMin decides between the contact and the time step
    const double least = std::max(opt.rMin, 0.5 * h);
    const double bump = std::min(H, opt.neighbourProtrusion * H);
    const double inscribed = h * *std::max_element(E.data.begin(), E.data.end());
    const auto limitAt = [&](const Vec3& c, double own) {
        double limit = clearance(c);
        if (limit < 0) return -1.0; // a centre outside the grain
        limit += own;
        if (neighbours) limit = std::min(limit, (*neighbours)(c) + own);
        for (const Plane& p : opt.planes) limit = std::min(limit, planeDistance(p, c));
        return limit;
    };
    m.contacts = opt.contacts.size();
    for (const ContactPoint& cp : opt.contacts) {
        double gap = std::numeric_limits<double>::infinity();
        for (std::size_t i = 0; i < spheres.size(); ++i)
            gap = std::min(gap, (cp.point - spheres.centers[i]).norm() - spheres.radii[i]);
        if (gap <= -reach) continue;
        // candidate centres: the solid voxel centres within the largest useful radius, on the grain's side of
        // the point, that the distance transform does not rule out (the clearance of a voxel centre is at
        // most E - 1/2 voxels); the farthest that the exact bound allows wins: the largest ball through the
        // point
        const Vec3 n = cp.inward.normalized();
        // a point across a separating line (findContacts' gap) lies beyond the grain: its ball may reach it
        // there, so that the two grains' clumps touch; the bound holds everywhere else (the ball protrudes at
        // most as far as the point lies beyond the grain's voxel cubes, plus the twentieth)
        const double own = std::max(bump, depthBeyond(S, cp.point) + reach);
        const double R = inscribed + std::max(h, own);
        const Vec3 lo = S.spec.toVoxel(cp.point - Vec3::Constant(R)),
                   hi = S.spec.toVoxel(cp.point + Vec3::Constant(R));
        std::vector<std::pair<double, Vec3>> candidates;
        for (int k = std::max(0, int(std::floor(lo.z())));
             k <= std::min(S.spec.dims[2] - 1, int(std::ceil(hi.z()))); ++k)
            for (int j = std::max(0, int(std::floor(lo.y())));
                 j <= std::min(S.spec.dims[1] - 1, int(std::ceil(hi.y()))); ++j)
                for (int i = std::max(0, int(std::floor(lo.x())));
                     i <= std::min(S.spec.dims[0] - 1, int(std::ceil(hi.x()))); ++i) {
                    if (!S(i, j, k)) continue;
                    const Vec3 c = S.spec.voxelCenter(i, j, k);
                    const double d = (c - cp.point).norm();
                    if (d > R || n.dot(c - cp.point) <= 0) continue;
                    if (d + reach > (E(i, j, k) - 0.5) * h + own) continue;
                    candidates.push_back({d, c});
                }
        for (int s = 1; s * h / 8 <= R; ++s) // and along the patch's normal, between the voxel centres
            candidates.push_back({s * h / 8, Vec3(cp.point + (s * h / 8) * n)});
        std::stable_sort(candidates.begin(), candidates.end(),
                         [](const auto& a, const auto& b) { return a.first > b.first; });
        bool added = false;
        for (const auto& [d, c] : candidates) {
            if (d + reach < least) break;
            if (d + reach <= limitAt(c, own)) {
                spheres.add(c, d + reach);
                added = true;
                break;
            }
        }
        ++(added ? m.contactsAdded : m.contactsMissed);
    }
}

} // namespace mss
