// Spheropolygons from 2-D particle images (Dobrohotoff et al. 2012): the image of a spheropolygon, the error
// pixels (eq. 3), roundness (eq. 9), the particle boundary, its convex and concave regions, and the three
// initialisations of section 3.1. Algorithm 1 is in spheropolygon_fit.cpp.
#include "mss/spheropolygon.hpp"
#include "mss/spheropolygon/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace mss {

namespace {

using namespace spgeom;

constexpr double kPi = 3.14159265358979323846;

bool inside(const Spheropolygon& sp, const Vec2& p) {
    const std::vector<Vec2>& v = sp.vertices;
    const std::size_t n = v.size();
    if (n == 1) return (p - v[0]).squaredNorm() <= sp.radiusOf(0) * sp.radiusOf(0);
    bool in = false;
    for (std::size_t a = 0, b = n - 1; a < n; b = a++) {
        if (nearEdge(p, v[b], sp.radiusOf(b), v[a], sp.radiusOf(a))) return true;
        if (crosses(p, v[b], v[a])) in = !in;
    }
    return in;
}

void validate(const Image2& im, const char* where) {
    if (im.nx < 1 || im.ny < 1 || im.data.size() != std::size_t(im.nx) * std::size_t(im.ny))
        throw std::invalid_argument(std::string(where) + ": the image is empty or its size does not match");
    if (!(im.pixel > 0) || !std::isfinite(im.pixel) || !im.origin.allFinite())
        throw std::invalid_argument(std::string(where) + ": pixel size must be > 0 and the origin finite");
}

void validate(const Spheropolygon& sp, const char* where) {
    if (sp.vertices.empty())
        throw std::invalid_argument(std::string(where) + ": a spheropolygon needs vertices");
    for (const Vec2& v : sp.vertices)
        if (!v.allFinite()) throw std::invalid_argument(std::string(where) + ": a vertex is not finite");
    if (!(sp.radius >= 0) || !std::isfinite(sp.radius))
        throw std::invalid_argument(std::string(where) + ": the spheroradius must be >= 0 and finite");
    if (!sp.radii.empty() && sp.radii.size() != sp.vertices.size())
        throw std::invalid_argument(std::string(where) + ": radii must be one per vertex (or none)");
    for (double r : sp.radii)
        if (!(r >= 0) || !std::isfinite(r))
            throw std::invalid_argument(std::string(where) + ": every vertex radius must be >= 0 and finite");
}

double largestRadius(const Spheropolygon& sp) {
    double r = sp.radius;
    if (!sp.radii.empty()) r = *std::max_element(sp.radii.begin(), sp.radii.end());
    return r;
}

/// The pixels of the largest 4-connected component of the image (the particle), as a mask.
Image2 largestComponent(const Image2& im) {
    Image2 label(im.nx, im.ny, im.pixel, im.origin);
    std::vector<int> id(im.data.size(), -1);
    std::vector<std::size_t> size;
    std::vector<std::size_t> stack;
    for (std::size_t s = 0; s < im.data.size(); ++s) {
        if (!im.data[s] || id[s] >= 0) continue;
        const int c = int(size.size());
        size.push_back(0);
        stack.assign(1, s);
        id[s] = c;
        while (!stack.empty()) {
            const std::size_t q = stack.back();
            stack.pop_back();
            ++size[std::size_t(c)];
            const int i = int(q % std::size_t(im.nx)), j = int(q / std::size_t(im.nx));
            const int di[4] = {1, -1, 0, 0}, dj[4] = {0, 0, 1, -1};
            for (int k = 0; k < 4; ++k) {
                const int a = i + di[k], b = j + dj[k];
                if (a < 0 || b < 0 || a >= im.nx || b >= im.ny) continue;
                const std::size_t r = std::size_t(b) * std::size_t(im.nx) + std::size_t(a);
                if (im.data[r] && id[r] < 0) {
                    id[r] = c;
                    stack.push_back(r);
                }
            }
        }
    }
    if (size.empty()) throw std::invalid_argument("spheropolygon: the image has no particle pixel");
    const int best = int(std::max_element(size.begin(), size.end()) - size.begin());
    for (std::size_t s = 0; s < id.size(); ++s) label.data[s] = id[s] == best;
    return label;
}

/// A closed polyline smoothed by a moving average over 2 k + 1 points.
std::vector<Vec2> smooth(const std::vector<Vec2>& p, int k) {
    const int n = int(p.size());
    std::vector<Vec2> out(p.size(), Vec2::Zero());
    for (int i = 0; i < n; ++i) {
        for (int d = -k; d <= k; ++d) out[std::size_t(i)] += p[std::size_t(((i + d) % n + n) % n)];
        out[std::size_t(i)] /= double(2 * k + 1);
    }
    return out;
}

/// @p n points along a closed polyline at equal steps of the cumulative weight (weights per segment).
std::vector<std::size_t> equalSteps(const std::vector<double>& w, int n) {
    std::vector<double> cum(w.size() + 1, 0.0);
    for (std::size_t i = 0; i < w.size(); ++i) cum[i + 1] = cum[i] + w[i];
    std::vector<std::size_t> out;
    std::size_t s = 0;
    for (int k = 0; k < n; ++k) {
        const double target = cum.back() * k / n;
        while (s + 1 < w.size() && cum[s + 1] <= target) ++s;
        out.push_back(s);
    }
    return out;
}

} // namespace

