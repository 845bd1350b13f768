#include "mss/generation/contacts.hpp"

#include "mss/core/edt.hpp"
#include "mss/core/mesh_query.hpp"
#include "mss/planes.hpp"

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

void reachContacts(SphereSet& spheres, const GenerateOptions& opt,
                   const std::function<double(const Vec3&)>& clearance, double H, double h, double inscribed,
                   const std::shared_ptr<NeighbourClearance>& neighbours, Metrics& m) {
    // reached: the point lies a twentieth of a voxel inside a sphere, so that the two grains' spheres overlap
    // there (a DEM code's contact detection sees them, not a gap of a rounding error)
    const double reach = 0.05 * h, least = std::max(opt.rMin, 0.5 * h);
    const double bump = std::min({0.5 * h, H, opt.neighbourProtrusion * H});
    m.contacts = opt.contacts.size();
    for (const ContactPoint& cp : opt.contacts) {
        double gap = std::numeric_limits<double>::infinity();
        for (std::size_t i = 0; i < spheres.size(); ++i)
            gap = std::min(gap, (cp.point - spheres.centers[i]).norm() - spheres.radii[i]);
        if (gap <= -reach) continue;
        const Vec3 n = cp.inward.normalized();
        double best = 0.0;
        for (int s = 1; s * h / 8 <= inscribed + h; ++s) {
            const double t = s * h / 8;
            const Vec3 c = cp.point + t * n;
            double limit = clearance(c);
            if (limit < 0) continue; // a centre outside the grain
            limit += bump;
            if (neighbours) limit = std::min(limit, (*neighbours)(c) + bump);
            for (const Plane& p : opt.planes) limit = std::min(limit, planeDistance(p, c));
            if (t + reach <= limit) best = t;
        }
        if (best + reach >= least) {
            spheres.add(cp.point + best * n, best + reach);
            ++m.contactsAdded;
        } else {
            ++m.contactsMissed;
        }
    }
}

} // namespace mss
