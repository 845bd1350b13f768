// Spheropolygons: Algorithm 1 of Dobrohotoff et al. (2012) with the sampling of eq. 4 and step 5, and what
// goes beyond the paper (relocations, a vertex in every convex or concave region, a radius per vertex).
#include "mss/spheropolygon.hpp"
#include "mss/spheropolygon/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

namespace mss {

using namespace spgeom;

namespace {

/// The pixels a move of vertex i can change, with what the other edges contribute to them fixed: a trial
/// then only tests the two edges at the vertex (the paper's section 4 speed-up). @p reach bounds how far the
/// vertex moves, @p grow how much its radius grows.
class LocalRegion {
public:
    LocalRegion(const Image2& target, const Spheropolygon& sp, std::size_t i, double reach, double grow)
        : t_(target) {
        const std::vector<Vec2>& v = sp.vertices;
        const std::size_t n = v.size(), ip = (i + n - 1) % n, in = (i + 1) % n;
        prev_ = v[ip];
        next_ = v[in];
        rPrev_ = sp.radiusOf(ip);
        rNext_ = sp.radiusOf(in);
        const double around = reach + sp.radiusOf(i) + grow;
        Vec2 lo = (prev_ - Vec2::Constant(rPrev_)).cwiseMin(next_ - Vec2::Constant(rNext_));
        Vec2 hi = (prev_ + Vec2::Constant(rPrev_)).cwiseMax(next_ + Vec2::Constant(rNext_));
        lo = lo.cwiseMin(v[i] - Vec2::Constant(around)) - Vec2::Constant(t_.pixel);
        hi = hi.cwiseMax(v[i] + Vec2::Constant(around)) + Vec2::Constant(t_.pixel);
        i0_ = std::max(0, int(std::floor((lo.x() - t_.origin.x()) / t_.pixel)));
        i1_ = std::min(t_.nx - 1, int(std::ceil((hi.x() - t_.origin.x()) / t_.pixel)));
        j0_ = std::max(0, int(std::floor((lo.y() - t_.origin.y()) / t_.pixel)));
        j1_ = std::min(t_.ny - 1, int(std::ceil((hi.y() - t_.origin.y()) / t_.pixel)));
        for (int j = j0_; j <= j1_; ++j)
            for (int ii = i0_; ii <= i1_; ++ii) {
                const Vec2 p = t_.center(ii, j);
                bool near = false, parity = false;
                for (std::size_t a = 0, b = n - 1; a < n; b = a++) {
                    if (a == i || b == i) continue; // the two edges at vertex i
                    near = near || nearEdge(p, v[b], sp.radiusOf(b), v[a], sp.radiusOf(a));
                    parity = parity != crosses(p, v[b], v[a]);
                }
                state_.push_back(std::uint8_t(near) | std::uint8_t(parity << 1) |
                                 std::uint8_t(t_(ii, j) ? 4 : 0));
            }
    }
    /// Error pixels in the region with vertex i at @p q, of radius @p r.
    long long errors(const Vec2& q, double r) const {
        long long e = 0;
        std::size_t s = 0;
        for (int j = j0_; j <= j1_; ++j)
            for (int ii = i0_; ii <= i1_; ++ii, ++s) {
                const std::uint8_t st = state_[s];
                const Vec2 p = t_.center(ii, j);
                bool in = (st & 1) || nearEdge(p, prev_, rPrev_, q, r) || nearEdge(p, q, r, next_, rNext_);
                if (!in) in = ((st >> 1) & 1) != (crosses(p, prev_, q) != crosses(p, q, next_));
                e += in != bool(st & 4);
            }
        return e;
    }

private:
    const Image2& t_;
    Vec2 prev_, next_;
    double rPrev_ = 0, rNext_ = 0;
    int i0_ = 0, i1_ = -1, j0_ = 0, j1_ = -1;
    std::vector<std::uint8_t> state_;
};

/// Which convex or concave region of the boundary each vertex is in (that whose core holds its nearest point
/// on the smoothed boundary), so that no move empties a region (SpOptions::regionVertices).
class Membership {
public:
    Membership(const Image2& image, double minTurning) {
        regions_ = boundaryRegions(image, minTurning, &boundary_);
        regionOf_.assign(boundary_.size(), -1);
        for (std::size_t k = 0; k < regions_.size(); ++k)
            for (std::size_t q = regions_[k].coreFirst;; q = (q + 1) % boundary_.size()) {
                regionOf_[q] = int(k);
                if (q == regions_[k].coreLast) break;
            }
    }
    const std::vector<SpRegion>& regions() const { return regions_; }
    const std::vector<Vec2>& boundary() const { return boundary_; }
    int regionOf(const Vec2& p) const {
        std::size_t best = 0;
        double d = std::numeric_limits<double>::infinity();
        for (std::size_t q = 0; q < boundary_.size(); ++q) {
            const double e = (boundary_[q] - p).squaredNorm();
            if (e < d) {
                d = e;
                best = q;
            }
        }
        return regionOf_[best];
    }
    void assign(const std::vector<Vec2>& v) {
        of_.clear();
        count_.assign(regions_.size(), 0);
        for (const Vec2& p : v) {
            of_.push_back(regionOf(p));
            if (of_.back() >= 0) ++count_[std::size_t(of_.back())];
        }
    }
    /// Whether vertex i may move to @p q: not if it is its region's only vertex and q is outside it.
    bool allows(std::size_t i, const Vec2& q) const {
        const int r = of_[i];
        return r < 0 || count_[std::size_t(r)] > 1 || regionOf(q) == r;
    }
    bool sole(std::size_t i) const { return of_[i] >= 0 && count_[std::size_t(of_[i])] == 1; }
    void moved(std::size_t i, const Vec2& q) {
        const int r = regionOf(q);
        if (r == of_[i]) return;
        if (of_[i] >= 0) --count_[std::size_t(of_[i])];
        if (r >= 0) ++count_[std::size_t(r)];
        of_[i] = r;
    }
    std::size_t count(std::size_t region) const { return count_[region]; }

private:
    std::vector<SpRegion> regions_;
    std::vector<Vec2> boundary_;
    std::vector<int> regionOf_;
    std::vector<int> of_;
    std::vector<std::size_t> count_;
};

void insertVertex(Spheropolygon& sp, std::size_t at, const Vec2& p, double r) {
    sp.vertices.insert(sp.vertices.begin() + std::ptrdiff_t(at), p);
    sp.radii.insert(sp.radii.begin() + std::ptrdiff_t(at), r);
}

void eraseVertex(Spheropolygon& sp, std::size_t at) {
    sp.vertices.erase(sp.vertices.begin() + std::ptrdiff_t(at));
    sp.radii.erase(sp.radii.begin() + std::ptrdiff_t(at));
}

/// Algorithm 1 from the spheropolygon in @p res (its V in history.back(), one radius per vertex in
/// sp.radii); counts iterations on. With @p radiusAxis (SpOptions::vertexRadii) each vertex also samples its
/// radius, from @p minRadius up; with @p m no move empties a convex or concave region.
void algorithmOne(const Image2& target, const SpOptions& o, SpResult& res, bool radiusAxis, double minRadius,
                  Membership* m) {
    // r_s of eq. 4; departure: when nothing moves, r_s is halved down to half a pixel (coarse to fine), where
    // the paper keeps one r_s
    double rs = o.samplingRadius > 0 ? o.samplingRadius : 4 * target.pixel;
    long long V = res.history.back();
    std::vector<Vec2>& v = res.sp.vertices;
    std::vector<double>& radius = res.sp.radii;
    // x, y (eq. 4); with radii per vertex (the (x, y, r) space of the paper's section 5) also r alone, and r
    // with the vertex moved inward by as much (the outline near the vertex kept: a fitted polygon's vertex
    // gains nothing from r or a move alone)
    const int axes = radiusAxis ? 4 : 2;
    double area = 0.0;
    for (std::size_t a = 0, b = v.size() - 1; a < v.size(); b = a++)
        area += v[b].x() * v[a].y() - v[a].x() * v[b].y();
    const double outward =
        area >= 0 ? 1.0 : -1.0; // the right normal points out of a counter-clockwise polygon
    // The inward move of vertex i per unit of radius: along the outward bisector, by 1 / sin(alpha / 2)
    // (|n_e + n_f| = 2 sin(alpha / 2), alpha the interior angle), which keeps the two bands' outer lines
    // where they were; none at a spike (alpha under ~24 degrees), where the move would run far.
    auto inward = [&](std::size_t i) -> Vec2 {
        const std::size_t n = v.size();
        const Vec2 e = (v[i] - v[(i + n - 1) % n]).normalized(), f = (v[(i + 1) % n] - v[i]).normalized();
        const Vec2 sum = outward * Vec2(e.y() + f.y(), -e.x() - f.x());
        const double len = sum.norm();
        return len > 0.4 ? Vec2(sum * (2 / (len * len))) : Vec2(Vec2::Zero());
    };
    for (int it = 0; it < o.maxIterations; ++it, ++res.iterations) {
        if (V <= o.tolerance * double(res.particlePixels)) break;
        bool moved = false;
        for (std::size_t i = 0; i < v.size(); ++i) {
            // the region holds every pixel the moves can change: x and y by up to r_s each, then the inward
            // move by up to r_s times its factor (at most that of the vertex as it stands now)
            const double factor = radiusAxis ? inward(i).norm() : 0.0;
            const LocalRegion region(target, res.sp, i, rs * (1 + factor) + target.pixel,
                                     radiusAxis ? rs + target.pixel : 0);
            for (int axis = 0; axis < axes; ++axis) {
                const long long here = region.errors(v[i], radius[i]);
                Vec2 normal = Vec2::Zero();
                if (axis == 3) {
                    normal = inward(i);
                    if (normal.isZero() || normal.norm() > factor) continue;
                }
                auto trial = [&](double step, Vec2& q, double& r) {
                    q = v[i];
                    r = radius[i];
                    if (axis < 2)
                        q[axis] += step;
                    else
                        r += step;
                    if (axis == 3) q -= step * normal;
                    return r >= minRadius && (!m || m->allows(i, q));
                };
                long long best = here;
                int bestK = 0;
                for (int k = -o.samples; k <= o.samples; ++k) { // eq. 4: 2 n_s + 1 samples
                    Vec2 q;
                    double r = 0;
                    if (k == 0 || !trial(rs * k / o.samples, q, r)) continue;
                    const long long e = region.errors(q, r);
                    if (e < best || (e == best && bestK != 0 && std::abs(k) < std::abs(bestK))) {
                        best = e;
                        bestK = k;
                    }
                }
                if (bestK == 0) continue;
                // step 5: a local minimum inside the range that gains more than the cutoff is taken; else
                // the offset is weighted by g
                const bool local = std::abs(bestK) < o.samples && here - best > o.cutoff;
                Vec2 q;
                double r = 0;
                if (!trial((local ? 1.0 : o.weight) * rs * bestK / o.samples, q, r)) continue;
                const long long e = local ? best : region.errors(q, r);
                if (e > here) continue; // a weighted step that would lose: not taken
                V += e - here;
                moved = moved || q != v[i] || r != radius[i];
                v[i] = q;
                radius[i] = r;
                if (m) m->moved(i, q);
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
/// With @p m, no region's only vertex is taken.
bool relocate(const Image2& target, const SpOptions& o, SpResult& res, Membership* m) {
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
    // the cost of removing each vertex (not the worst edge's ends, nor a region's only vertex)
    long long leastCost = std::numeric_limits<long long>::max();
    std::size_t drop = n;
    for (std::size_t i = 0; i < n; ++i) {
        if (i == worst || i == (worst + 1) % n || (m && m->sole(i))) continue;
        Spheropolygon without = res.sp;
        eraseVertex(without, i);
        const long long cost = errorPixels(target, without) - res.history.back();
        if (cost < leastCost) {
            leastCost = cost;
            drop = i;
        }
    }
    if (drop == n || double(leastCost) >= count[worst]) return false;
    SpResult trial = res;
    const Vec2 at = sum[worst] / count[worst];
    const Vec2 a = v[worst], b = v[(worst + 1) % n];
    const double t = std::clamp((at - a).dot(b - a) / std::max((b - a).squaredNorm(), 1e-300), 0.05, 0.95);
    insertVertex(trial.sp, worst + 1, a + t * (b - a) + 0.5 * (at - (a + t * (b - a))),
                 0.5 * (res.sp.radii[worst] + res.sp.radii[(worst + 1) % n]));
    eraseVertex(trial.sp, drop < worst + 1 ? drop : drop + 1);
    trial.history.push_back(errorPixels(target, trial.sp));
    SpOptions again = o;
    again.maxIterations = std::max(10, o.maxIterations / 3);
    std::optional<Membership> mm;
    if (m) {
        mm = *m;
        mm->assign(trial.sp.vertices);
    }
    algorithmOne(target, again, trial, false, 0.0, m ? &*mm : nullptr);
    if (trial.history.back() >= res.history.back()) return false;
    res = std::move(trial);
    if (m) *m = std::move(*mm);
    return true;
}

/// A vertex at the centre of every region Algorithm 1 left without one (one spheroradius inside, if inset):
/// inserted on the nearest edge in place of a vertex that holds no region alone, or such a vertex moved
/// there, whichever of the three cheapest ways ends lowest after a short Algorithm 1. Regions are taken by
/// their turning, largest first, while such a vertex is left. @return the regions filled.
int fillRegions(const Image2& target, const SpOptions& o, SpResult& res, Membership& m) {
    const std::vector<SpRegion>& regions = m.regions();
    std::vector<std::size_t> order(regions.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return std::abs(regions[a].turning) > std::abs(regions[b].turning);
    });
    const std::vector<Vec2>& b = m.boundary();
    const std::size_t nb = b.size();
    int filled = 0;
    for (std::size_t k : order) {
        if (m.count(k) > 0) continue;
        std::vector<Vec2>& v = res.sp.vertices;
        const std::size_t n = v.size(), c = regions[k].centre;
        Vec2 p = b[c];
        if (o.inset) { // one spheroradius inward: the left normal of the counter-clockwise boundary
            const Vec2 t = (b[(c + 3) % nb] - b[(c + nb - 3) % nb]).normalized();
            p += o.radius * Vec2(-t.y(), t.x());
            if (m.regionOf(p) != int(k)) p = b[c]; // a feature thinner than two spheroradii
        }
        std::size_t edge = 0;
        double d = std::numeric_limits<double>::infinity();
        for (std::size_t e = 0; e < n; ++e) {
            const double de = segmentDistance2(p, v[e], v[(e + 1) % n]);
            if (de < d) {
                d = de;
                edge = e;
            }
        }
        // the ways to free a vertex for the region: drop one that holds no region alone and insert the new
        // one on the nearest edge, or move such a vertex there; the three that cost least at once are each
        // tuned by a short Algorithm 1, and the best is kept
        std::vector<std::pair<long long, Spheropolygon>> ways;
        for (std::size_t i = 0; i < n; ++i) {
            if (m.sole(i)) continue;
            Spheropolygon without = res.sp;
            eraseVertex(without, i);
            insertVertex(without, i < edge + 1 ? edge : edge + 1, p, o.radius);
            ways.emplace_back(errorPixels(target, without), std::move(without));
            Spheropolygon moved = res.sp;
            moved.vertices[i] = p;
            ways.emplace_back(errorPixels(target, moved), std::move(moved));
        }
        if (ways.empty()) break; // every vertex holds a region alone: N is too small for the regions
        std::stable_sort(ways.begin(), ways.end(),
                         [](const auto& a, const auto& b) { return a.first < b.first; });
        SpOptions shortRun = o;
        shortRun.maxIterations = 8;
        std::optional<SpResult> best;
        std::optional<Membership> bestM;
        for (std::size_t w = 0; w < std::min<std::size_t>(3, ways.size()); ++w) {
            SpResult trial = res;
            trial.sp = ways[w].second;
            trial.history.push_back(ways[w].first);
            Membership tm = m;
            tm.assign(trial.sp.vertices);
            if (tm.count(k) == 0) continue; // a moved vertex left another region empty: not this way
            algorithmOne(target, shortRun, trial, false, 0.0, &tm);
            if (!best || trial.history.back() < best->history.back()) {
                best = std::move(trial);
                bestM = std::move(tm);
            }
        }
        if (!best) continue;
        res = std::move(*best);
        m = std::move(*bestM);
        ++filled;
    }
    return filled;
}

} // namespace

SpResult fitSpheropolygon(const Image2& target, const SpOptions& o) {
    if (o.samples < 1 || !(o.weight > 0 && o.weight < 1) || o.maxIterations < 0 || !(o.tolerance >= 0) ||
        o.relocations < 0)
        throw std::invalid_argument("spheropolygon: samples >= 1, 0 < weight < 1, maxIterations >= 0, "
                                    "tolerance >= 0, relocations >= 0");
    const double minRadius = o.minRadius.value_or(o.radius);
    if (o.minRadius && !(*o.minRadius >= 0 && *o.minRadius <= o.radius))
        throw std::invalid_argument("spheropolygon: minRadius must be between 0 and the spheroradius (" +
                                    std::to_string(o.radius) + "), got " + std::to_string(*o.minRadius));
    if (o.minRadius && !o.vertexRadii)
        throw std::invalid_argument(
            "spheropolygon: minRadius bounds the radii per vertex: it needs vertexRadii");
    SpResult res;
    res.sp = initialSpheropolygon(target, o);
    res.sp.radii.assign(res.sp.vertices.size(), o.radius);
    for (std::uint8_t v : target.data) res.particlePixels += v != 0;
    res.history.push_back(errorPixels(target, res.sp));
    std::optional<Membership> m;
    if (o.regionVertices) {
        m.emplace(target, o.regionTurning);
        m->assign(res.sp.vertices);
        res.regions = int(m->regions().size());
    }
    Membership* regions = m ? &*m : nullptr;
    algorithmOne(target, o, res, false, 0.0, regions);
    if (m && (res.regionsFilled = fillRegions(target, o, res, *m)) > 0)
        algorithmOne(target, o, res, false, 0.0, regions);
    for (int k = 0; k < o.relocations && res.history.back() > o.tolerance * double(res.particlePixels); ++k)
        if (!relocate(target, o, res, regions)) break;
    if (o.vertexRadii) {
        res.history.push_back(errorPixels(target, res.sp));
        algorithmOne(target, o, res, true, minRadius, regions);
        res.sp.radius = *std::min_element(res.sp.radii.begin(), res.sp.radii.end());
    } else {
        res.sp.radii.clear();
    }
    if (m) {
        res.regionsMissed = 0;
        for (std::size_t k = 0; k < m->regions().size(); ++k) res.regionsMissed += m->count(k) == 0;
    }
    res.errorPixels = errorPixels(target, res.sp);
    res.error = res.particlePixels ? double(res.errorPixels) / double(res.particlePixels) : 0.0;
    return res;
}

} // namespace mss
