// Mesh writers (.stl binary, .obj, .ply binary little-endian): rows of io/formats.cpp. Each gives the whole
// file; writeMesh writes it atomically. Coordinates: OBJ at full precision (17 digits); STL holds floats by
// its definition; PLY is written in doubles.
#include "mss/io/mesh_writers.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace mss::detail {

namespace {

template <class T> void put(std::string& out, T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T)); // the project builds on little-endian machines (the readers say so too)
    out.append(b, sizeof(T));
}

/// Refuses a mesh that binary STL's single-precision floats cannot hold: a reader merges the corners with the
/// same coordinates, so two distinct vertices that round to the same floats (spheres far from the origin, a
/// tiny sphere on a large one), or a triangle whose corners do, would read back as an open or broken mesh.
void checkFloatsHold(const TriangleMesh& m) {
    using F3 = std::array<float, 3>;
    std::vector<std::pair<F3, std::size_t>> rounded(m.vertices.size());
    for (std::size_t i = 0; i < m.vertices.size(); ++i) {
        const Vec3& v = m.vertices[i];
        rounded[i] = {{float(v[0]), float(v[1]), float(v[2])}, i};
        for (float x : rounded[i].first)
            if (!std::isfinite(x))
                throw std::invalid_argument(
                    "writeMesh: vertex " + std::to_string(i) +
                    " is beyond single precision (3.4e38): binary STL cannot hold it; "
                    "write .obj or .ply (full precision)");
    }
    std::sort(rounded.begin(), rounded.end());
    std::size_t merged = 0, example = 0;
    for (std::size_t k = 1; k < rounded.size(); ++k)
        if (rounded[k].first == rounded[k - 1].first &&
            m.vertices[rounded[k].second] != m.vertices[rounded[k - 1].second]) {
            if (merged++ == 0) example = rounded[k].second;
        }
    if (merged > 0) {
        const Vec3& v = m.vertices[example];
        std::ostringstream s;
        s << std::setprecision(6) << "writeMesh: binary STL holds single-precision floats, and " << merged
          << " of " << m.vertices.size() << " vertices would merge with another when rounded to them (vertex "
          << example << " at " << v[0] << ", " << v[1] << ", " << v[2]
          << "): read back, the surface would be open; write .obj or .ply (full precision), or move the "
             "spheres "
             "nearer the origin";
        throw std::invalid_argument(s.str());
    }
}

} // namespace

std::string formatStl(const TriangleMesh& m) {
    if (m.triangles.size() > 0xffffffffu)
        throw std::invalid_argument("writeMesh: " + std::to_string(m.triangles.size()) +
                                    " triangles do not fit binary STL's 32-bit count");
    checkFloatsHold(m);
    std::string out(80, ' ');
    const char head[] = "binary STL written by yade-mss";
    std::memcpy(out.data(), head, sizeof(head) - 1);
    put<std::uint32_t>(out, std::uint32_t(m.triangles.size()));
    for (const auto& t : m.triangles) {
        const Vec3 &a = m.vertices[std::size_t(t[0])], &b = m.vertices[std::size_t(t[1])],
                   &c = m.vertices[std::size_t(t[2])];
        Vec3 n = (b - a).cross(c - a);
        if (n.norm() > 0) n.normalize();
        for (const Vec3& v : {n, a, b, c})
            for (int k = 0; k < 3; ++k) put<float>(out, float(v[k]));
        put<std::uint16_t>(out, 0);
    }
    return out;
}

std::string formatObj(const TriangleMesh& m) {
    std::ostringstream out;
    out << std::setprecision(17) << "# written by yade-mss: " << m.vertices.size() << " vertices, "
        << m.triangles.size() << " triangles, counter-clockwise seen from outside\n";
    for (const Vec3& v : m.vertices) out << "v " << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
    for (const auto& t : m.triangles) out << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
    return out.str();
}

std::string formatPly(const TriangleMesh& m) {
    std::ostringstream head;
    head << "ply\nformat binary_little_endian 1.0\ncomment written by yade-mss\nelement vertex "
         << m.vertices.size() << "\nproperty double x\nproperty double y\nproperty double z\nelement face "
         << m.triangles.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
    std::string out = head.str();
    out.reserve(out.size() + 24 * m.vertices.size() + 13 * m.triangles.size());
    for (const Vec3& v : m.vertices)
        for (int k = 0; k < 3; ++k) put<double>(out, v[k]);
    for (const auto& t : m.triangles) {
        put<std::uint8_t>(out, 3);
        for (int k = 0; k < 3; ++k) put<std::int32_t>(out, t[std::size_t(k)]);
    }
    return out;
}

} // namespace mss::detail
