// The surface of a clump: the boundary of the union of its spheres as a triangle mesh (mss surface).
#pragma once

#include "mss/mesh.hpp"
#include "mss/spheres.hpp"
#include "mss/work.hpp"

#include <cstddef>

namespace mss {

/// Bounds on the mesh of a union's boundary.
struct SurfaceOptions {
    /// The mesh is refined until its volume is within this fraction of the union's (sphereUnionVolume).
    /// In (0, 0.5).
    double tolerance = 0.002;
    /// And until no edge is longer than this (world units); 0: no bound on edges.
    double maxEdge = 0.0;
    /// Refused when meeting the bounds needs more triangles than this.
    std::size_t maxTriangles = 20000000;
    /// Seconds: refuse bounds whose estimated work is more, before the work (mss/work.hpp).
    double maxWork = kDefaultMaxWork;
};

/// What unionSurface did, for reports.
struct SurfaceReport {
    int subdivisions = 0;       ///< refinements of the first mesh (each makes four triangles of one)
    double volume = 0.0;        ///< of the mesh
    double unionVolume = 0.0;   ///< of the union of the spheres (sphereUnionVolume)
    double longestEdge = 0.0;   ///< world units
    double smallestAngle = 0.0; ///< degrees, over all triangles
};

/// The boundary of the union of @p spheres as a closed, manifold triangle mesh with outward normals
/// (counter-clockwise seen from outside); one component per connected group of spheres. Its vertices lie on
/// the boundary: CGAL's union of balls (Kruithof and Vegter, "Meshing skin surfaces with certified topology",
/// 2007; CGAL Skin_surface_3 with shrink factor 1, whose skin is the union's boundary) meshed, then
/// subdivided until @p options hold. O(n log n) for n spheres, then O(T) a subdivision.
/// @throws std::invalid_argument on bad spheres or options, or when the bounds need more than
/// options.maxTriangles triangles.
TriangleMesh unionSurface(const SphereSet& spheres, const SurfaceOptions& options = {},
                          SurfaceReport* report = nullptr);

} // namespace mss
