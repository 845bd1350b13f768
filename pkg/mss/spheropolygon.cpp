#include "mss/spheropolygon.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace mss {

namespace {

constexpr double kPi = 3.14159265358979323846;

double segmentDistance2(const Vec2& p, const Vec2& a, const Vec2& b) {
    const Vec2 ab = b - a;
    const double len2 = ab.squaredNorm();
    const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    return (a + t * ab - p).squaredNorm();
}

/// Whether the horizontal ray from p to +x crosses edge a-b (half-open in y: every crossing counted once).
bool crosses(const Vec2& p, const Vec2& a, const Vec2& b) {
    if ((a.y() > p.y()) == (b.y() > p.y())) return false;
    return p.x() < a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
}

bool inside(const std::vector<Vec2>& v, double r2, const Vec2& p) {
    const std::size_t n = v.size();
    if (n == 1) return (p - v[0]).squaredNorm() <= r2;
    bool in = false;
    for (std::size_t a = 0, b = n - 1; a < n; b = a++) {
        if (segmentDistance2(p, v[b], v[a]) <= r2) return true;
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
    const double r2 = sp.radius * sp.radius;
    Vec2 lo = sp.vertices[0], hi = sp.vertices[0];
    for (const Vec2& v : sp.vertices) {
        lo = lo.cwiseMin(v);
        hi = hi.cwiseMax(v);
    }
    lo -= Vec2::Constant(sp.radius);
    hi += Vec2::Constant(sp.radius);
    const int i0 = std::max(0, int(std::floor((lo.x() - like.origin.x()) / like.pixel))),
              i1 = std::min(like.nx - 1, int(std::ceil((hi.x() - like.origin.x()) / like.pixel)));
    const int j0 = std::max(0, int(std::floor((lo.y() - like.origin.y()) / like.pixel))),
              j1 = std::min(like.ny - 1, int(std::ceil((hi.y() - like.origin.y()) / like.pixel)));
    for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) out(i, j) = inside(sp.vertices, r2, like.center(i, j));
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
    r.area = 0.5 * std::abs(a) + p * sp.radius + kPi * sp.radius * sp.radius;
    r.perimeter = p + 2 * kPi * sp.radius;
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
    const std::vector<Vec2> raw = particleBoundary(image);
    // the staircase of pixel edges, rounded over about 5 pixels: what is left is the particle's own turning
    const std::vector<Vec2> b = smooth(raw, 5);
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

namespace {

/// The pixels a move of vertex i can change, with what the other edges contribute to them fixed: a trial
/// then only tests the two edges at the vertex (the paper's section 4 speed-up).
class LocalRegion {
public:
    LocalRegion(const Image2& target, const std::vector<Vec2>& v, std::size_t i, double r, double reach)
        : t_(target) {
        const std::size_t n = v.size();
        prev_ = v[(i + n - 1) % n];
        next_ = v[(i + 1) % n];
        Vec2 lo = prev_.cwiseMin(next_).cwiseMin(v[i] - Vec2::Constant(reach));
        Vec2 hi = prev_.cwiseMax(next_).cwiseMax(v[i] + Vec2::Constant(reach));
        lo -= Vec2::Constant(r + t_.pixel);
        hi += Vec2::Constant(r + t_.pixel);
        i0_ = std::max(0, int(std::floor((lo.x() - t_.origin.x()) / t_.pixel)));
        i1_ = std::min(t_.nx - 1, int(std::ceil((hi.x() - t_.origin.x()) / t_.pixel)));
        j0_ = std::max(0, int(std::floor((lo.y() - t_.origin.y()) / t_.pixel)));
        j1_ = std::min(t_.ny - 1, int(std::ceil((hi.y() - t_.origin.y()) / t_.pixel)));
        r2_ = r * r;
        for (int j = j0_; j <= j1_; ++j)
            for (int ii = i0_; ii <= i1_; ++ii) {
                const Vec2 p = t_.center(ii, j);
                bool near = false, parity = false;
                for (std::size_t a = 0, b = n - 1; a < n; b = a++) {
                    if (a == i || b == i) continue; // the two edges at vertex i
                    near = near || segmentDistance2(p, v[b], v[a]) <= r2_;
                    parity = parity != crosses(p, v[b], v[a]);
                }
                state_.push_back(std::uint8_t(near) | std::uint8_t(parity << 1) |
                                 std::uint8_t(t_(ii, j) ? 4 : 0));
            }
    }
    /// Error pixels in the region with vertex i at @p q.
    long long errors(const Vec2& q) const {
        long long e = 0;
        std::size_t s = 0;
        for (int j = j0_; j <= j1_; ++j)
            for (int ii = i0_; ii <= i1_; ++ii, ++s) {
                const std::uint8_t st = state_[s];
                const Vec2 p = t_.center(ii, j);
                bool in =
                    (st & 1) || segmentDistance2(p, prev_, q) <= r2_ || segmentDistance2(p, q, next_) <= r2_;
                if (!in) in = ((st >> 1) & 1) != (crosses(p, prev_, q) != crosses(p, q, next_));
                e += in != bool(st & 4);
            }
        return e;
    }

private:
    const Image2& t_;
    Vec2 prev_, next_;
    int i0_ = 0, i1_ = -1, j0_ = 0, j1_ = -1;
    double r2_ = 0;
    std::vector<std::uint8_t> state_;
};

} // namespace

namespace {

/// Algorithm 1 from the spheropolygon in @p res (its V in history.back()); counts iterations on.
void algorithmOne(const Image2& target, const SpOptions& o, SpResult& res) {
    // r_s of eq. 4; departure: when nothing moves, r_s is halved down to half a pixel (coarse to fine), where
    // the paper keeps one r_s
    double rs = o.samplingRadius > 0 ? o.samplingRadius : 4 * target.pixel;
    long long V = res.history.back();
    std::vector<Vec2>& v = res.sp.vertices;
    for (int it = 0; it < o.maxIterations; ++it, ++res.iterations) {
        if (V <= o.tolerance * double(res.particlePixels)) break;
        bool moved = false;
        for (std::size_t i = 0; i < v.size(); ++i) {
            const LocalRegion region(target, v, i, o.radius, rs + target.pixel);
            for (int axis = 0; axis < 2; ++axis) {
                const long long here = region.errors(v[i]);
                long long best = here;
                int bestK = 0;
                for (int k = -o.samples; k <= o.samples; ++k) { // eq. 4: 2 n_s + 1 samples
                    if (k == 0) continue;
                    Vec2 q = v[i];
                    q[axis] += rs * k / o.samples;
                    const long long e = region.errors(q);
                    if (e < best || (e == best && bestK != 0 && std::abs(k) < std::abs(bestK))) {
                        best = e;
                        bestK = k;
                    }
                }
                if (bestK == 0) continue;
                // step 5: a local minimum inside the range that gains more than the cutoff is taken; else
                // the offset is weighted by g
                const bool local = std::abs(bestK) < o.samples && here - best > o.cutoff;
                Vec2 q = v[i];
                q[axis] += (local ? 1.0 : o.weight) * rs * bestK / o.samples;
                const long long e = local ? best : region.errors(q);
                if (e > here) continue; // a weighted step that would lose: not taken
                V += e - here;
                moved = moved || q != v[i];
                v[i] = q;
            }
        }
        res.history.push_back(V);
        if (!moved) {
            if (rs <= 0.5 * target.pixel) break;
            rs = std::max(0.5 * target.pixel, 0.5 * rs);
        }
    }
}

/// Relocation (beyond the paper, which keeps the initial count along the boundary): the vertex whose removal
/// costs least goes to the edge with the most error pixels near it (at their centroid), then Algorithm 1 runs
/// again; kept while V falls. A feature the start under-sampled (a leg, a tail) gets its vertices this way.
bool relocate(const Image2& target, const SpOptions& o, SpResult& res) {
    std::vector<Vec2>& v = res.sp.vertices;
    const std::size_t n = v.size();
    // error pixels by their nearest edge
    const Image2 im = rasterize(res.sp, target);
    std::vector<double> count(n, 0.0);
    std::vector<Vec2> sum(n, Vec2::Zero());
    for (int j = 0; j < target.ny; ++j)
        for (int i = 0; i < target.nx; ++i) {
            if ((im(i, j) != 0) == (target(i, j) != 0)) continue;
            const Vec2 p = target.center(i, j);
            std::size_t best = 0;
            double d = 1e300;
            for (std::size_t e = 0; e < n; ++e) {
                const double de = segmentDistance2(p, v[e], v[(e + 1) % n]);
                if (de < d) {
                    d = de;
                    best = e;
                }
            }
            count[best] += 1;
            sum[best] += p;
        }
    const std::size_t worst = std::size_t(std::max_element(count.begin(), count.end()) - count.begin());
    // the cost of removing each vertex (not the worst edge's ends)
    long long leastCost = std::numeric_limits<long long>::max();
    std::size_t drop = n;
    for (std::size_t i = 0; i < n; ++i) {
        if (i == worst || i == (worst + 1) % n) continue;
        Spheropolygon without = res.sp;
        without.vertices.erase(without.vertices.begin() + std::ptrdiff_t(i));
        const long long cost = errorPixels(target, without) - res.history.back();
        if (cost < leastCost) {
            leastCost = cost;
            drop = i;
        }
    }
    if (drop == n || double(leastCost) >= count[worst]) return false;
    SpResult trial = res;
    std::vector<Vec2>& w = trial.sp.vertices;
    const Vec2 at = sum[worst] / count[worst];
    const Vec2 a = w[worst], b = w[(worst + 1) % n];
    const double t = std::clamp((at - a).dot(b - a) / std::max((b - a).squaredNorm(), 1e-300), 0.05, 0.95);
    w.insert(w.begin() + std::ptrdiff_t(worst + 1), a + t * (b - a) + 0.5 * (at - (a + t * (b - a))));
    w.erase(w.begin() + std::ptrdiff_t(drop < worst + 1 ? drop : drop + 1));
    trial.history.push_back(errorPixels(target, trial.sp));
    SpOptions again = o;
    again.maxIterations = std::max(10, o.maxIterations / 3);
    algorithmOne(target, again, trial);
    if (trial.history.back() >= res.history.back()) return false;
    res = std::move(trial);
    return true;
}

} // namespace

SpResult fitSpheropolygon(const Image2& target, const SpOptions& o) {
    if (o.samples < 1 || !(o.weight > 0 && o.weight < 1) || o.maxIterations < 0 || !(o.tolerance >= 0) ||
        o.relocations < 0)
        throw std::invalid_argument("spheropolygon: samples >= 1, 0 < weight < 1, maxIterations >= 0, "
                                    "tolerance >= 0, relocations >= 0");
    SpResult res;
    res.sp = initialSpheropolygon(target, o);
    for (std::uint8_t v : target.data) res.particlePixels += v != 0;
    res.history.push_back(errorPixels(target, res.sp));
    algorithmOne(target, o, res);
    for (int k = 0; k < o.relocations && res.history.back() > o.tolerance * double(res.particlePixels); ++k)
        if (!relocate(target, o, res)) break;
    res.errorPixels = errorPixels(target, res.sp);
    res.error = res.particlePixels ? double(res.errorPixels) / double(res.particlePixels) : 0.0;
    return res;
}

} // namespace mss
