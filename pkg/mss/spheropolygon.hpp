// Spheropolygons from 2-D particle images (Dobrohotoff et al., "Optimal description of two-dimensional
// complex-shaped objects using spheropolygons", Granular Matter 2012): the image of a spheropolygon, the
// error pixels (eq. 3), Algorithm 1 with the sampling of eq. 4, and the three initialisations of section 3.1.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace mss {

using Vec2 = Eigen::Vector2d;

/// A binary image: pixel (i, j), i along x (fastest in memory), has its centre at origin + pixel (i, j).
struct Image2 {
    int nx = 0, ny = 0;
    double pixel = 1.0;
    Vec2 origin = Vec2::Zero();
    std::vector<std::uint8_t> data; ///< non-zero: the particle

    Image2() = default;
    Image2(int nx_, int ny_, double pixel_ = 1.0, Vec2 origin_ = Vec2::Zero())
        : nx(nx_), ny(ny_), pixel(pixel_), origin(origin_), data(std::size_t(nx_) * std::size_t(ny_), 0) {}
    std::uint8_t& operator()(int i, int j) { return data[std::size_t(j) * std::size_t(nx) + std::size_t(i)]; }
    std::uint8_t operator()(int i, int j) const {
        return data[std::size_t(j) * std::size_t(nx) + std::size_t(i)];
    }
    Vec2 center(int i, int j) const { return origin + pixel * Vec2(i, j); }
};

/// A polygon's Minkowski sum with a disc: vertices (world units, in order) and the spheroradius. With a
/// radius per vertex (beyond the paper, its section 5), each edge is swept by a disc whose radius changes
/// linearly from one vertex's to the next: the convex hull of the two vertex discs.
struct Spheropolygon {
    std::vector<Vec2> vertices;
    double radius = 0.0;       ///< the spheroradius (of all vertices when radii is empty; else the least)
    std::vector<double> radii; ///< one per vertex, or empty
    double radiusOf(std::size_t i) const { return radii.empty() ? radius : radii[i]; }
};

/// f(SP): a pixel is inside when its centre is inside the polygon (even-odd rule) or within the spheroradius
/// of an edge (with radii per vertex: inside the convex hull of the edge's two vertex discs; for N = 1 the
/// vertex's disc). O(pixels in the bounding box x N).
Image2 rasterize(const Spheropolygon& sp, const Image2& like);

/// V = |I_SP - I_0| (eq. 3): the number of error pixels. @throws std::invalid_argument on bad input.
long long errorPixels(const Image2& target, const Spheropolygon& sp);

/// Area, perimeter and roundness R = 4 pi A / P^2 (eq. 9) of a spheropolygon: A = A_polygon + P_polygon r +
/// pi r^2 and P = P_polygon + 2 pi r, exact for a convex polygon (an approximation for a non-convex one).
/// With radii per vertex: A = A_polygon + sum over edges L (r_a + r_b) / 2 + sum over vertices theta r^2 / 2
/// and P = P_polygon + sum theta r (theta: the exterior angle), exact for equal radii, else approximate.
struct Roundness {
    double area = 0.0, perimeter = 0.0, roundness = 0.0;
};
Roundness roundness(const Spheropolygon& sp);

/// The three initial vertex sets of section 3.1.
enum class SpInit {
    Circle,    ///< equally spaced on a circle about the particle's centroid
    Boundary,  ///< equally spaced along the particle's boundary
    Curvature, ///< along the boundary, closest where the curvature is highest (the paper's best; default)
};
SpInit parseSpInit(const std::string& name);