Image2 rasterize(const Spheropolygon& sp, const Image2& like) {
    validate(like, "rasterize");
    validate(sp, "rasterize");
    Image2 out(like.nx, like.ny, like.pixel, like.origin);
    const double reach = largestRadius(sp);
    Vec2 lo = sp.vertices[0], hi = sp.vertices[0];
    for (const Vec2& v : sp.vertices) {
        lo = lo.cwiseMin(v);
        hi = hi.cwiseMax(v);
    }
    lo -= Vec2::Constant(reach);
    hi += Vec2::Constant(reach);
    const int i0 = std::max(0, int(std::floor((lo.x() - like.origin.x()) / like.pixel))),
              i1 = std::min(like.nx - 1, int(std::ceil((hi.x() - like.origin.x()) / like.pixel)));
    const int j0 = std::max(0, int(std::floor((lo.y() - like.origin.y()) / like.pixel))),
              j1 = std::min(like.ny - 1, int(std::ceil((hi.y() - like.origin.y()) / like.pixel)));
    for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) out(i, j) = inside(sp, like.center(i, j));
    return out;
}

long long errorPixels(const Image2& target, const Spheropolygon& sp) {
    const Image2 im = rasterize(sp, target);
    long long v = 0;
    for (std::size_t q = 0; q < im.data.size(); ++q) v += (im.data[q] != 0) != (target.data[q] != 0);
    return v;
}

Roundness roundness(const Spheropolygon& sp) {
    validate(sp, "roundness");
    double a = 0.0, p = 0.0;
    const std::size_t n = sp.vertices.size();
    for (std::size_t i = 0, k = n - 1; i < n; k = i++) {
        const Vec2 &u = sp.vertices[k], &v = sp.vertices[i];
        a += u.x() * v.y() - v.x() * u.y();
        if (n > 1) p += (v - u).norm();
    }
    Roundness r;
    if (sp.radii.empty()) {
        r.area = 0.5 * std::abs(a) + p * sp.radius + kPi * sp.radius * sp.radius;
        r.perimeter = p + 2 * kPi * sp.radius;
    } else { // bands of the mean radius along the edges, sectors of the exterior angle at the vertices
        const double orient = a >= 0 ? 1.0 : -1.0;
        r.area = 0.5 * std::abs(a);
        r.perimeter = p;
        for (std::size_t i = 0; i < n; ++i) {
            const Vec2 &u = sp.vertices[(i + n - 1) % n], &v = sp.vertices[i], &w = sp.vertices[(i + 1) % n];
            const Vec2 e = v - u, f = w - v;
            const double ri = sp.radii[i];
            const double theta = n > 2 ? orient * std::atan2(e.x() * f.y() - e.y() * f.x(), e.dot(f))
                                       : (n == 2 ? kPi : 2 * kPi);
            if (n > 1) r.area += 0.5 * f.norm() * (ri + sp.radii[(i + 1) % n]);
            r.area += 0.5 * theta * ri * ri;
            r.perimeter += theta * ri;
        }
    }
    r.roundness = r.perimeter > 0 ? 4 * kPi * r.area / (r.perimeter * r.perimeter) : 0.0;
    return r;
}

