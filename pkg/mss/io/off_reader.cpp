// Object File Format (OFF): our own reader (CGAL 5.5's, fuzzed, reserved gigabytes on the say-so of a header
// and ran into undefined behaviour on malformed files; fuzz/regressions keeps those inputs). One row of
// io/formats.cpp.
#include "mss/io/mesh_readers.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <map>
#include <sstream>
#include <string_view>

namespace mss::detail {

/// Object File Format: "[ST][C][N][4][n]OFF", counts, vertex lines, face lines "n i1 ... in [colour]".
/// ST, C and N add data after a vertex's coordinates (skipped); 4 makes them homogeneous (x y z w: the
/// vertex is x/w, y/w, z/w); n gives the dimension next, and only 3 is a mesh of ours. Binary OFF is refused.
TriangleMesh readOff(const std::string& path) {
    const FileBytes buf(path);
    TriangleMesh mesh;
    long long nv = -1, nf = -1, seenV = 0, seenF = 0;
    bool magic = false, homogeneous = false, dimension = false;
    std::vector<long long> poly;
    forLines(buf, [&](std::string_view line, std::size_t no) {
        auto w = words(line);
        if (w.empty()) return true;
        const std::string at = "OFF line " + std::to_string(no);
        if (!magic) {
            if (w[0].size() < 3 || w[0].substr(w[0].size() - 3) != "OFF")
                fail(path, "not an OFF file (it must start with OFF)");
            const std::string_view prefix = w[0].substr(0, w[0].size() - 3);
            std::string_view rest = prefix;
            for (std::string_view p : {"ST", "C", "N", "4", "n"})
                if (rest.substr(0, p.size()) == p) {
                    rest.remove_prefix(p.size());
                    homogeneous = homogeneous || p == "4";
                    dimension = dimension || p == "n";
                }
            if (!rest.empty())
                fail(path, "not an OFF file (unknown header " + std::string(w[0]) +
                               ": [ST][C][N][4][n]OFF is read)");
            magic = true;
            if (w.size() > 1 && w[1] == "BINARY") fail(path, "binary OFF is not supported");
            w.erase(w.begin());
            if (dimension) { // nOFF: the dimension comes first
                if (w.empty()) return true;
                long long d = 0;
                if (!parseInt(w[0], d) || d != 3)
                    fail(path,
                         at + ": an OFF of dimension " + std::string(w[0]) + " (only 3-D meshes are read)");
                dimension = false;
                w.erase(w.begin());
            }
            if (w.empty()) return true;
        }
        if (dimension) {
            long long d = 0;
            if (!parseInt(w[0], d) || d != 3)
                fail(path, at + ": an OFF of dimension " + std::string(w[0]) + " (only 3-D meshes are read)");
            dimension = false;
            w.erase(w.begin());
            if (w.empty()) return true;
        }
        if (nv < 0) {
            if (w.size() < 2 || !parseInt(w[0], nv) || !parseInt(w[1], nf) || nv < 0 || nf < 0)
                fail(path, at + ": expected the vertex and face counts");
            // every vertex takes at least 6 characters ("0 0 0\n"), every face at least 8 ("3 0 1 2\n")
            const long long size = static_cast<long long>(buf.size()); // compared so that nothing overflows
            if (nv > size / 6 || nf > size / 8 || nv * 6 + nf * 8 > size)
                fail(path, "OFF header announces " + std::to_string(nv) + " vertices and " +
                               std::to_string(nf) + " faces, more than the file holds");
            mesh.vertices.reserve(static_cast<std::size_t>(nv));
            return true;
        }
        if (seenV < nv) {
            Vec3 v = vertexOf(w, 0, path, at);
            if (homogeneous) { // 4OFF: x y z w
                double h = 0.0;
                if (w.size() < 4 || !parseDouble(w[3], h))
                    fail(path, at + ": a 4OFF vertex is x y z w (homogeneous coordinates)");
                if (!(std::isfinite(h) && h != 0.0))
                    fail(path, at + ": a 4OFF vertex's w must be a finite nonzero number");
                v /= h;
                if (!v.allFinite()) fail(path, at + ": x/w, y/w, z/w is not finite");
            }
            mesh.vertices.push_back(v);
            ++seenV;
            return true;
        }
        if (seenF < nf) {
            long long n;
            if (!parseInt(w[0], n) || n < 3 || static_cast<long long>(w.size()) < n + 1)
                fail(path, at + ": a face is a count n >= 3 and n vertex indices");
            poly.clear();
            for (long long k = 1; k <= n; ++k) {
                long long idx;
                if (!parseInt(w[static_cast<std::size_t>(k)], idx)) fail(path, at + ": bad vertex index");
                poly.push_back(idx);
            }
            addPolygon(mesh, poly, path, at);
            ++seenF;
            return true;
        }
        return false;
    });
    if (!magic || nv < 0) fail(path, "malformed OFF file (no header)");
    if (seenV < nv || seenF < nf)
        fail(path, "OFF file ends early: " + std::to_string(seenV) + " of " + std::to_string(nv) +
                       " vertices, " + std::to_string(seenF) + " of " + std::to_string(nf) + " faces");
    if (mesh.triangles.empty()) fail(path, "OFF file has no faces");
    return mesh;
}

} // namespace mss::detail
