// The volume of a union of spheres, to near machine precision: by the divergence theorem,
//   V = 1/3 sum_i  integral over the exposed part of sphere i of  x . n dA,
// where on sphere i (centre c, radius r, outward normal n) x . n = c . n + r and dA = r^2 dz dphi (z = cos of
// the polar angle). Along each circle of latitude the spheres that overlap sphere i cover arcs known in
// closed form, so the phi integral is exact; the z integral is Gauss-Legendre between the latitudes where a
// covering cap starts or ends, in a variable that smooths the square-root behaviour there. The grid
// integration of sphereUnionMassProperties is O(h / R); this is the reference that checks it and the surface
// meshes.
#include "mss/mass.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <utility>
#include <vector>

namespace mss {

namespace {

constexpr double kPi = 3.14159265358979323846;

/// Gauss-Legendre nodes and weights on [0, 1] (Newton on the Legendre polynomial: Numerical Recipes, gauleg).
void gaussLegendre(int n, std::vector<double>& x, std::vector<double>& w) {
    x.assign(std::size_t(n), 0.0);
    w.assign(std::size_t(n), 0.0);
    for (int i = 0; i < (n + 1) / 2; ++i) {
        double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 0.0;
        for (int it = 0; it < 100; ++it) {
            double p1 = 1.0, p2 = 0.0;
            for (int j = 1; j <= n; ++j) {
                const double p3 = p2;
                p2 = p1;
                p1 = ((2.0 * j - 1.0) * z * p2 - (j - 1.0) * p3) / j;
            }
            dp = n * (z * p1 - p2) / (z * z - 1.0);
            const double dz = p1 / dp;
            z -= dz;
            if (std::abs(dz) < 1e-16) break;
        }
        x[std::size_t(i)] = 0.5 * (1.0 - z);
        x[std::size_t(n - 1 - i)] = 0.5 * (1.0 + z);
        w[std::size_t(i)] = w[std::size_t(n - 1 - i)] = 1.0 / ((1.0 - z * z) * dp * dp);
    }
}

/// A neighbour's cap on sphere i: the directions n with n . u > t are inside it.
struct Cap {
    Vec3 u;
    double t;
    double zlo = -1.0, zhi = 1.0; ///< the latitudes the cap reaches
};

/// For each sphere, the spheres it overlaps (a sweep along x over the spheres sorted by their lower x).
std::vector<std::vector<std::size_t>> overlapping(const SphereSet& s) {
    const std::size_t n = s.size();
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return s.centers[a].x() - s.radii[a] < s.centers[b].x() - s.radii[b];
    });
    std::vector<std::vector<std::size_t>> near(n);
    for (std::size_t a = 0; a < n; ++a) {
        const std::size_t i = order[a];
        const double hi = s.centers[i].x() + s.radii[i];
        for (std::size_t b = a + 1; b < n; ++b) {
            const std::size_t j = order[b];
            if (s.centers[j].x() - s.radii[j] > hi) break;
            if ((s.centers[i] - s.centers[j]).norm() < s.radii[i] + s.radii[j]) {
                near[i].push_back(j);
                near[j].push_back(i);
            }
        }
    }
    return near;
}

/// The caps sphere @p i's neighbours cover on it, with the latitudes each reaches; false when a neighbour
/// holds all of it (a duplicate sphere counts once: the first of equals is kept).
bool capsOn(const SphereSet& s, std::size_t i, const std::vector<std::size_t>& near, std::vector<Cap>& caps) {
    const Vec3 ci = s.centers[i];
    const double ri = s.radii[i];
    caps.clear();
    for (std::size_t j : near) {
        const Vec3 d = s.centers[j] - ci;
        const double dist = d.norm(), rj = s.radii[j];
        if (dist + ri < rj || (dist + ri == rj && (ri < rj || j < i))) return false;
        if (dist == 0.0) continue; // j is inside i: it covers none of i's surface
        const double t = (ri * ri + dist * dist - rj * rj) / (2.0 * ri * dist);
        if (t >= 1.0) continue;
        Cap c{d / dist, std::max(t, -1.0)};
        const double w =
            std::sqrt(std::max(0.0, 1.0 - c.u.z() * c.u.z())) * std::sqrt(std::max(0.0, 1.0 - c.t * c.t));
        c.zlo = -c.u.z() > c.t ? -1.0 : c.u.z() * c.t - w; // a pole inside the cap: it reaches that far
        c.zhi = c.u.z() > c.t ? 1.0 : c.u.z() * c.t + w;
        caps.push_back(c);
    }
    return true;
}

