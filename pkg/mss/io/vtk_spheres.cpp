// Sphere sets in legacy VTK files (what CLUMP's outputVTK= and our own .vtk write): POLYDATA points with a
// radius array, ASCII or BINARY (big-endian, as the legacy format prescribes).
#include "mss/io.hpp"
#include "mss/io/input_file.hpp"
#include "mss/io/sphere_writers.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <sstream>
#include <stdexcept>

namespace mss {

namespace {

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

/// A cursor over the file: header lines as words, data arrays as ASCII numbers or big-endian binary.
class VtkCursor {
public:
    VtkCursor(const std::string& path, std::vector<char> buf) : path_(path), buf_(std::move(buf)) {}

    [[noreturn]] void fail(const std::string& what) const {
        throw std::invalid_argument("readSpheres: " + path_ + ": VTK: " + what);
    }
    bool atEnd() {
        skipSpace();
        return pos_ >= buf_.size();
    }
    /// The words of the next non-empty line.
    std::vector<std::string> line() {
        std::vector<std::string> w;
        while (w.empty() && pos_ < buf_.size()) {
            std::size_t e = pos_;
            while (e < buf_.size() && buf_[e] != '\n') ++e;
            std::istringstream is(std::string(buf_.data() + pos_, e - pos_));
            for (std::string t; is >> t;) w.push_back(t);
            pos_ = std::min(buf_.size(), e + 1);
        }
        return w;
    }
    void setBinary(bool b) { binary_ = b; }
    /// @p n values of VTK type @p type.
    std::vector<double> values(std::size_t n, const std::string& type) {
        const int size = typeSize(type);
        if (size == 0) fail("unknown data type '" + type + "'");
        if (n > buf_.size()) fail(std::to_string(n) + " values announced, more than the file holds");
        std::vector<double> out;
        out.reserve(n);
        if (!binary_) {
            for (std::size_t i = 0; i < n; ++i) {
                skipSpace();
                std::size_t e = pos_;
                while (e < buf_.size() && !std::isspace(static_cast<unsigned char>(buf_[e]))) ++e;
                const std::string tok(buf_.data() + pos_, e - pos_);
                if (tok.empty())
                    fail("data end early (" + std::to_string(i) + " of " + std::to_string(n) + ")");
                char* end = nullptr;
                const double v = std::strtod(tok.c_str(), &end);
                if (end == tok.c_str() || *end != '\0') fail("'" + tok + "' is not a number");
                out.push_back(v);
                pos_ = e;
            }
            return out;
        }
        if (n * std::size_t(size) > buf_.size() - pos_) fail("binary data end early");
        for (std::size_t i = 0; i < n; ++i, pos_ += std::size_t(size)) out.push_back(binaryValue(type, size));
        if (pos_ < buf_.size() && buf_[pos_] == '\n') ++pos_;
        return out;
    }

private:
    static int typeSize(const std::string& type) {
        const std::string t = lower(type);
        if (t == "float") return 4;
        if (t == "double") return 8;
        if (t == "int" || t == "unsigned_int") return 4;
        if (t == "long" || t == "unsigned_long" || t == "vtkidtype") return 8;
        if (t == "short" || t == "unsigned_short") return 2;
        if (t == "char" || t == "unsigned_char" || t == "bit") return 1;
        return 0;
    }
    double binaryValue(const std::string& type, int size) const {
        unsigned char b[8];
        std::memcpy(b, buf_.data() + pos_, std::size_t(size));
        std::reverse(b, b + size); // big-endian in the file
        const std::string t = lower(type);
        auto as = [&b](auto v) {
            std::memcpy(&v, b, sizeof(v));
            return static_cast<double>(v);
        };
        if (t == "float") return as(float{});
        if (t == "double") return as(double{});
        if (t == "int") return as(std::int32_t{});
        if (t == "unsigned_int") return as(std::uint32_t{});
        if (t == "long" || t == "vtkidtype") return as(std::int64_t{});
        if (t == "unsigned_long") return as(std::uint64_t{});
        if (t == "short") return as(std::int16_t{});
        if (t == "unsigned_short") return as(std::uint16_t{});
        if (t == "char") return as(std::int8_t{});
        return as(std::uint8_t{});
    }
    void skipSpace() {
        while (pos_ < buf_.size() && std::isspace(static_cast<unsigned char>(buf_[pos_]))) ++pos_;
    }
    std::string path_;
    std::vector<char> buf_;
    std::size_t pos_ = 0;
    bool binary_ = false;
};

std::size_t count(VtkCursor& c, const std::string& word) {
    char* end = nullptr;
    const long long n = std::strtoll(word.c_str(), &end, 10);
    if (end == word.c_str() || *end != '\0' || n < 0) c.fail("bad count '" + word + "'");
    return static_cast<std::size_t>(n);
}

bool isRadiusName(const std::string& name) {
    const std::string n = lower(name);
    return n == "radius" || n == "radii" || n == "r";
}

} // namespace

SphereSet readVtkSpheres(const std::string& path) {
    detail::requireRegularFile("readSpheres", path);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::invalid_argument("readSpheres: " + path + ": cannot open file");
    VtkCursor c(path,
                std::vector<char>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>()));
    c.line(); // "# vtk DataFile Version x.y"
    c.line(); // the title
    const std::vector<std::string> mode = c.line();
    if (mode.empty() || (lower(mode[0]) != "ascii" && lower(mode[0]) != "binary"))
        c.fail("third line must be ASCII or BINARY");
    c.setBinary(lower(mode[0]) == "binary");
    const std::vector<std::string> dataset = c.line();
    if (dataset.size() < 2 || lower(dataset[0]) != "dataset" || lower(dataset[1]) != "polydata")
        c.fail("only POLYDATA point sets are read (got '" + (dataset.size() > 1 ? dataset[1] : "") + "')");
    std::vector<double> points, radii;
    std::vector<std::string> arrays; // names seen, for the message when no radius is there
    while (!c.atEnd()) {
        const std::vector<std::string> w = c.line();
        const std::string key = lower(w[0]);
        if (key == "points" && w.size() >= 3) {
            points = c.values(3 * count(c, w[1]), w[2]);
        } else if ((key == "vertices" || key == "lines" || key == "polygons" || key == "triangle_strips") &&
                   w.size() >= 3) {
            c.values(count(c, w[2]), "int"); // cells: not needed
        } else if (key == "point_data" || key == "cell_data") {
            if (key == "cell_data") break; // cell arrays follow: nothing of ours
        } else if (key == "scalars" && w.size() >= 3) {
            const std::size_t comps = w.size() >= 4 ? count(c, w[3]) : 1;
            std::vector<std::string> next = c.line();
            if (next.empty() || lower(next[0]) != "lookup_table") c.fail("SCALARS without LOOKUP_TABLE");
            std::vector<double> v = c.values(comps * (points.size() / 3), w[2]);
            arrays.push_back(w[1]);
            if (isRadiusName(w[1]) && comps == 1) radii = std::move(v);
        } else if (key == "field" && w.size() >= 3) {
            const std::size_t k = count(c, w[2]);
            for (std::size_t a = 0; a < k; ++a) {
                const std::vector<std::string> h = c.line();
                if (h.size() < 4) c.fail("malformed FIELD array");
                std::vector<double> v = c.values(count(c, h[1]) * count(c, h[2]), h[3]);
                arrays.push_back(h[0]);
                if (isRadiusName(h[0]) && h[1] == "1") radii = std::move(v);
            }
        } else {
            c.fail("unexpected '" + w[0] + "'");
        }
    }
    if (points.empty()) c.fail("no points");
    if (radii.empty()) {
        std::string names;
        for (const std::string& n : arrays) names += (names.empty() ? "" : ", ") + n;
        c.fail("no point array named radius" + (names.empty() ? std::string() : " (arrays: " + names + ")"));
    }
    if (radii.size() != points.size() / 3)
        c.fail(std::to_string(points.size() / 3) + " points but " + std::to_string(radii.size()) + " radii");
    SphereSet s;
    for (std::size_t i = 0; i < radii.size(); ++i)
        s.add(Vec3(points[3 * i], points[3 * i + 1], points[3 * i + 2]), radii[i]);
    validateSpheres(s, "readSpheres: " + path);
    return s;
}

namespace detail {

std::string formatVtk(const SphereSet& s) {
    std::ostringstream out;
    out << std::setprecision(17)
        << "# vtk DataFile Version 3.0\nyade-mss spheres\nASCII\nDATASET POLYDATA\nPOINTS " << s.size()
        << " double\n";
    for (std::size_t i = 0; i < s.size(); ++i)
        out << s.centers[i].x() << ' ' << s.centers[i].y() << ' ' << s.centers[i].z() << '\n';
    out << "VERTICES " << s.size() << ' ' << 2 * s.size() << '\n';
    for (std::size_t i = 0; i < s.size(); ++i) out << "1 " << i << '\n';
    out << "POINT_DATA " << s.size() << "\nSCALARS radius double 1\nLOOKUP_TABLE default\n";
    for (std::size_t i = 0; i < s.size(); ++i) out << s.radii[i] << '\n';
    return out.str();
}

} // namespace detail

} // namespace mss
