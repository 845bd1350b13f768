// Internal to the mesh readers (one file per format: stl_reader.cpp, obj_reader.cpp, off_reader.cpp,
// ply_reader.cpp; the table that names them is io/formats.cpp): a file's bytes, the error every reader
// throws, the text helpers they share (mesh_readers.cpp).
#pragma once

#include "mss/mesh.hpp"

#include <charconv>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace mss::detail {

/// The readers' error: names the file and the problem.
[[noreturn]] inline void fail(const std::string& path, const std::string& what) {
    throw std::invalid_argument("readMesh: " + path + ": " + what);
}

/// A whole file in memory, read-only, read in one piece (a byte-by-byte stream iterator took a third of
/// reading an ASCII STL). Not mapped: a file that shrinks while mapped kills the reader with SIGBUS; a read
/// just stops short. Empty for a file that is not a regular file or cannot be read.
class FileBytes {
public:
    explicit FileBytes(const std::string& path) {
        std::error_code ec;
        if (!std::filesystem::is_regular_file(path, ec)) return; // (a directory's size is no size)
        const std::uintmax_t size = std::filesystem::file_size(path, ec);
        std::ifstream in(path, std::ios::binary);
        if (ec || !in || size == 0) return;
        copy_.resize(static_cast<std::size_t>(size));
        in.read(copy_.data(), static_cast<std::streamsize>(size));
        copy_.resize(static_cast<std::size_t>(in.gcount()));
        data_ = copy_.data();
        size_ = copy_.size();
    }
    FileBytes(const FileBytes&) = delete;
    FileBytes& operator=(const FileBytes&) = delete;

    const char* data() const { return data_; }
    std::size_t size() const { return size_; }
    char operator[](std::size_t i) const { return data_[i]; }

private:
    const char* data_ = nullptr;
    std::size_t size_ = 0;
    std::vector<char> copy_;
};

/// The number that is all of [@p b, @p e): an optional '+', then what std::from_chars takes; false if it is
/// not one. Plain decimals ([-]digits[.digits][e[+-]digits]) whose digits make an integer m <= 2^53 and whose
/// value is m times 10^k, |k| <= 22, take Clinger's fast path: m and 10^|k| are exact doubles, so one
/// multiplication or division rounds once, to the same double as std::from_chars (which took a fifth of
/// reading an ASCII STL); anything else goes to std::from_chars.
inline bool parseDouble(const char* b, const char* e, double& v) {
    static constexpr double kPow10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                          1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                          1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
    const char* p = b;
    const bool negative = p < e && *p == '-';
    p += negative;
    std::uint64_t m = 0;
    int digits = 0, scale = 0; // significant digits read; 10^scale divides m
    const char* d0 = p;
    for (; p < e && unsigned(*p - '0') < 10; ++p, ++digits) m = 10 * m + unsigned(*p - '0');
    bool plain = p > d0;
    if (plain && p < e && *p == '.') {
        const char* f0 = ++p;
        for (; p < e && unsigned(*p - '0') < 10; ++p, ++digits, ++scale) m = 10 * m + unsigned(*p - '0');
        plain = p > f0;
    }
    int exponent = 0;
    if (plain && p < e && (*p == 'e' || *p == 'E')) {
        ++p;
        const bool minus = p < e && *p == '-';
        p += p < e && (*p == '-' || *p == '+');
        const char* x0 = p;
        for (; p < e && unsigned(*p - '0') < 10 && exponent < 10000; ++p)
            exponent = 10 * exponent + (*p - '0');
        plain = p > x0;
        if (minus) exponent = -exponent;
    }
    const int k = exponent - scale;
    if (plain && p == e && digits <= 19 && m <= (std::uint64_t(1) << 53) && k >= -22 && k <= 22) {
        const double x = double(m);
        v = k >= 0 ? x * kPow10[k] : x / kPow10[-k];
        if (negative) v = -v;
        return true;
    }
    const char* start = b + (b < e && *b == '+');
    const auto r = std::from_chars(start, e, v);
    return b < e && r.ec == std::errc() && r.ptr == e;
}

/// Reads an STL file, ASCII or binary (stl_reader.cpp).
TriangleMesh readStl(const std::string& path);
/// Wavefront OBJ (obj_reader.cpp).
TriangleMesh readObj(const std::string& path);
/// Object File Format (off_reader.cpp).
TriangleMesh readOff(const std::string& path);
/// Polygon File Format, ASCII and binary (ply_reader.cpp).
TriangleMesh readPly(const std::string& path);

/// Faces with more than three corners become triangle fans; indices are checked against the vertex count.
void addPolygon(TriangleMesh& mesh, const std::vector<long long>& poly, const std::string& path,
                const std::string& where);
bool parseDouble(std::string_view w, double& v);
bool parseInt(std::string_view w, long long& v);
/// Splits a line into whitespace-separated words.
std::vector<std::string_view> words(std::string_view line);
/// The vertex in words @p first .. @p first + 2 of a line (OBJ "v x y z", OFF "x y z"); @p at names the line.
Vec3 vertexOf(const std::vector<std::string_view>& w, std::size_t first, const std::string& path,
              const std::string& at);

/// Line by line, with its number, '#' comments removed.
template <class F> void forLines(const FileBytes& buf, F&& f) {
    std::size_t i = 0, lineNo = 0;
    while (i < buf.size()) {
        std::size_t e = i;
        while (e < buf.size() && buf[e] != '\n') ++e;
        std::string_view line(buf.data() + i, e - i);
        const auto hash = line.find('#');
        if (hash != std::string_view::npos) line = line.substr(0, hash);
        if (!f(line, ++lineNo)) return;
        i = e + 1;
    }
}

} // namespace mss::detail