SpInit parseSpInit(const std::string& name) {
    if (name == "circle") return SpInit::Circle;
    if (name == "boundary") return SpInit::Boundary;
    if (name == "curvature") return SpInit::Curvature;
    throw std::invalid_argument("spheropolygon: init must be circle, boundary or curvature, got '" + name +
                                "'");
}

std::vector<Vec2> particleBoundary(const Image2& image) {
    validate(image, "particleBoundary");
    const Image2 m = largestComponent(image);
    auto solid = [&m](int i, int j) { return i >= 0 && j >= 0 && i < m.nx && j < m.ny && m(i, j) != 0; };
    int si = -1, sj = -1;
    for (int j = 0; j < m.ny && si < 0; ++j)
        for (int i = 0; i < m.nx; ++i)
            if (m(i, j)) {
                si = i;
                sj = j;
                break;
            }
    // crack following along pixel edges, the particle on the left (counter-clockwise), 4-connected: at each
    // corner turn left if that edge is a boundary edge, else go straight, else turn right
    const int dx[4] = {1, 0, -1, 0}, dy[4] = {0, 1, 0, -1}; // +x, +y, -x, -y
    auto boundaryEdge = [&](int cx, int cy, int d) {
        switch (d) {
        case 0:
            return solid(cx, cy) && !solid(cx, cy - 1);
        case 1:
            return solid(cx - 1, cy) && !solid(cx, cy);
        case 2:
            return solid(cx - 1, cy - 1) && !solid(cx - 1, cy);
        default:
            return solid(cx, cy - 1) && !solid(cx - 1, cy - 1);
        }
    };
    std::vector<Vec2> out;
    int cx = si, cy = sj, d = 0;
    const std::size_t cap = 4 * m.data.size() + 8;
    do {
        out.push_back(m.origin + m.pixel * Vec2(cx - 0.5, cy - 0.5));
        cx += dx[d];
        cy += dy[d];
        const int turns[3] = {(d + 1) % 4, d, (d + 3) % 4};
        for (int t : turns)
            if (boundaryEdge(cx, cy, t)) {
                d = t;
                break;
            }
    } while ((cx != si || cy != sj || d != 0) && out.size() < cap);
    return out;
}

namespace {

/// The particle's boundary with the staircase of pixel edges rounded over about 5 pixels: what is left is
/// the particle's own turning.
std::vector<Vec2> smoothedBoundary(const Image2& image) {
    return smooth(particleBoundary(image), 5);
}

} // namespace

std::vector<SpRegion> boundaryRegions(const Image2& image, double minTurning, std::vector<Vec2>* smoothed) {
    validate(image, "spheropolygon");
    if (!(minTurning > 0) || !std::isfinite(minTurning))
        throw std::invalid_argument("spheropolygon: regionTurning must be > 0 degrees and finite");
    const std::vector<Vec2> b = smoothedBoundary(image);
    const std::size_t n = b.size();
    std::vector<double> turn(n); // signed, radians: > 0 turns left, convex for the counter-clockwise boundary
    for (std::size_t i = 0; i < n; ++i) {
        const Vec2 u = b[i] - b[(i + n - 1) % n], v = b[(i + 1) % n] - b[i];
        turn[i] = std::atan2(u.x() * v.y() - u.y() * v.x(), u.dot(v));
    }
    // the sign of the turning over 13 points; below about a degree it is no sign (a straight stretch)
    std::vector<int> sign(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        double k = 0.0;
        for (int d = -6; d <= 6; ++d) k += turn[(i + n + std::size_t(d + int(n))) % n];
        sign[i] = k > 0.02 ? 1 : (k < -0.02 ? -1 : 0);
    }
    std::vector<SpRegion> out;
    std::size_t start = 0; // a run's first point, so that no run wraps past the scan's end
    while (start < n && sign[start] == sign[(start + n - 1) % n]) ++start;
    if (start == n) { // one sign all round: a convex particle (or a straight nothing)
        double total = 0.0;
        for (double t : turn) total += t;
        if (sign[0] != 0 && std::abs(total) * 180 / kPi >= minTurning) {
            SpRegion r;
            r.first = r.coreFirst = 0;
            r.last = r.coreLast = n - 1;
            r.turning = total * 180 / kPi;
            out.push_back(r);
        }
    } else {
        for (std::size_t k = 0; k < n;) {
            const std::size_t first = (start + k) % n;
            std::size_t len = 1;
            while (k + len < n && sign[(first + len) % n] == sign[first]) ++len;
            k += len;
            if (sign[first] == 0) continue;
            double total = 0.0;
            for (std::size_t d = 0; d < len; ++d) total += turn[(first + d) % n];
            if (std::abs(total) * 180 / kPi < minTurning) continue;
            SpRegion r;
            r.first = first;
            r.last = (first + len - 1) % n;
            r.turning = total * 180 / kPi;
            // the core (a quarter to three quarters of the turning) and the centre (half of it)
            double done = 0.0;
            bool inCore = false, pastCentre = false;
            for (std::size_t d = 0; d < len; ++d) {
                const std::size_t q = (first + d) % n;
                done += turn[q];
                const double f = std::abs(done) / std::abs(total);
                if (!inCore && f >= 0.25) {
                    inCore = true;
                    r.coreFirst = q;
                }
                if (!pastCentre && f >= 0.5) {
                    pastCentre = true;
                    r.centre = q;
                }
                if (f <= 0.75 || d == 0) r.coreLast = q;
            }
            if (!inCore) r.coreFirst = r.coreLast = r.centre = first;
            out.push_back(r);
        }
    }
    if (smoothed) *smoothed = b;
    return out;
}

