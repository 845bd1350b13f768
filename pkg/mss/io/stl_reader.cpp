// STL files, binary and ASCII (the ASCII parse in two parts on two threads for large files).
#include "mss/core/index_table.hpp"
#include "mss/io/mesh_readers.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <string_view>
#include <vector>

namespace mss::detail {

namespace {

/// Merges identical vertex positions (STL stores each triangle's corners separately), in order of first
/// appearance, through an IndexTable of the mesh's vertices.
class VertexMerger {
public:
    /// @p m's vertices, if any, must be distinct: they are indexed as they are. @p expected: about how many
    /// vertices there will be in all (the table and the vertex list are sized for it at once; a closed mesh
    /// has about a sixth as many vertices as corners, the callers ask for a quarter): grown from 1024 slots
    /// and an empty list, the table was rehashed five times and the list copied on the way (the ellipsoid's
    /// binary STL, 61,440 corners: the copies alone a tenth of reading it).
    explicit VertexMerger(TriangleMesh& m, std::size_t expected = 0)
        : mesh_(m), table_(std::max(expected, m.vertices.size())) {
        mesh_.vertices.reserve(std::max(expected, mesh_.vertices.size()));
        table_.addAll(mesh_.vertices.size(), [this](int v) { return hash(mesh_.vertices[std::size_t(v)]); });
    }
    int operator()(const Vec3& p) {
        const int v = table_.findOrAdd(
            hash(p), mesh_.vertices.size(),
            [&](int q) { return mesh_.vertices[std::size_t(q)] == p; }, // -0 == 0
            [this](int q) { return hash(mesh_.vertices[std::size_t(q)]); });
        if (v >= 0) return v;
        mesh_.vertices.push_back(p);
        return static_cast<int>(mesh_.vertices.size()) - 1;
    }

private:
    static std::uint64_t hash(const Vec3& p) {
        std::uint64_t h = 1469598103934665603ull, w;
        for (int a = 0; a < 3; ++a) {
            const double v = p[a] == 0.0 ? 0.0 : p[a]; // -0 hashes as 0
            std::memcpy(&w, &v, 8);
            h = (h ^ w) * 1099511628211ull;
            h ^= h >> 29;
        }
        return h ^ (h >> 32);
    }
    TriangleMesh& mesh_;
    IndexTable table_;
};

void addTriangle(TriangleMesh& mesh, VertexMerger& merge, const Vec3 (&p)[3]) {
    mesh.triangles.push_back({merge(p[0]), merge(p[1]), merge(p[2])});
}

/// std::isspace for the "C" locale, inline (the library call was a tenth of reading an ASCII STL).
bool space(char c) {
    return c == ' ' || c == '\n' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/// Binary STL: 80-byte header, uint32 count, then 50 bytes per triangle (normal, 3 corners, attribute).
TriangleMesh readBinaryStl(const std::string& path, const FileBytes& buf) {
    std::uint32_t n = 0;
    std::memcpy(&n, buf.data() + 80, 4);
    TriangleMesh mesh;
    mesh.triangles.reserve(n);
    VertexMerger merge(mesh, std::size_t(n) * 3 / 4);
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

/// The next whitespace-separated word of [@p p, @p e), @p p moved past it (empty at the end).
inline std::string_view nextWord(const char*& p, const char* e) {
    while (p < e && space(*p)) ++p;
    const char* w = p;
    while (p < e && !space(*p)) ++p;
    return std::string_view(w, static_cast<std::size_t>(p - w));
}

/// Parses ASCII STL text [@p b, @p e) into the corners of its facets, three per facet, in order; false (and
/// @p error, with its line counted from @p b) at the first fault. @p header: the text must start with "solid"
/// (the file's start; a later part starts at a facet). The cursor is a local that the compiler keeps in a
/// register, and lines are counted only for an error: with lambdas that shared the cursor and counted every
/// newline, the scan was half of reading the femur's ASCII STL.
bool parseAsciiStl(const char* b, const char* e, bool header, std::vector<Vec3>& corners,
                   std::string& error) {
    const char* p = b;
    auto bad = [&](const std::string& what) {
        const std::size_t line = 1 + static_cast<std::size_t>(std::count(b, std::min(p, e), '\n'));
        error = "ASCII STL line " + std::to_string(line) + ": " + what;
        return false;
    };
    // the next word as a finite number, else false with the error
    auto number = [&](double& v) {
        const char* w = p;
        const std::string_view word = nextWord(p, e);
        if (!parseDouble(word.data(), word.data() + word.size(), v)) {
            p = w; // the error's line: where the word begins
            while (p < e && space(*p)) ++p;
            return bad("expected a number, got '" + std::string(word) + "'");
        }
        if (!std::isfinite(v)) return bad("non-finite coordinate '" + std::string(word) + "'");
        return true;
    };
    if (header) {
        if (nextWord(p, e) != "solid") return bad("does not start with 'solid'");
        while (p < e && *p != '\n') ++p; // the solid's name
    }
    Vec3 corner[3];
    int count = 0;
    for (;;) {
        const std::string_view w = nextWord(p, e);
        if (w.empty()) break;
        if (w == "vertex") {
            if (count == 3) return bad("more than three vertices in a facet");
            double x, y, z;
            if (!number(x) || !number(y) || !number(z)) return false;
            corner[count++] = Vec3(x, y, z);
        } else if (w == "endsolid" || w == "solid") { // the end, or several solids in one file
            while (p < e && *p != '\n') ++p;
        } else if (w == "facet") {
            if (nextWord(p, e) != "normal") return bad("expected 'normal'");
            double n;
            if (!number(n) || !number(n) || !number(n)) return false;
            count = 0;
        } else if (w == "outer") {
            if (nextWord(p, e) != "loop") return bad("expected 'loop'");
        } else if (w == "endloop") {
            if (count != 3) return bad("facet with " + std::to_string(count) + " vertices");
        } else if (w == "endfacet") {
            if (count != 3) return bad("facet with " + std::to_string(count) + " vertices");
            corners.insert(corners.end(), corner, corner + 3);
            count = 0;
        } else {
            return bad("unexpected '" + std::string(w) + "'");
        }
    }
    return true;
}

/// Where a second thread may start parsing ASCII STL text: just after the first whole "endfacet" token at or
/// after the middle, or nullptr. A split that lands wrongly (the word inside a solid's name) makes the second
/// part fail to parse, and the caller then parses the whole text alone, which is always the answer.
const char* asciiStlSplit(const char* b, const char* e) {
    constexpr std::string_view kEnd = "endfacet";
    for (const char* p = b + (e - b) / 2; p + kEnd.size() < e; ++p)
        if (std::string_view(p, kEnd.size()) == kEnd && space(p[-1]) && space(p[kEnd.size()]))
            return p + kEnd.size();
    return nullptr;
}

/// ASCII STL: "solid ... facet normal ... outer loop / vertex x y z (x3) / endloop endfacet ... endsolid".
/// Files of 1 MB or more are parsed in two parts on two threads (the femur's about 1.8x faster), each part's
/// corners merged into vertices there too; the second part's vertices then join the first's in their order
/// of first appearance, which numbers them as merging all corners in file order does (the serial merge of
/// the femur's 41,000 corners was a third of the read or more). Where either part fails, the whole text is
/// parsed again in one part, which reports the fault at its line.
TriangleMesh readAsciiStl(const std::string& path, const FileBytes& buf) {
    const char* b = buf.data();
    const char* e = b + buf.size();
    std::vector<Vec3> parts[2]; // the facets' corners, in file order
    TriangleMesh meshes[2];     // each part's
    auto mergeCorners = [&](int q) {
        meshes[q].triangles.reserve(parts[q].size() / 3);
        VertexMerger merge(meshes[q], parts[q].size() / 4);
        const std::vector<Vec3>& corners = parts[q];
        for (std::size_t c = 0; c + 2 < corners.size(); c += 3)
            addTriangle(meshes[q], merge, {corners[c], corners[c + 1], corners[c + 2]});
    };
    std::string error;
    const char* split = buf.size() >= (std::size_t(1) << 20) ? asciiStlSplit(b, e) : nullptr;
    bool parsed = false;
    if (split) {
        std::string errors[2];
        bool ok[2] = {false, false};
#pragma omp parallel for schedule(static, 1)
        for (int q = 0; q < 2; ++q) {
            parts[q].reserve(buf.size() / 160 * 3); // a facet takes at least ~80 bytes
            ok[q] = q == 0 ? parseAsciiStl(b, split, true, parts[0], errors[0])
                           : parseAsciiStl(split, e, false, parts[1], errors[1]);
            if (ok[q]) mergeCorners(q);
        }
        parsed = ok[0] && ok[1];
    }
    if (!parsed) {
        for (int q = 0; q < 2; ++q) {
            parts[q].clear();
            meshes[q] = TriangleMesh();
        }
        if (!parseAsciiStl(b, e, true, parts[0], error)) fail(path, error);
        mergeCorners(0);
    }
    if (meshes[0].triangles.empty() && meshes[1].triangles.empty()) fail(path, "ASCII STL has no facets");
    { // a file cut after a whole facet parsed, and passed as an open mesh: every writer ends with endsolid
        const char* last = e;
        while (last > b && std::isspace(static_cast<unsigned char>(last[-1]))) --last; // trailing blanks
        const std::size_t tail = std::min<std::size_t>(std::size_t(last - b), 4096);
        const std::string end(last - tail, tail);
        const std::size_t at = end.rfind("endsolid");
        // the last line must be that endsolid (its solid's name may hold any word)
        if (at == std::string::npos || end.find('\n', at) != std::string::npos)
            fail(path, "ASCII STL ends without 'endsolid' (truncated?)");
    }
    TriangleMesh mesh = std::move(meshes[0]);
    VertexMerger merge(mesh, mesh.vertices.size() + meshes[1].vertices.size());
    std::vector<int> global(meshes[1].vertices.size());
    for (std::size_t v = 0; v < global.size(); ++v) global[v] = merge(meshes[1].vertices[v]);
    mesh.triangles.reserve(mesh.triangles.size() + meshes[1].triangles.size());
    for (const auto& t : meshes[1].triangles)
        mesh.triangles.push_back(
            {global[std::size_t(t[0])], global[std::size_t(t[1])], global[std::size_t(t[2])]});
    return mesh;
}

} // namespace

/// Reads an STL file, ASCII or binary. A file is binary when its size matches the triangle count in its
/// header (a binary header may itself start with "solid"); else it must be ASCII text.
TriangleMesh readStl(const std::string& path) {
    const FileBytes buf(path);
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
    // ASCII STL is text: control bytes mark a binary file; bytes of 0x80 and above are UTF-8 (a solid's name
    // in another script: "solid Größe" was refused)
    for (std::size_t i = 0; i < std::min<std::size_t>(size, 1 << 16); ++i) {
        const unsigned char c = static_cast<unsigned char>(buf[i]);
        if ((c < 0x20 && !std::isspace(c)) || c == 0x7f)
            fail(path,
                 "neither binary STL (size does not match its triangle count) nor ASCII STL (binary bytes)");
    }
    return readAsciiStl(path, buf);
}

} // namespace mss::detail