struct SpOptions {
    int vertices = 30;
    double radius = 1.0; ///< spheroradius, world units
    SpInit init = SpInit::Curvature;
    bool inset = true;         ///< start the vertices one spheroradius inside the boundary (beyond the paper)
    double samplingRadius = 0; ///< r_s of eq. 4 at the start, world units; 0: 4 pixels; halved when still
    int samples = 6;           ///< n_s of eq. 4: 2 n_s + 1 samples per axis
    double weight = 0.5;       ///< g of step 5 (the paper's 0.5)
    long long cutoff = 0;      ///< Delta V_cutoff of step 5, pixels
    double tolerance = 0.0;    ///< stop when V <= tolerance x the particle's pixels (step 6)
    int maxIterations = 100;
    /// Beyond the paper: up to this many relocations of the least useful vertex to the edge with the most
    /// error pixels, each followed by Algorithm 1 again and kept only if V falls (0: the paper's Algorithm
    /// 1).
    int relocations = 0;
    /// Beyond the paper (its section 4): at least one vertex in every convex or concave region of the
    /// boundary (a run of one sign of the smoothed turning that turns by at least regionTurning degrees),
    /// placed at the region's centre where Algorithm 1 left none, and kept there by every later move.
    bool regionVertices = false;
    double regionTurning = 90.0;
    /// Beyond the paper (its section 5): a spheroradius per vertex (3N parameters), Algorithm 1 sampling
    /// (x, y, r) after the equal-radius fit. No radius falls below minRadius (the contact stiffness, hence
    /// the time step, is set by the smallest; unset: the spheroradius, so the time step never gets worse).
    bool vertexRadii = false;
    std::optional<double> minRadius;
};

struct SpResult {
    Spheropolygon sp;
    long long errorPixels = 0;    ///< V, eq. 3
    long long particlePixels = 0; ///< pixels of I_0
    double error = 0.0;           ///< V / particle pixels
    int iterations = 0;
    std::vector<long long> history; ///< V after each iteration (the first: the initial spheropolygon)
    int regions = 0;                ///< convex or concave regions found (regionVertices)
    int regionsFilled = 0;          ///< of those, how many needed a vertex put in
    int regionsMissed = 0;          ///< of those, how many have no vertex (more regions than N can hold)
};

/// A convex or concave region of a particle's boundary: a run of one sign of the smoothed turning. A vertex
/// is in the region when its nearest point on the smoothed boundary lies in the region's core, where the
/// middle half of its turning is done (a vertex at a horn's base is not in the horn).
struct SpRegion {
    std::size_t first = 0, last = 0;         ///< indices into the smoothed boundary (cyclic, first to last)
    std::size_t coreFirst = 0, coreLast = 0; ///< the core: from a quarter to three quarters of the turning
    std::size_t centre = 0;                  ///< where half the region's turning is done
    double turning = 0.0; ///< signed, degrees (> 0: convex for the counter-clockwise boundary)
};

/// The convex and concave regions of the particle's boundary (smoothed over about 5 pixels) turning by at
/// least @p minTurning degrees, and that smoothed boundary.
std::vector<SpRegion> boundaryRegions(const Image2& image, double minTurning,
                                      std::vector<Vec2>* smoothed = nullptr);

/// The particle's outer boundary (the largest 4-connected component), as the polygon of its pixels' outer
/// edges, counter-clockwise, world units. @throws std::invalid_argument for an empty image.
std::vector<Vec2> particleBoundary(const Image2& image);

/// The initial spheropolygon of @p init (with the inset, if asked).
Spheropolygon initialSpheropolygon(const Image2& image, const SpOptions& o);

/// Algorithm 1: every vertex in turn, V sampled at 2 n_s + 1 offsets along x (then along y) up to r_s (eq.
/// 4), the vertex moved to a local minimum strictly inside the range that lowers V by more than the cutoff,
/// else by g times the best offset (step 5); iterations until V is within the tolerance, nothing moves, or
/// the cap. A trial only recounts the pixels near the moved vertex's two edges (the paper's section 4
/// speed-up): a trial costs O(local area x N), an iteration O(N x samples x local area x N), not whole
/// images.
SpResult fitSpheropolygon(const Image2& target, const SpOptions& o);

} // namespace mss
