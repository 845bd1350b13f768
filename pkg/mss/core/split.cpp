// A closed mesh cut by a plane into its pieces (fragmentation: the MSS paper's summary, constraint planes for
// the fragmentation plane). The cut is clipMeshByPlanes' (Sutherland-Hodgman per triangle, a signed fan over
// the cut segments), done on an indexed mesh so that the pieces on each side can be told apart and split
// again.
#include "mss/planes.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <stdexcept>
#include <unordered_map>

namespace mss {

namespace {

/// Equal coordinates are one vertex: meshes read from STL are soups of triangles.
TriangleMesh welded(const TriangleMesh& mesh) {
    struct Key {
        std::array<std::uint64_t, 3> bits;
        bool operator==(const Key& o) const { return bits == o.bits; }
    };
    struct Hash {
        std::size_t operator()(const Key& k) const {
            std::uint64_t h = 1469598103934665603ull;
            for (std::uint64_t b : k.bits) h = (h ^ b) * 1099511628211ull;
            return std::size_t(h);
        }
    };
    std::unordered_map<Key, int, Hash> index;
    index.reserve(mesh.vertices.size());
    std::vector<int> map(mesh.vertices.size());
    TriangleMesh out;
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
        Key k;
        for (int a = 0; a < 3; ++a) {
            const double x = mesh.vertices[v][a] == 0.0 ? 0.0 : mesh.vertices[v][a]; // -0 is 0
            std::memcpy(&k.bits[std::size_t(a)], &x, sizeof x);
        }
        auto [it, fresh] = index.emplace(k, int(out.vertices.size()));
        if (fresh) out.vertices.push_back(mesh.vertices[v]);
        map[v] = it->second;
    }
    for (const auto& t : mesh.triangles) {
        const std::array<int, 3> u{map[std::size_t(t[0])], map[std::size_t(t[1])], map[std::size_t(t[2])]};
        if (u[0] != u[1] && u[1] != u[2] && u[0] != u[2]) out.triangles.push_back(u);
    }
    return out;
}

struct UnionFind {
    std::vector<int> parent;
    explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
    int find(int a) {
        while (parent[std::size_t(a)] != a)
            a = parent[std::size_t(a)] = parent[std::size_t(parent[std::size_t(a)])];
        return a;
    }
    void join(int a, int b) { parent[std::size_t(find(a))] = find(b); }
};

/// One side's polygons (vertex ids) and cut segments (entry, exit) before they are told apart.
struct Side {
    std::vector<std::array<int, 3>> triangles;
    std::vector<std::pair<int, int>> cuts;
};

/// The pieces of one side: components by shared vertices, each capped by a fan from the mean of its cut
/// points put on the plane (the cap runs against the side triangles along each cut: exit to entry there).
/// Six times the signed volume a mesh encloses (divergence theorem).
double volume6(const TriangleMesh& m) {
    double v = 0.0;
    for (const auto& t : m.triangles)
        v += m.vertices[std::size_t(t[0])].dot(
            m.vertices[std::size_t(t[1])].cross(m.vertices[std::size_t(t[2])]));
    return v;
}

/// @p smallest: six times the volume below which a piece is dropped (slivers along the plane, caps that
/// cancel where the surface only touches it).
std::vector<TriangleMesh> pieces(const Side& side, const std::vector<Vec3>& points, const Plane& plane,
                                 double smallest) {
    UnionFind uf(points.size());
    std::vector<char> used(points.size(), 0);
    for (const auto& t : side.triangles) {
        uf.join(t[0], t[1]), uf.join(t[1], t[2]);
        for (int v : t) used[std::size_t(v)] = 1;
    }
    for (const auto& [a, b] : side.cuts) uf.join(a, b), used[std::size_t(a)] = used[std::size_t(b)] = 1;
    // root -> piece, in order of first vertex: deterministic
    std::vector<int> pieceOf(points.size(), -1);
    int found = 0;
    for (std::size_t v = 0; v < points.size(); ++v)
        if (used[v] && pieceOf[std::size_t(uf.find(int(v)))] < 0)
            pieceOf[std::size_t(uf.find(int(v)))] = found++;
    auto component = [&](int root) { return pieceOf[std::size_t(root)]; };
    std::vector<TriangleMesh> out(static_cast<std::size_t>(found));
    std::vector<int> local(points.size(), -1);
    auto id = [&](int v) {
        if (local[std::size_t(v)] < 0) {
            TriangleMesh& m = out[std::size_t(component(uf.find(v)))];
            local[std::size_t(v)] = int(m.vertices.size());
            m.vertices.push_back(points[std::size_t(v)]);
        }
        return local[std::size_t(v)];
    };
    for (const auto& t : side.triangles)
        out[std::size_t(component(uf.find(t[0])))].triangles.push_back({id(t[0]), id(t[1]), id(t[2])});
    std::vector<Vec3> mean(out.size(), Vec3::Zero());
    std::vector<int> count(out.size(), 0);
    for (const auto& [a, b] : side.cuts) {
        const std::size_t c = std::size_t(component(uf.find(a)));
        mean[c] += points[std::size_t(a)] + points[std::size_t(b)];
        count[c] += 2;
    }
    const Vec3 n = plane.normal.normalized();
    std::vector<int> apex(out.size(), -1);
    for (std::size_t c = 0; c < out.size(); ++c)
        if (count[c] > 0) {
            const Vec3 m = mean[c] / double(count[c]);
            apex[c] = int(out[c].vertices.size());
            out[c].vertices.push_back(m - n * planeDistance(plane, m));
        }
    for (const auto& [a, b] : side.cuts) {
        const std::size_t c = std::size_t(component(uf.find(a)));
        out[c].triangles.push_back({apex[c], id(a), id(b)});
    }
    out.erase(std::remove_if(out.begin(), out.end(),
                             [&](const TriangleMesh& m) { return !(std::abs(volume6(m)) > smallest); }),
              out.end());
    return out;
}

} // namespace

