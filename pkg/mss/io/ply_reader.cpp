// Polygon File Format (PLY), ASCII and binary of either byte order: our own reader (CGAL 5.5's, fuzzed,
// reserved gigabytes on the say-so of a header and ran into undefined behaviour on malformed files;
// fuzz/regressions keeps those inputs). One row of io/formats.cpp.
#include "mss/io/mesh_readers.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <map>
#include <sstream>
#include <string_view>

namespace mss::detail {

namespace {

/// Polygon File Format (PLY), ASCII and binary of either byte order: "vertex" elements give x, y, z; "face"
/// elements a list property (vertex_indices); other elements and properties are skipped.
/// A PLY file's header: its elements and their properties (Turk's PLY format, ASCII and binary).
struct PlyProperty {
    std::string name, type, countType; // countType non-empty: a list
};
struct PlyElement {
    std::string name;
    long long count;
    std::vector<PlyProperty> props;
};
struct PlyHeader {
    std::vector<PlyElement> elements;
    std::string format;
};

int plyTypeSize(const std::string& t) {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32")
        return 4;
    if (t == "double" || t == "float64") return 8;
    return 0;
}

/// One header line's property: a scalar or a list.
void addPlyProperty(const std::string& path, const std::string& at, const std::vector<std::string_view>& w,
                    std::vector<PlyElement>& elements) {
    if (elements.empty()) fail(path, at + "property before any element");
    if (w.size() >= 5 && w[1] == "list") {
        if (!plyTypeSize(std::string(w[2])) || !plyTypeSize(std::string(w[3])))
            fail(path, at + "unknown type in list property");
        elements.back().props.push_back({std::string(w[4]), std::string(w[3]), std::string(w[2])});
    } else if (w.size() >= 3 && plyTypeSize(std::string(w[1]))) {
        elements.back().props.push_back({std::string(w[2]), std::string(w[1]), ""});
    } else {
        fail(path, at + "malformed property");
    }
}

/// Reads the header from @p buf; @p pos: where the data begin, afterwards. Checks that the counts announced
/// fit in the file before anything is allocated.
PlyHeader readPlyHeader(const std::string& path, const FileBytes& buf, std::size_t& pos) {
    PlyHeader h;
    std::size_t lineNo = 0;
    bool end = false;
    auto nextLine = [&]() {
        std::size_t e = pos;
        while (e < buf.size() && buf[e] != '\n') ++e;
        std::string_view line(buf.data() + pos, e - pos);
        pos = std::min(buf.size(), e + 1);
        ++lineNo;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        return line;
    };
    if (nextLine() != "ply") fail(path, "not a PLY file (it must start with ply)");
    while (pos < buf.size()) {
        const auto w = words(nextLine());
        if (w.empty()) continue;
        const std::string at = "PLY header line " + std::to_string(lineNo) + ": ";
        if (w[0] == "format") {
            if (w.size() < 2 ||
                (w[1] != "ascii" && w[1] != "binary_little_endian" && w[1] != "binary_big_endian"))
                fail(path, at + "unknown format");
            h.format = std::string(w[1]);
        } else if (w[0] == "comment" || w[0] == "obj_info") {
        } else if (w[0] == "element") {
            long long n;
            if (w.size() < 3 || !parseInt(w[2], n) || n < 0)
                fail(path, at + "element needs a name and a count");
            if (n > static_cast<long long>(buf.size()))
                fail(path, at + "element count " + std::to_string(n) + " is more than the file holds");
            h.elements.push_back({std::string(w[1]), n, {}});
        } else if (w[0] == "property") {
            addPlyProperty(path, at, w, h.elements);
        } else if (w[0] == "end_header") {
            end = true;
            break;
        } else {
            fail(path, at + "unexpected '" + std::string(w[0]) + "'");
        }
    }
    if (h.format.empty() || !end) fail(path, "malformed PLY header (format or end_header missing)");
    long long items = 0;
    bool hasVertex = false, hasFace = false;
    for (const PlyElement& e : h.elements) {
        items += e.count;
        hasVertex = hasVertex || e.name == "vertex";
        hasFace = hasFace || e.name == "face";
    }
    if (!hasVertex || !hasFace) fail(path, "PLY file without vertex or face element");
    if (items * (h.format == "ascii" ? 2 : 1) > static_cast<long long>(buf.size() - pos))
        fail(path, "PLY header announces " + std::to_string(items) + " elements, more than the file holds");
    return h;
}

/// Reads one value after another from the PLY data, ASCII or binary (either byte order).
class PlyValues {
public:
    PlyValues(const std::string& path, const FileBytes& buf, std::size_t pos, const std::string& format)
        : path_(path), buf_(buf), pos_(pos), start_(pos), ascii_(format == "ascii"),
          swap_(format == "binary_big_endian") {
        if (ascii_) tokens_ = words(std::string_view(buf.data() + pos, buf.size() - pos));
    }
    double operator()(const std::string& type) {
        if (ascii_) {
            if (tok_ >= tokens_.size()) fail(path_, "PLY data ends early" + where());
            double v;
            if (!parseDouble(tokens_[tok_++], v))
                fail(path_, "PLY data" + where() + ": '" + std::string(tokens_[tok_ - 1].substr(0, 40)) +
                                "' is not a number");
            return v;
        }
        const int n = plyTypeSize(type);
        if (pos_ + static_cast<std::size_t>(n) > buf_.size()) fail(path_, "PLY data ends early" + where());
        unsigned char b[8];
        std::memcpy(b, buf_.data() + pos_, static_cast<std::size_t>(n));
        pos_ += static_cast<std::size_t>(n);
        if (swap_) std::reverse(b, b + n);
        return binary(type, b);
    }