/// The latitudes where the covered arcs stop being smooth in z: the poles, each rim's extremes, and where two
/// rims cross (n . u1 = t1, n . u2 = t2, |n| = 1: n = a u1 + b u2 +- h (u1 x u2)). Sorted.
void breakpoints(const std::vector<Cap>& caps, std::vector<double>& breaks) {
    breaks.assign({-1.0, 1.0});
    auto add = [&breaks](double z) {
        if (z > -1.0 && z < 1.0) breaks.push_back(z);
    };
    for (const Cap& c : caps) {
        const double w =
            std::sqrt(std::max(0.0, 1.0 - c.u.z() * c.u.z())) * std::sqrt(std::max(0.0, 1.0 - c.t * c.t));
        add(c.u.z() * c.t - w);
        add(c.u.z() * c.t + w);
    }
    for (std::size_t p = 0; p < caps.size(); ++p)
        for (std::size_t q = p + 1; q < caps.size(); ++q) {
            const Cap &c1 = caps[p], &c2 = caps[q];
            const double g = c1.u.dot(c2.u), det = 1.0 - g * g;
            if (!(det > 1e-14)) continue; // parallel rims: they never cross
            const double a = (c1.t - g * c2.t) / det, b = (c2.t - g * c1.t) / det;
            const Vec3 base = a * c1.u + b * c2.u, w = c1.u.cross(c2.u);
            const double h2 = (1.0 - base.squaredNorm()) / w.squaredNorm();
            if (!(h2 >= 0.0)) continue;
            add(base.z() - std::sqrt(h2) * w.z());
            add(base.z() + std::sqrt(h2) * w.z());
        }
    std::sort(breaks.begin(), breaks.end());
}

/// The integral over the exposed part of the circle of latitude z of (c . n + r) dphi, n = (rho cos phi, rho
/// sin phi, z): the complement of the arcs the caps cover, in closed form.
double latitude(const std::vector<const Cap*>& caps, const Vec3& c, double r, double z,
                std::vector<std::pair<double, double>>& arcs) {
    const double rho = std::sqrt(std::max(0.0, 1.0 - z * z));
    arcs.clear();
    for (const Cap* cp : caps) {
        const double A = rho * std::hypot(cp->u.x(), cp->u.y());
        const double rhs = cp->t - z * cp->u.z();
        if (rhs >= A) continue;   // this latitude misses the cap
        if (rhs < -A) return 0.0; // the cap holds all of it
        const double mid = std::atan2(cp->u.y(), cp->u.x());
        const double half = std::acos(std::clamp(rhs / A, -1.0, 1.0));
        double lo = mid - half, hi = mid + half;
        if (lo < -kPi) { // on [-pi, pi): an arc across the seam in two
            arcs.push_back({lo + 2 * kPi, kPi});
            lo = -kPi;
        }
        if (hi > kPi) {
            arcs.push_back({-kPi, hi - 2 * kPi});
            hi = kPi;
        }
        arcs.push_back({lo, hi});
    }
    std::sort(arcs.begin(), arcs.end());
    auto piece = [&](double a, double e) {
        return rho * (c.x() * (std::sin(e) - std::sin(a)) - c.y() * (std::cos(e) - std::cos(a))) +
               (c.z() * z + r) * (e - a);
    };
    double f = 0.0, at = -kPi;
    for (const auto& arc : arcs) {
        if (arc.first > at) f += piece(at, arc.first);
        at = std::max(at, arc.second);
    }
    if (at < kPi) f += piece(at, kPi);
    return f;
}

} // namespace

double sphereUnionVolume(const SphereSet& spheres) {
    validateSpheres(spheres, "sphereUnionVolume");
    const std::size_t n = spheres.size();
    const std::vector<std::vector<std::size_t>> near = overlapping(spheres);
    Vec3 origin = Vec3::Zero(); // about the spheres' mean: the terms c . n stay small
    for (const Vec3& c : spheres.centers) origin += c / double(n);
    // one panel of 48 nodes between breakpoints: two spheres to 1e-14 (more panels of fewer nodes cost more
    // for the same error)
    std::vector<double> gx, gw;
    gaussLegendre(48, gx, gw);
    double total = 0.0;
    std::vector<Cap> caps;
    std::vector<const Cap*> active;
    std::vector<double> breaks;
    std::vector<std::pair<double, double>> arcs;
    for (std::size_t i = 0; i < n; ++i) {
        if (!capsOn(spheres, i, near[i], caps)) continue;
        breakpoints(caps, breaks);
        const Vec3 c = spheres.centers[i] - origin;
        double sum = 0.0;
        for (std::size_t b = 0; b + 1 < breaks.size(); ++b) {
            const double z0 = breaks[b], z1 = breaks[b + 1];
            if (!(z1 > z0)) continue;
            active.clear();
            for (const Cap& cap : caps)
                if (cap.zhi > z0 && cap.zlo < z1) active.push_back(&cap);
            for (std::size_t g = 0; g < gx.size(); ++g) {
                // z = z0 + (z1 - z0) (1 - cos(pi s)) / 2, s in [0, 1]: flattens the square roots at the ends
                const double z = z0 + (z1 - z0) * 0.5 * (1.0 - std::cos(kPi * gx[g]));
                const double dzds = (z1 - z0) * 0.5 * kPi * std::sin(kPi * gx[g]);
                sum += latitude(active, c, spheres.radii[i], z, arcs) * dzds * gw[g];
            }
        }
        total += spheres.radii[i] * spheres.radii[i] * sum / 3.0; // dA = r^2 dz dphi, V = 1/3 of the flux
    }
    return total;
}

} // namespace mss
