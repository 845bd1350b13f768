// Planes no sphere crosses (system walls, a fragmentation plane): the grain cut by them, spheres clipped.
#pragma once

#include "mss/grid.hpp"
#include "mss/mesh.hpp"
#include "mss/spheres.hpp"

#include <memory>
#include <vector>

namespace mss {

/// A plane no sphere may cross: spheres stay on the side the normal points to, {x : (x - point) . n >= 0}.
struct Plane {
    Vec3 point = Vec3::Zero();
    Vec3 normal = Vec3::UnitZ();
};

/// Throws std::invalid_argument for a plane with a non-finite point or a zero or non-finite normal.
void validatePlane(const Plane& p, const char* where);

/// Signed distance from @p x to the plane, positive on the allowed side.
double planeDistance(const Plane& p, const Vec3& x);

/// planeDistance() to one plane for many points, its normal made unit once (a square root and a division a
/// point were most of cutting a grid's voxels): the same arithmetic, so the same distances bit for bit.
class PlaneDistance {
public:
    explicit PlaneDistance(const Plane& p) : point_(p.point), unit_(p.normal.normalized()) {}
    double operator()(const Vec3& x) const { return (x - point_).dot(unit_); }

private:
    Vec3 point_, unit_;
};

/// The part of a closed mesh on the allowed side of every plane, closed again: each triangle is clipped
/// (Sutherland-Hodgman) and each cut is capped by a fan of triangles over its cut segments, from a point of
/// the plane (a signed fan, exact for the integrals of meshMassProperties whatever the cut's shape: holes and
/// several loops included). The result is a triangle soup with the input's orientation, empty when nothing
/// is left. @throws std::invalid_argument on a bad plane.
TriangleMesh clipMeshByPlanes(const TriangleMesh& mesh, const std::vector<Plane>& planes);

/// A closed mesh cut by one plane into its pieces: the connected parts on either side, each closed by its
/// own cap (a signed fan over its cut segments from a point of the plane, exact for the integrals of
/// meshMassProperties, as in clipMeshByPlanes). Each piece is an indexed mesh (vertices shared between its
/// triangles), so a piece can be split again. Vertices on the plane count on the allowed side; cut points are
/// computed once per edge, so both sides and neighbouring triangles share them. Connectivity is through
/// shared vertices: the input is welded first (equal coordinates are one vertex). O(T log T).
struct MeshSplit {
    std::vector<TriangleMesh> above; ///< pieces on the side the normal points to
    std::vector<TriangleMesh> below; ///< pieces on the other side
};

/// @throws std::invalid_argument on a bad plane or mesh.
MeshSplit splitMeshByPlane(const TriangleMesh& mesh, const Plane& plane);

/// The voxels of @p volume whose centre lies on the allowed side of every plane (a fragment at voxel
/// accuracy). @throws std::invalid_argument on a bad plane.
VoxelGrid cutVoxelsByPlanes(const VoxelGrid& volume, const std::vector<Plane>& planes);

/// Clips a sphere set: each radius becomes at most the exact distance from its centre to the mesh surface
/// (when @p mesh is given) and to every plane; a sphere whose centre is outside the mesh (generalised winding
/// number < 1/2) or beyond a plane, or whose radius would fall below @p rMin, is removed.
/// @param changed if given, receives the number of spheres shrunk or removed.
SphereSet clipSpheres(const SphereSet& spheres, const TriangleMesh* mesh, const std::vector<Plane>& planes,
                      double rMin = 0.0, std::size_t* changed = nullptr);

} // namespace mss