    /// Where the last value read lies: " at line N" (ASCII: the file's line) or " at byte N" (binary), for
    /// messages (counted only then).
    std::string where() const {
        if (!ascii_) return " at byte " + std::to_string(pos_);
        const char* at = tok_ == 0                ? buf_.data() + start_
                         : tok_ <= tokens_.size() ? tokens_[tok_ - 1].data()
                                                  : buf_.data() + buf_.size();
        return " at line " + std::to_string(1 + std::count(buf_.data(), at, '\n'));
    }

private:
    template <class T> static double as(const unsigned char* b) {
        T v;
        std::memcpy(&v, b, sizeof(T));
        return static_cast<double>(v);
    }
    static double binary(const std::string& type, const unsigned char* b) {
        if (type == "char" || type == "int8") return as<std::int8_t>(b);
        if (type == "uchar" || type == "uint8") return as<std::uint8_t>(b);
        if (type == "short" || type == "int16") return as<std::int16_t>(b);
        if (type == "ushort" || type == "uint16") return as<std::uint16_t>(b);
        if (type == "int" || type == "int32") return as<std::int32_t>(b);
        if (type == "uint" || type == "uint32") return as<std::uint32_t>(b);
        if (type == "float" || type == "float32") return as<float>(b);
        return as<double>(b);
    }
    const std::string& path_;
    const FileBytes& buf_;
    std::size_t pos_, start_;
    bool ascii_, swap_;
    std::vector<std::string_view> tokens_;
    std::size_t tok_ = 0;
};

/// The elements' data: vertices (x, y, z) and faces (a list of vertex indices); other elements and
/// properties are read past.
/// The faces of a PLY file, kept until every vertex is read (a file may list its faces first): their vertex
/// indices one after another, and where each face starts.
struct PlyFaces {
    std::vector<long long> indices;
    std::vector<std::size_t> starts;
};

void readPlyElement(const std::string& path, const PlyElement& e, PlyValues& value, TriangleMesh& mesh,
                    PlyFaces& faces) {
    int ix = -1, iy = -1, iz = -1, il = -1;
    for (int k = 0; k < static_cast<int>(e.props.size()); ++k) {
        const PlyProperty& p = e.props[static_cast<std::size_t>(k)];
        if (p.name == "x") ix = k;
        if (p.name == "y") iy = k;
        if (p.name == "z") iz = k;
        if (!p.countType.empty() && (il < 0 || p.name == "vertex_indices" || p.name == "vertex_index"))
            il = k;
    }
    if (e.name == "vertex" && (ix < 0 || iy < 0 || iz < 0)) fail(path, "PLY vertex element without x, y, z");
    if (e.name == "face" && il < 0) fail(path, "PLY face element without a list of vertex indices");
    std::vector<long long> poly;
    for (long long n = 0; n < e.count; ++n) {
        Vec3 v = Vec3::Zero();
        poly.clear();
        for (int k = 0; k < static_cast<int>(e.props.size()); ++k) {
            const PlyProperty& p = e.props[static_cast<std::size_t>(k)];
            if (p.countType.empty()) {
                const double x = value(p.type);
                if (k == ix) v.x() = x;
                if (k == iy) v.y() = x;
                if (k == iz) v.z() = x;
                continue;
            }
            const double len = value(p.countType);
            if (!(len >= 0 && len <= 1e6) || len != std::floor(len)) {
                std::ostringstream os;
                os << "PLY " << e.name << " " << n << value.where() << ": a list of " << len
                   << " values (a count from 0 to 1e6 is expected)";
                fail(path, os.str());
            }
            for (long long q = 0; q < static_cast<long long>(len); ++q) {
                const double idx = value(p.type);
                if (k == il) {
                    if (idx != std::floor(idx) || std::abs(idx) > 9e18) {
                        std::ostringstream os;
                        os << "PLY " << e.name << " " << n << value.where() << ": vertex index " << idx
                           << " is not a whole number";
                        fail(path, os.str());
                    }
                    poly.push_back(static_cast<long long>(idx));
                }
            }
        }
        if (e.name == "vertex") {
            if (!v.allFinite())
                fail(path, "PLY vertex " + std::to_string(n) + " has a non-finite coordinate");
            mesh.vertices.push_back(v);
        } else if (e.name == "face") {
            faces.starts.push_back(faces.indices.size());
            faces.indices.insert(faces.indices.end(), poly.begin(), poly.end());
        }
    }
}

} // namespace

TriangleMesh readPly(const std::string& path) {
    const FileBytes buf(path);
    std::size_t pos = 0;
    const PlyHeader h = readPlyHeader(path, buf, pos);
    PlyValues value(path, buf, pos, h.format);
    TriangleMesh mesh;
    PlyFaces faces;
    for (const PlyElement& e : h.elements) readPlyElement(path, e, value, mesh, faces);
    std::vector<long long> poly;
    for (std::size_t f = 0; f < faces.starts.size(); ++f) {
        const std::size_t end = f + 1 < faces.starts.size() ? faces.starts[f + 1] : faces.indices.size();
        poly.assign(faces.indices.begin() + long(faces.starts[f]), faces.indices.begin() + long(end));
        addPolygon(mesh, poly, path, "PLY face " + std::to_string(f));
    }
    if (mesh.triangles.empty()) fail(path, "PLY file has no faces");
    return mesh;
}

} // namespace mss::detail
