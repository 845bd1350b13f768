#include "mss/mesh.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <tuple>
#include <unordered_map>

namespace mss {

void validateMesh(const TriangleMesh& mesh, const std::string& where) {
    if (mesh.triangles.empty()) throw std::invalid_argument(where + ": mesh has no triangles");
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
        if (!mesh.vertices[v].allFinite())
            throw std::invalid_argument(where + ": vertex " + std::to_string(v) +
                                        " has a non-finite coordinate");
        // mass properties sum coordinates to the fifth power (the inertia): beyond this they overflow a
        // double
        constexpr double kMaxCoordinate = 1e60;
        if (mesh.vertices[v].cwiseAbs().maxCoeff() > kMaxCoordinate) {
            std::ostringstream os;
            os << where << ": vertex " << v << " has a coordinate of "
               << mesh.vertices[v].cwiseAbs().maxCoeff() << ", too large (at most " << kMaxCoordinate
               << ": the inertia, which grows as size^5, would overflow)";
            throw std::invalid_argument(os.str());
        }
    }
    const long long nv = static_cast<long long>(mesh.vertices.size());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        for (int c : mesh.triangles[t]) {
            if (c < 0 || c >= nv)
                throw std::invalid_argument(where + ": triangle " + std::to_string(t) + " refers to vertex " +
                                            std::to_string(c) + " of " + std::to_string(nv));
        }
    }
}

std::pair<Vec3, Vec3> meshBox(const TriangleMesh& mesh) {
    if (mesh.vertices.empty()) return {Vec3::Zero(), Vec3::Zero()};
    Vec3 lower = mesh.vertices[0], upper = mesh.vertices[0];
    for (const Vec3& v : mesh.vertices) {
        lower = lower.cwiseMin(v);
        upper = upper.cwiseMax(v);
    }
    return {lower, upper};
}

MeshInfo analyzeMesh(const TriangleMesh& mesh) {
    MeshInfo info;
    info.vertices = mesh.vertices.size();
    info.triangles = mesh.triangles.size();
    std::tie(info.lower, info.upper) = meshBox(mesh);
    // Directed edges grouped by undirected edge: count uses and directions per edge. Bucketed by the lower
    // vertex (a counting sort), each bucket (a few edges) sorted by the higher one and its direction bit.
    // Why not one std::sort of all edges: a mesh's edges come in runs, and introsort fell back to heapsort on
    // them (femur, 13,752 triangles: 8x slower than this).
    const std::size_t nv = mesh.vertices.size();
    std::vector<std::size_t> first(nv + 1, 0);
    std::vector<std::uint64_t> higher(mesh.triangles.size() * 3); // (higher index, direction bit)
    auto forEachEdge = [&mesh](auto&& f) {
        for (const auto& t : mesh.triangles)
            for (int e = 0; e < 3; ++e) {
                const auto u = static_cast<std::uint64_t>(t[e]),
                           w = static_cast<std::uint64_t>(t[(e + 1) % 3]);
                if (u != w) f(std::min(u, w), (std::max(u, w) << 1) | (u < w ? 1u : 0u));
            }
    };
    forEachEdge([&](std::uint64_t lo, std::uint64_t) { ++first[lo + 1]; });
    for (std::size_t v = 0; v < nv; ++v) first[v + 1] += first[v];
    {
        std::vector<std::size_t> fill(first.begin(), first.end() - 1);
        forEachEdge([&](std::uint64_t lo, std::uint64_t hiDir) { higher[fill[lo]++] = hiDir; });
    }
    for (std::size_t v = 0; v < nv; ++v) {
        std::uint64_t* b = higher.data() + first[v];
        std::uint64_t* e = higher.data() + first[v + 1];
        std::sort(b, e);
        for (std::uint64_t* i = b; i != e;) {
            std::uint64_t* j = i;
            int sum = 0;
            while (j != e && (*j >> 1) == (*i >> 1)) sum += (*j++ & 1u) ? 1 : -1;
            const std::ptrdiff_t uses = j - i;
            if (uses == 1)
                ++info.boundaryEdges;
            else if (uses > 2)
                ++info.nonManifoldEdges;
            else if (sum != 0)
                ++info.inconsistentEdges;
            i = j;
        }
    }
    // Signed volume by the divergence theorem, about the bounding-box centre to limit cancellation.
    const Vec3 c = 0.5 * (info.lower + info.upper);
    long double vol6 = 0;
    for (const auto& t : mesh.triangles) {
        const Vec3 a = mesh.vertices[t[0]] - c, b = mesh.vertices[t[1]] - c, d = mesh.vertices[t[2]] - c;
        const Vec3 n = (b - a).cross(d - a);
        if (n.squaredNorm() == 0.0 || t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
            ++info.degenerateTriangles;
        vol6 += a.dot(b.cross(d));
    }
    info.signedVolume = static_cast<double>(vol6 / 6.0L);
    info.closed = info.boundaryEdges == 0 && info.nonManifoldEdges == 0 && info.triangles > 0;
    info.consistentlyOriented = info.inconsistentEdges == 0;
    return info;
}

TriangleMesh capHoles(const TriangleMesh& mesh) {
    validateMesh(mesh, "capHoles");
    // directed edges without their twin are boundary edges; the cap runs along them backwards
    std::map<std::pair<int, int>, int> directed;
    for (const auto& t : mesh.triangles)
        for (int e = 0; e < 3; ++e) ++directed[{t[e], t[(e + 1) % 3]}];
    std::multimap<int, int> next; // boundary edge u -> v, keyed by u
    for (const auto& [edge, n] : directed)
        if (!directed.count({edge.second, edge.first})) next.emplace(edge.first, edge.second);
    TriangleMesh out = mesh;
    while (!next.empty()) {
        std::vector<int> loop;
        auto it = next.begin();
        const int start = it->first;
        int u = start;
        while (it != next.end()) {
            loop.push_back(u);
            const int v = it->second;
            next.erase(it);
            u = v;
            if (u == start) break;
            it = next.find(u);
        }
        if (loop.size() < 3) continue;
        Vec3 c = Vec3::Zero();
        for (int v : loop) c += mesh.vertices[v];
        c /= double(loop.size());
        const int ci = static_cast<int>(out.vertices.size());
        out.vertices.push_back(c);
        for (std::size_t q = 0; q < loop.size(); ++q) {
            const int a = loop[q], b = loop[(q + 1) % loop.size()];
            out.triangles.push_back({b, a, ci}); // edge a -> b is on the boundary: the cap uses b -> a
        }
    }
    return out;
}

} // namespace mss