Spheropolygon initialSpheropolygon(const Image2& image, const SpOptions& o) {
    validate(image, "spheropolygon");
    if (o.vertices < 3)
        throw std::invalid_argument("spheropolygon: vertices must be >= 3, got " +
                                    std::to_string(o.vertices));
    if (!(o.radius >= 0) || !std::isfinite(o.radius))
        throw std::invalid_argument("spheropolygon: the spheroradius must be >= 0");
    Spheropolygon sp;
    sp.radius = o.radius;
    const double inset = o.inset ? o.radius : 0.0;
    if (o.init == SpInit::Circle) {
        const Image2 m = largestComponent(image);
        Vec2 c = Vec2::Zero();
        double n = 0;
        for (int j = 0; j < m.ny; ++j)
            for (int i = 0; i < m.nx; ++i)
                if (m(i, j)) {
                    c += m.center(i, j);
                    n += 1;
                }
        c /= n;
        const double R = std::max(m.pixel, std::sqrt(n / kPi) * m.pixel - inset);
        for (int k = 0; k < o.vertices; ++k)
            sp.vertices.push_back(
                c + R * Vec2(std::cos(2 * kPi * k / o.vertices), std::sin(2 * kPi * k / o.vertices)));
        return sp;
    }
    const std::vector<Vec2> b = smoothedBoundary(image);
    const std::size_t n = b.size();
    std::vector<double> len(n), turn(n);
    for (std::size_t i = 0; i < n; ++i) len[i] = (b[(i + 1) % n] - b[i]).norm();
    for (std::size_t i = 0; i < n; ++i) {
        const Vec2 u = b[i] - b[(i + n - 1) % n], v = b[(i + 1) % n] - b[i];
        turn[i] = std::abs(std::atan2(u.x() * v.y() - u.y() * v.x(), u.dot(v)));
    }
    std::vector<double> w = len;
    if (o.init == SpInit::Curvature) { // density ~ curvature (turning per length, smoothed) + its mean
        std::vector<double> k(n, 0.0);
        const int h = 6;
        double mean = 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            for (int d = -h; d <= h; ++d) k[i] += turn[(i + n + std::size_t(d + int(n))) % n];
            mean += k[i] / double(n);
        }
        for (std::size_t i = 0; i < n; ++i) w[i] = len[i] * (k[i] + mean) / std::max(mean, 1e-12);
    }
    for (std::size_t s : equalSteps(w, o.vertices)) {
        Vec2 p = b[s];
        if (inset >
            0) { // one spheroradius inward: the left normal of the boundary's tangent (counter-clockwise)
            const Vec2 t = (b[(s + 3) % n] - b[(s + n - 3) % n]).normalized();
            p += inset * Vec2(-t.y(), t.x());
        }
        sp.vertices.push_back(p);
    }
    return sp;
}

} // namespace mss
