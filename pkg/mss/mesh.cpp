#include "mss/mesh.hpp"

#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <unordered_map>

namespace mss {

namespace {

using Kernel = CGAL::Simple_cartesian<double>;

[[noreturn]] void fail(const std::string& path, const std::string& what) {
    throw std::invalid_argument("readMesh: " + path + ": " + what);
}

/// Merges identical vertex positions (STL stores each triangle's corners separately).
class VertexMerger {
public:
    explicit VertexMerger(TriangleMesh& m) : mesh_(m) {}
    int operator()(const Vec3& p) {
        auto [it, inserted] =
            index_.emplace(Key{p.x(), p.y(), p.z()}, static_cast<int>(mesh_.vertices.size()));
        if (inserted) mesh_.vertices.push_back(p);
        return it->second;
    }

private:
    struct Key {
        double x, y, z;
        bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
    };
    struct Hash {
        std::size_t operator()(const Key& k) const {
            std::uint64_t h = 1469598103934665603ull, w;
            for (double v : {k.x, k.y, k.z}) {
                v = v == 0.0 ? 0.0 : v; // -0 == +0
                std::memcpy(&w, &v, 8);
                h = (h ^ w) * 1099511628211ull;
                h ^= h >> 29;
            }
            return static_cast<std::size_t>(h);
        }
    };
    TriangleMesh& mesh_;
    std::unordered_map<Key, int, Hash> index_;
};

void addTriangle(TriangleMesh& mesh, VertexMerger& merge, const Vec3 (&p)[3]) {
    mesh.triangles.push_back({merge(p[0]), merge(p[1]), merge(p[2])});
}

/// Binary STL: 80-byte header, uint32 count, then 50 bytes per triangle (normal, 3 corners, attribute).
TriangleMesh readBinaryStl(const std::string& path, const std::vector<char>& buf) {
    std::uint32_t n = 0;
    std::memcpy(&n, buf.data() + 80, 4);
    TriangleMesh mesh;
    mesh.triangles.reserve(n);
    VertexMerger merge(mesh);
    for (std::uint32_t t = 0; t < n; ++t) {
        const char* rec = buf.data() + 84 + 50ull * t + 12;
        Vec3 p[3];
        for (int c = 0; c < 3; ++c) {
            float xyz[3];
            std::memcpy(xyz, rec + 12 * c, 12);
            p[c] = Vec3(xyz[0], xyz[1], xyz[2]);
            if (!p[c].allFinite())
                fail(path, "triangle " + std::to_string(t) + " has a non-finite coordinate");
        }
        addTriangle(mesh, merge, p);
    }
    return mesh;
}

/// ASCII STL: "solid ... facet normal ... outer loop / vertex x y z (x3) / endloop endfacet ... endsolid".
TriangleMesh readAsciiStl(const std::string& path, const std::vector<char>& buf) {
    TriangleMesh mesh;
    VertexMerger merge(mesh);
    const char* p = buf.data();
    const char* end = p + buf.size();
    std::size_t line = 1;
    auto skipSpace = [&]() {
        while (p < end && std::isspace(static_cast<unsigned char>(*p))) line += (*p++ == '\n');
    };
    auto word = [&]() {
        skipSpace();
        const char* b = p;
        while (p < end && !std::isspace(static_cast<unsigned char>(*p))) ++p;
        return std::string_view(b, static_cast<std::size_t>(p - b));
    };
    auto bad = [&](const std::string& what) {
        fail(path, "ASCII STL line " + std::to_string(line) + ": " + what);
    };
    auto number = [&]() {
        const std::string_view w = word();
        double v = 0.0;
        const char* b = w.data() + (!w.empty() && w[0] == '+');
        const auto r = std::from_chars(b, w.data() + w.size(), v);
        if (w.empty() || r.ec != std::errc() || r.ptr != w.data() + w.size())
            bad("expected a number, got '" + std::string(w) + "'");
        if (!std::isfinite(v)) bad("non-finite coordinate '" + std::string(w) + "'");
        return v;
    };
    if (word() != "solid") bad("does not start with 'solid'");
    while (p < end && *p != '\n') ++p; // the solid's name
    Vec3 corner[3];
    int count = 0;
    for (;;) {
        const std::string_view w = word();
        if (w.empty()) break;
        if (w == "endsolid") {
            while (p < end && *p != '\n') ++p;
            continue;
        }
        if (w == "solid") { // several solids in one file
            while (p < end && *p != '\n') ++p;
            continue;
        }
        if (w == "facet") {
            if (word() != "normal") bad("expected 'normal'");
            number(), number(), number();
            count = 0;
        } else if (w == "outer") {
            if (word() != "loop") bad("expected 'loop'");
        } else if (w == "vertex") {
            if (count == 3) bad("more than three vertices in a facet");
            const double x = number(), y = number(), z = number();
            corner[count++] = Vec3(x, y, z);
        } else if (w == "endloop") {
            if (count != 3) bad("facet with " + std::to_string(count) + " vertices");
        } else if (w == "endfacet") {
            if (count != 3) bad("facet with " + std::to_string(count) + " vertices");
            addTriangle(mesh, merge, corner);
            count = 0;
        } else {
            bad("unexpected '" + std::string(w) + "'");
        }
    }
    if (mesh.triangles.empty()) fail(path, "ASCII STL has no facets");
    return mesh;
}

/// Reads an STL file, ASCII or binary. A file is binary when its size matches the triangle count in its
/// header (a binary header may itself start with "solid"); else it must be ASCII text.
TriangleMesh readStl(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::vector<char> buf((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t size = buf.size();
    const bool startsSolid = size >= 5 && std::string(buf.data(), 5) == "solid";
    if (size >= 84) {
        std::uint32_t n = 0;
        std::memcpy(&n, buf.data() + 80, 4);
        const std::uint64_t expected = 84 + 50ull * n;
        if (expected == size) {
            if (n == 0) fail(path, "binary STL has no triangles");
            return readBinaryStl(path, buf);
        }
        if (!startsSolid)
            fail(path, "binary STL header says " + std::to_string(n) + " triangles (" +
                           std::to_string(expected) + " bytes) but the file has " + std::to_string(size) +
                           " bytes");
    } else if (!startsSolid) {
        fail(path, "file too short for binary STL (" + std::to_string(size) + " bytes, need at least 84)");
    }
    for (std::size_t i = 0; i < std::min<std::size_t>(size, 1 << 16); ++i) {
        const unsigned char c = static_cast<unsigned char>(buf[i]);
        if (!(std::isprint(c) || std::isspace(c)))
            fail(path,
                 "neither binary STL (size does not match its triangle count) nor ASCII STL (binary bytes)");
    }
    return readAsciiStl(path, buf);
}

} // namespace

std::string fileExtension(const std::string& path) {
    const auto slash = path.find_last_of("/\\");
    const auto dot = path.find_last_of('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    std::string ext = path.substr(dot);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    return ext;
}

void validateMesh(const TriangleMesh& mesh, const std::string& where) {
    if (mesh.triangles.empty()) throw std::invalid_argument(where + ": mesh has no triangles");
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
        if (!mesh.vertices[v].allFinite())
            throw std::invalid_argument(where + ": vertex " + std::to_string(v) +
                                        " has a non-finite coordinate");
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

MeshInfo analyzeMesh(const TriangleMesh& mesh) {
    MeshInfo info;
    info.vertices = mesh.vertices.size();
    info.triangles = mesh.triangles.size();
    if (!mesh.vertices.empty()) {
        info.lower = info.upper = mesh.vertices[0];
        for (const Vec3& v : mesh.vertices) {
            info.lower = info.lower.cwiseMin(v);
            info.upper = info.upper.cwiseMax(v);
        }
    }
    // Directed edges sorted by undirected key: count uses and directions per undirected edge.
    std::vector<std::pair<std::uint64_t, int>> edges; // (key, +1 if a<b else -1)
    edges.reserve(mesh.triangles.size() * 3);
    // Signed volume by the divergence theorem, about the bounding-box centre to limit cancellation.
    const Vec3 c = 0.5 * (info.lower + info.upper);
    long double vol6 = 0;
    for (const auto& t : mesh.triangles) {
        const Vec3 a = mesh.vertices[t[0]] - c, b = mesh.vertices[t[1]] - c, d = mesh.vertices[t[2]] - c;
        const Vec3 n = (b - a).cross(d - a);
        if (n.squaredNorm() == 0.0 || t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
            ++info.degenerateTriangles;
        vol6 += a.dot(b.cross(d));
        for (int e = 0; e < 3; ++e) {
            std::uint32_t u = static_cast<std::uint32_t>(t[e]),
                          w = static_cast<std::uint32_t>(t[(e + 1) % 3]);
            if (u == w) continue;
            const int dir = u < w ? 1 : -1;
            if (u > w) std::swap(u, w);
            edges.emplace_back((static_cast<std::uint64_t>(u) << 32) | w, dir);
        }
    }
    info.signedVolume = static_cast<double>(vol6 / 6.0L);
    std::sort(edges.begin(), edges.end());
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i;
        int sum = 0;
        while (j < edges.size() && edges[j].first == edges[i].first) sum += edges[j++].second;
        const std::size_t uses = j - i;
        if (uses == 1)
            ++info.boundaryEdges;
        else if (uses > 2)
            ++info.nonManifoldEdges;
        else if (sum != 0)
            ++info.inconsistentEdges;
        i = j;
    }
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

TriangleMesh readMesh(const std::string& path) {
    const std::string ext = fileExtension(path);
    if (ext != ".stl" && ext != ".obj" && ext != ".off" && ext != ".ply")
        fail(path, "unknown mesh extension '" + ext + "' (expected .stl, .obj, .off or .ply)");
    std::ifstream probe(path, std::ios::binary | std::ios::ate);
    if (!probe) fail(path, "cannot open file");
    const auto end = probe.tellg();
    if (end <= 0) fail(path, "file is empty");
    probe.close();
    if (ext == ".stl") {
        TriangleMesh mesh = readStl(path);
        validateMesh(mesh, "readMesh: " + path);
        return mesh;
    }

    std::vector<Kernel::Point_3> points;
    std::vector<std::vector<std::size_t>> polygons;
    bool ok = false;
    try {
        ok = CGAL::IO::read_polygon_soup(path, points, polygons, CGAL::parameters::verbose(false));
    } catch (const std::exception& e) {
        fail(path, std::string("malformed file: ") + e.what());
    }
    if (!ok) fail(path, "malformed " + ext.substr(1) + " file (CGAL's reader refused it)");

    TriangleMesh mesh;
    mesh.vertices.reserve(points.size());
    for (const auto& p : points) mesh.vertices.emplace_back(p.x(), p.y(), p.z());
    for (const auto& poly : polygons) {
        for (std::size_t c : poly) {
            if (c >= points.size())
                fail(path,
                     "a face refers to vertex " + std::to_string(c) + " of " + std::to_string(points.size()));
        }
        for (std::size_t c = 2; c < poly.size(); ++c) {
            mesh.triangles.push_back(
                {static_cast<int>(poly[0]), static_cast<int>(poly[c - 1]), static_cast<int>(poly[c])});
        }
    }
    validateMesh(mesh, "readMesh: " + path);
    return mesh;
}

} // namespace mss
