// Triangle meshes: in memory, from files, and what can be said about them.
#pragma once

#include "mss/grid.hpp"

#include <array>
#include <string>
#include <utility>
#include <vector>

namespace mss {

/// A triangle mesh in memory: vertex positions (world units) and triangles as vertex index triples.
/// Triangles are expected counter-clockwise seen from outside (outward normals); inverted meshes are handled.
struct TriangleMesh {
    std::vector<Vec3> vertices;
    std::vector<std::array<int, 3>> triangles;
};

/// What a mesh is: counts, topology, volume and extent.
struct MeshInfo {
    std::size_t vertices = 0;
    std::size_t triangles = 0;
    std::size_t degenerateTriangles = 0; ///< zero area
    std::size_t boundaryEdges = 0;       ///< edges used by one triangle
    std::size_t nonManifoldEdges = 0;    ///< edges used by more than two triangles
    std::size_t inconsistentEdges = 0;   ///< edges whose two triangles traverse them in the same direction
    bool closed = false;                 ///< no boundary and no non-manifold edge
    bool consistentlyOriented = false;   ///< every interior edge traversed once each way
    double signedVolume = 0.0;           ///< divergence theorem; negative for an inside-out closed mesh
    Vec3 lower = Vec3::Zero();           ///< bounding box
    Vec3 upper = Vec3::Zero();
};

/// Checks a mesh for use (at least one triangle, indices in range, finite coordinates);
/// throws std::invalid_argument naming @p where and the problem.
void validateMesh(const TriangleMesh& mesh, const std::string& where);

/// Topology, volume and bounding box. O(T log T).
MeshInfo analyzeMesh(const TriangleMesh& mesh);

/// The bounding box of the vertices (lower, upper corners; zero for no vertex): analyzeMesh's, without the
/// edges. O(V).
std::pair<Vec3, Vec3> meshBox(const TriangleMesh& mesh);

/// The distance from @p p to the surface of a closed mesh when @p p lies inside it (generalised winding
/// number of magnitude >= 1/2), else 0: the room a sphere centred there has. O(T log T) for the mesh's
/// distance hierarchy, then O(log T). @throws std::invalid_argument on a bad mesh or a non-finite point.
double insideClearance(const TriangleMesh& mesh, const Vec3& p);

/// The mesh with each hole (loop of boundary edges) closed by a fan of triangles around the loop's centroid,
/// oriented like the rest. Simple, not pretty: for volumes and tests, not for display.
TriangleMesh capHoles(const TriangleMesh& mesh);

} // namespace mss