MeshSplit splitMeshByPlane(const TriangleMesh& input, const Plane& plane) {
    validatePlane(plane, "splitMeshByPlane");
    validateMesh(input, "splitMeshByPlane");
    const TriangleMesh mesh = welded(input);
    std::vector<Vec3> points = mesh.vertices;
    std::vector<double> s(points.size());
    double extent = 0.0;
    const PlaneDistance distance(plane);
    for (std::size_t v = 0; v < points.size(); ++v)
        s[v] = distance(points[v]), extent = std::max(extent, std::abs(s[v]));
    // a vertex on the plane up to rounding is on it: otherwise the edges from it to the other side get cut
    // points at its own coordinates, and the pieces slivers of zero area and edges used four times (the
    // octahedron's vertex (1/16, 1/4, -11/16) and the plane x + 0.3 y + 0.2 z = 0: distance 3.5e-18)
    for (double& d : s)
        if (std::abs(d) <= 1e-12 * extent) d = 0.0;
    auto above = [&](int v) { return s[std::size_t(v)] >= 0.0; };
    // a cut point per edge, from its endpoints in a fixed order: one vertex for both triangles and sides
    std::unordered_map<std::uint64_t, int> cutOf;
    auto cut = [&](int a, int b) {
        if (a > b) std::swap(a, b);
        if (s[std::size_t(a)] == 0.0) return a;
        if (s[std::size_t(b)] == 0.0) return b;
        const std::uint64_t key = (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b);
        auto it = cutOf.find(key);
        if (it != cutOf.end()) return it->second;
        const double t = s[std::size_t(a)] / (s[std::size_t(a)] - s[std::size_t(b)]);
        points.push_back(points[std::size_t(a)] + (points[std::size_t(b)] - points[std::size_t(a)]) * t);
        cutOf.emplace(key, int(points.size() - 1));
        return int(points.size() - 1);
    };
    Side sides[2]; // 0: above, 1: below
    for (const auto& t : mesh.triangles) {
        for (int side = 0; side < 2; ++side) {
            auto keep = [&](int v) { return above(v) == (side == 0); };
            std::array<int, 4> poly;
            int n = 0, entry = -1, exit = -1;
            for (int q = 0; q < 3; ++q) {
                const int a = t[std::size_t(q)], b = t[std::size_t((q + 1) % 3)];
                // a vertex on the plane is both the cut point of the edge before it and a kept vertex: once
                if (keep(a) && (n == 0 || poly[std::size_t(n - 1)] != a)) poly[std::size_t(n++)] = a;
                if (keep(a) != keep(b)) {
                    const int x = cut(a, b);
                    if (n == 0 || poly[std::size_t(n - 1)] != x) poly[std::size_t(n++)] = x;
                    (keep(a) ? exit : entry) = x;
                }
            }
            if (n > 1 && poly[0] == poly[std::size_t(n - 1)]) --n;
            if (n < 3) {
                if (entry >= 0 && exit >= 0 && entry != exit && n == 2)
                    sides[side].cuts.emplace_back(entry, exit);
                continue;
            }
            for (int q = 1; q + 1 < n; ++q)
                sides[side].triangles.push_back({poly[0], poly[std::size_t(q)], poly[std::size_t(q + 1)]});
            if (entry >= 0 && exit >= 0 && entry != exit) sides[side].cuts.emplace_back(entry, exit);
        }
    }
    // relative to the grain: what rounding leaves of a piece that is not there
    const double smallest = 1e-14 * std::abs(volume6(mesh));
    MeshSplit out;
    out.above = pieces(sides[0], points, plane, smallest);
    out.below = pieces(sides[1], points, Plane{plane.point, -plane.normal}, smallest);
    return out;
}

} // namespace mss
