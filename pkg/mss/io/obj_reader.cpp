// Wavefront OBJ: our own reader (CGAL 5.5's, fuzzed, reserved gigabytes on the say-so of a header and ran
// into undefined behaviour on malformed files; fuzz/regressions keeps those inputs). One row of
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

/// Wavefront OBJ: "v x y z [w]" and "f a b c ..." (each index "i", "i/t", "i//n" or "i/t/n"; negative: from
/// the end); everything else (vt, vn, g, o, s, usemtl, l, ...) is ignored.
TriangleMesh readObj(const std::string& path) {
    const FileBytes buf(path);
    TriangleMesh mesh;
    std::vector<long long> poly;
    forLines(buf, [&](std::string_view line, std::size_t no) {
        const auto w = words(line);
        if (w.empty()) return true;
        const std::string at = "OBJ line " + std::to_string(no);
        if (w[0] == "v") {
            mesh.vertices.push_back(vertexOf(w, 1, path, at));
        } else if (w[0] == "f") {
            poly.clear();
            for (std::size_t k = 1; k < w.size(); ++k) {
                long long idx;
                if (!parseInt(w[k].substr(0, w[k].find('/')), idx) || idx == 0)
                    fail(path, at + ": '" + std::string(w[k].substr(0, 40)) + "' is not a vertex index");
                const auto defined = static_cast<long long>(mesh.vertices.size());
                if (idx < 0 && -idx > defined) // named as written, not as the index it would stand for
                    fail(path, at + ": vertex index " + std::to_string(idx) +
                                   " counts back from the last vertex, but " + std::to_string(defined) +
                                   " are defined before this line");
                poly.push_back(idx > 0 ? idx - 1 : static_cast<long long>(mesh.vertices.size()) + idx);
            }
            addPolygon(mesh, poly, path, at);
        }
        return true;
    });
    if (mesh.triangles.empty()) fail(path, "OBJ file has no faces");
    return mesh;
}

} // namespace mss::detail
