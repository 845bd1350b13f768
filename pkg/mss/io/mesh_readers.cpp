// The text helpers the mesh readers share (mesh_readers.hpp).
#include "mss/io/mesh_readers.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>

namespace mss::detail {

void addPolygon(TriangleMesh& mesh, const std::vector<long long>& poly, const std::string& path,
                const std::string& where) {
    if (poly.size() < 3) fail(path, where + ": a face needs at least 3 vertices");
    for (long long c : poly)
        if (c < 0 || c >= static_cast<long long>(mesh.vertices.size()))
            fail(path, where + ": a face refers to vertex " + std::to_string(c) + " of " +
                           std::to_string(mesh.vertices.size()));
    if (poly.size() > 3) { // a polygon visits each corner once: one that repeats them piles its fan's
        // triangles on each other (10^5 repeated indices: hours in the queries that meet them all)
        std::vector<long long> sorted(poly);
        std::sort(sorted.begin(), sorted.end());
        const auto twice = std::adjacent_find(sorted.begin(), sorted.end());
        if (twice != sorted.end())
            fail(path, where + ": a face of " + std::to_string(poly.size()) + " corners visits vertex " +
                           std::to_string(*twice) + " more than once (a polygon's corners are distinct)");
    }
    for (std::size_t c = 2; c < poly.size(); ++c)
        mesh.triangles.push_back(
            {static_cast<int>(poly[0]), static_cast<int>(poly[c - 1]), static_cast<int>(poly[c])});
}

bool parseDouble(std::string_view w, double& v) {
    return parseDouble(w.data(), w.data() + w.size(), v);
}

bool parseInt(std::string_view w, long long& v) {
    const char* b = w.data() + (!w.empty() && w[0] == '+');
    const auto r = std::from_chars(b, w.data() + w.size(), v);
    return !w.empty() && r.ec == std::errc() && r.ptr == w.data() + w.size();
}

std::vector<std::string_view> words(std::string_view line) {
    std::vector<std::string_view> out;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
        const std::size_t b = i;
        while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
        if (i > b) out.push_back(line.substr(b, i - b));
    }
    return out;
}

Vec3 vertexOf(const std::vector<std::string_view>& w, std::size_t first, const std::string& path,
              const std::string& at) {
    if (w.size() < first + 3)
        fail(path, at + ": a vertex needs three numbers, got " +
                       std::to_string(w.size() - std::min(first, w.size())));
    double c[3];
    for (int k = 0; k < 3; ++k) {
        const std::string_view t = w[first + std::size_t(k)];
        if (parseDouble(t, c[k]) && std::isfinite(c[k])) continue;
        // a number past the double range (1e999) is not "not a number": say which it is
        const std::string text(t.substr(0, 40));
        char* end = nullptr;
        errno = 0;
        const double v = std::strtod(text.c_str(), &end);
        const bool numeric = !text.empty() && end == text.c_str() + text.size();
        fail(path, at + ": coordinate " + "xyz"[k] + " '" + text + "' " +
                       (numeric && (errno == ERANGE || !std::isfinite(v))
                            ? "is beyond the range of a double (about 1.8e308)"
                            : "is not a finite number"));
    }
    return Vec3(c[0], c[1], c[2]);
}

} // namespace mss::detail
