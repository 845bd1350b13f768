// Spheropolygons from 2-D particle images (Dobrohotoff et al., "Optimal description of two-dimensional
// complex-shaped objects using spheropolygons", Granular Matter 2012): the image of a spheropolygon, the
// error pixels (eq. 3), Algorithm 1 with the sampling of eq. 4, and the three initialisations of section 3.1.
#pragma once

#include <Eigen/Core>

#include <cstdint>
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

/// A polygon's Minkowski sum with a disc: vertices (world units, in order) and the spheroradius.
struct Spheropolygon {
    std::vector<Vec2> vertices;
    double radius = 0.0;
};

/// f(SP): a pixel is inside when its centre is inside the polygon (even-odd rule) or within the spheroradius
/// of an edge (or of the vertex, for N = 1). O(pixels in the bounding box x N).
Image2 rasterize(const Spheropolygon& sp, const Image2& like);

/// V = |I_SP - I_0| (eq. 3): the number of error pixels. @throws std::invalid_argument on bad input.
long long errorPixels(const Image2& target, const Spheropolygon& sp);

/// Area, perimeter and roundness R = 4 pi A / P^2 (eq. 9) of a spheropolygon: A = A_polygon + P_polygon r +
/// pi r^2 and P = P_polygon + 2 pi r, exact for a convex polygon (an approximation for a non-convex one).
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
};

struct SpResult {
    Spheropolygon sp;
    long long errorPixels = 0;    ///< V, eq. 3
    long long particlePixels = 0; ///< pixels of I_0
    double error = 0.0;           ///< V / particle pixels
    int iterations = 0;
    std::vector<long long> history; ///< V after each iteration (the first: the initial spheropolygon)
};

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
