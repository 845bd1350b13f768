#include "mss/io.hpp"
#include "mss/io/input_file.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>
#include <type_traits>

namespace mss {

namespace {
[[noreturn]] void fail(const std::string& path, const std::string& what) {
    throw std::invalid_argument("readNpy: " + path + ": " + what);
}
} // namespace

namespace {

/// NumPy writes headers of a few hundred bytes (padded to 64); a longer one is refused before it is read.
constexpr std::size_t kMaxNpyHeader = 1 << 16;

/// The position just after key @p key's ':' in a Python dict literal, or npos.
std::size_t afterKey(const std::string& h, const std::string& key) {
    for (const char q : {'\'', '"'}) {
        const std::string quoted = std::string(1, q) + key + q;
        std::size_t at = h.find(quoted);
        if (at == std::string::npos) continue;
        at = h.find_first_not_of(" \t", at + quoted.size());
        if (at == std::string::npos || h[at] != ':') return std::string::npos;
        return h.find_first_not_of(" \t", at + 1);
    }
    return std::string::npos;
}

/// The text between @p open and @p close after key @p key (a quoted string: either quote), or false.
bool headerValue(const std::string& h, const std::string& key, char open, char close, std::string& out) {
    std::size_t at = afterKey(h, key);
    if (at == std::string::npos) return false;
    if (open == '\'' && h[at] == '"') open = close = '"';
    if (h[at] != open) return false;
    const std::size_t end = h.find(close, at + 1);
    if (end == std::string::npos) return false;
    out = h.substr(at + 1, end - at - 1);
    return true;
}

/// The word (letters) after key @p key, or false.
bool headerWord(const std::string& h, const std::string& key, std::string& out) {
    const std::size_t at = afterKey(h, key);
    if (at == std::string::npos) return false;
    std::size_t end = at;
    while (end < h.size() && std::isalpha(static_cast<unsigned char>(h[end]))) ++end;
    out = h.substr(at, end - at);
    return !out.empty();
}

/// What a .npy header says (NumPy format versions 1-3), checked: a 3-D boolean or integer array.
struct NpyHeader {
    std::vector<long long> shape;
    bool fortran = false;
    char kind = 0;
    int width = 0;
    std::size_t dataOffset = 0; ///< bytes before the data
    bool bigEndian = false;     ///< values stored most significant byte first (swapped on reading)
};

NpyHeader readNpyHeader(const std::string& path, std::ifstream& in, std::streamoff size) {
    char magic[10] = {};
    in.read(magic, 10);
    if (in.gcount() < 10 || std::memcmp(magic, "\x93NUMPY", 6) != 0)
        fail(path, "not a .npy file (bad magic)");
    const int major = static_cast<unsigned char>(magic[6]);
    std::size_t headerLen = 0, pre = 10;
    if (major == 1) {
        headerLen = static_cast<unsigned char>(magic[8]) | (static_cast<unsigned char>(magic[9]) << 8);
    } else if (major == 2 || major == 3) {
        char more[2];
        in.read(more, 2);
        headerLen = static_cast<unsigned char>(magic[8]) | (static_cast<unsigned char>(magic[9]) << 8) |
                    (static_cast<std::size_t>(static_cast<unsigned char>(more[0])) << 16) |
                    (static_cast<std::size_t>(static_cast<unsigned char>(more[1])) << 24);
        pre = 12;
    } else {
        fail(path, "unsupported .npy version " + std::to_string(major));
    }
    if (static_cast<std::streamoff>(pre + headerLen) > size) fail(path, "truncated header");
    if (headerLen > kMaxNpyHeader)
        fail(path, "header of " + std::to_string(headerLen) + " bytes (at most " +
                       std::to_string(kMaxNpyHeader) + ": not a volume's)");
    std::string header(headerLen, '\0');
    in.read(header.data(), static_cast<std::streamsize>(headerLen));
    if (in.gcount() != static_cast<std::streamsize>(headerLen)) fail(path, "truncated header");
    // the header is a Python dict literal; its three keys are found by plain scans (no regex, no recursion:
    // std::regex recursed once per character and overflowed the stack on long headers)
    std::string descr, order, shapeText;
    if (!headerValue(header, "descr", '\'', '\'', descr) || !headerWord(header, "fortran_order", order) ||
        !headerValue(header, "shape", '(', ')', shapeText) || !(order == "True" || order == "False")) {
        const std::size_t d = header.find("'descr'");
        const std::size_t open = d == std::string::npos ? d : header.find_first_not_of(": ", d + 7);
        if (open != std::string::npos && header[open] == '[') // numpy writes a structured dtype as a list
            fail(path, "a structured dtype (named fields): save one field as a plain array "
                       "(np.save(path, volume['field']))");
        fail(path, "malformed header");
    }
    const bool fortran = order == "True";
    std::vector<long long> shape;
    {
        std::stringstream ss(shapeText);
        std::string tok;
        while (std::getline(ss, tok, ',')) {
            if (tok.find_first_not_of(" \t") == std::string::npos) continue;
            if (shape.size() == 3) fail(path, "array must be 3-D, got more dimensions");
            try {
                std::size_t used = 0;
                shape.push_back(std::stoll(tok, &used));
                if (tok.find_first_not_of(" \tL", used) != std::string::npos) fail(path, "malformed shape");
            } catch (const std::invalid_argument&) {
                fail(path, "malformed shape");
            } catch (const std::out_of_range&) {
                fail(path, "malformed shape");
            }
        }
    }
    if (shape.size() != 3) fail(path, "array must be 3-D, got " + std::to_string(shape.size()) + "-D");
    for (long long d : shape) {
        if (d == 0) fail(path, "array is empty (shape has a zero)");
        if (d < 0) fail(path, "malformed shape (a negative size: " + std::to_string(d) + ")");
    }
    if (descr.size() < 3) fail(path, "unsupported dtype '" + descr + "'");
    const char endian = descr[0], kind = descr[1];
    int width = 0;
    try {
        width = std::stoi(descr.substr(2));
    } catch (...) {
        fail(path, "unsupported dtype '" + descr + "'");
    }
    if (!(kind == 'b' || kind == 'u' || kind == 'i') ||
        !(width == 1 || width == 2 || width == 4 || width == 8))
        fail(path, "dtype '" + descr + "' is not boolean or integer (threshold a grey-level volume first)");
    NpyHeader h;
    h.bigEndian = endian == '>' && width > 1;
    h.shape = shape;
    h.fortran = fortran;
    h.kind = kind;
    h.width = width;
    h.dataOffset = pre + headerLen;
    return h;
}

/// The solid flags of @p n values of type T (label >= 0: equal to it; else non-zero), and with @p labels the
/// distinct non-zero values (up to 64; asked only where the value changes, as neighbours mostly share one).
template <class T>
void typedFlags(const char* raw, std::size_t n, long long label, std::vector<std::uint8_t>& on,
                std::set<long long>* labels) {
    long long last = 0;
    for (std::size_t q = 0; q < n; ++q) {
        T v;
        std::memcpy(&v, raw + q * sizeof(T), sizeof(T));
        const long long x = static_cast<long long>(v);
        const bool solid = label >= 0 ? x == label : x != 0;
        on[q] = solid;
        if (labels && label < 0 && solid && x != last && labels->size() < 64) {
            labels->insert(x);
            last = x;
        }
    }
}

/// A .npy file's header and data, checked: its size against the file's, the grid's against the limits;
/// the bytes in the machine's order.
struct NpyData {
    NpyHeader header;
    std::vector<char> raw;
    std::size_t count = 0;
};

NpyData readNpyData(const std::string& path, double voxelSize, const Vec3& origin) {
    if (!(voxelSize > 0.0) || !std::isfinite(voxelSize)) {
        std::ostringstream os;
        os << "voxel size must be > 0 and finite, got " << voxelSize;
        fail(path, os.str());
    }
    if (!origin.allFinite()) fail(path, "origin is not finite");
    detail::requireRegularFile("readNpy", path);
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) fail(path, "cannot open file");
    const std::streamoff size = in.tellg();
    in.seekg(0);
    NpyData d;
    d.header = readNpyHeader(path, in, size);
    const std::vector<long long>& shape = d.header.shape;
    const int width = d.header.width;
    // the header's word against the file's size first (in long double: a lying shape overflows 64 bits)
    const std::uintmax_t held = static_cast<std::uintmax_t>(size) - d.header.dataOffset;
    const long double wanted = static_cast<long double>(shape[0]) * shape[1] * shape[2] * width;
    if (wanted > static_cast<long double>(held)) {
        std::ostringstream os;
        os << "truncated data: the shape " << shape[0] << "x" << shape[1] << "x" << shape[2] << " needs "
           << static_cast<double>(wanted) << " bytes after the header, more than the file holds (" << held
           << ")";
        fail(path, os.str());
    }
    checkGridSize("readNpy", {shape[0], shape[1], shape[2]}, 1, std::size_t(1) << 40);
    d.count = static_cast<std::size_t>(shape[0] * shape[1] * shape[2]);
    d.raw.resize(d.count * static_cast<std::size_t>(width));
    in.read(d.raw.data(), static_cast<std::streamsize>(d.raw.size()));
    if (static_cast<std::size_t>(in.gcount()) != d.raw.size()) fail(path, "truncated data");
    if (d.header.bigEndian)
        for (std::size_t q = 0; q < d.raw.size(); q += static_cast<std::size_t>(width))
            std::reverse(d.raw.begin() + static_cast<std::ptrdiff_t>(q),
                         d.raw.begin() + static_cast<std::ptrdiff_t>(q) + width);
    return d;
}

/// @p in (the file's order) into @p out (the grid's, x fastest): a copy for Fortran order, a transpose of x
/// and z in 32 x 32 tiles for C order (both sides stay in cache).
template <class T, class U>
void toGridOrder(const std::vector<T>& in, const std::vector<long long>& shape, bool fortran, U* out) {
    const std::size_t n0 = std::size_t(shape[0]), n1 = std::size_t(shape[1]), n2 = std::size_t(shape[2]);
    if (fortran) {
        std::copy(in.begin(), in.end(), out);
        return;
    }
    constexpr std::size_t kTile = 32;
    for (std::size_t b = 0; b < n1; ++b)
        for (std::size_t a0 = 0; a0 < n0; a0 += kTile)
            for (std::size_t c0 = 0; c0 < n2; c0 += kTile)
                for (std::size_t c = c0; c < std::min(n2, c0 + kTile); ++c)
                    for (std::size_t a = a0; a < std::min(n0, a0 + kTile); ++a)
                        out[a + n0 * (b + n1 * c)] = in[c + n2 * (b + n1 * a)];
}

/// Calls @p f with a value of the C++ type of a .npy element: kind 'b', 'i' or 'u', @p width bytes.
template <class F> void byType(char kind, int width, F&& f) {
    switch (width) {
    case 1:
        if (kind == 'i')
            f(std::int8_t{});
        else
            f(std::uint8_t{});
        break;
    case 2:
        if (kind == 'u')
            f(std::uint16_t{});
        else
            f(std::int16_t{});
        break;
    case 4:
        if (kind == 'u')
            f(std::uint32_t{});
        else
            f(std::int32_t{});
        break;
    default:
        if (kind == 'u')
            f(std::uint64_t{});
        else
            f(std::int64_t{});
    }
}

/// The labels of @p n values of type T as 64-bit integers.
template <class T> void typedLabels(const char* raw, std::size_t n, std::vector<std::int64_t>& out) {
    for (std::size_t q = 0; q < n; ++q) {
        T v;
        std::memcpy(&v, raw + q * sizeof(T), sizeof(T));
        out[q] = static_cast<std::int64_t>(v);
    }
}

} // namespace

VoxelGrid readNpy(const std::string& path, double voxelSize, const Vec3& origin, long long label) {
    const NpyData d = readNpyData(path, voxelSize, origin);
    const std::vector<long long>& shape = d.header.shape;
    const char kind = d.header.kind;
    const int width = d.header.width;
    const std::size_t count = d.count;
    const std::vector<char>& raw = d.raw;
    GridSpec g;
    g.dims = {static_cast<int>(shape[0]), static_cast<int>(shape[1]), static_cast<int>(shape[2])};
    g.h = voxelSize;
    g.origin = origin;
    VoxelGrid out(g, 0);
    // the flags in the file's order (one typed pass), then into the grid's (x fastest)
    std::vector<std::uint8_t> on(count);
    std::set<long long> labels; // without a label, several labels would merge grains: refused below
    byType(kind, width, [&](auto zero) {
        typedFlags<decltype(zero)>(raw.data(), count, label, on, kind == 'b' ? nullptr : &labels);
    });
    std::size_t solid = 0;
    for (std::uint8_t v : on) solid += v;
    toGridOrder(on, shape, d.header.fortran, out.data.data());
    if (labels.size() > 1) {
        std::ostringstream os;
        os << "the volume holds " << (labels.size() < 64 ? "" : "at least ") << labels.size() << " labels (";
        int k = 0;
        for (long long l : labels) {
            if (k == 20) {
                os << ", ...";
                break;
            }
            os << (k++ ? ", " : "") << l;
        }
        os << "): choose one grain with the option label";
        fail(path, os.str());
    }
    if (solid == 0)
        fail(path,
             label >= 0 ? "no voxel has label " + std::to_string(label) : "the volume has no solid voxel");
    return out;
}

LabelGrid readNpyLabels(const std::string& path, double voxelSize, const Vec3& origin) {
    const NpyData d = readNpyData(path, voxelSize, origin);
    const char kind = d.header.kind;
    std::vector<std::int64_t> flat(d.count);
    byType(kind, d.header.width, [&](auto zero) {
        using T = decltype(zero);
        if constexpr (std::is_same_v<T, std::uint64_t>) // a label over 2^63 would turn negative: refused
            for (std::size_t q = 0; q < d.count; ++q) {
                std::uint64_t v;
                std::memcpy(&v, d.raw.data() + q * 8, 8);
                if (v > std::uint64_t(std::numeric_limits<std::int64_t>::max()))
                    fail(path, "a label over 2^63 - 1");
            }
        typedLabels<T>(d.raw.data(), d.count, flat);
    });
    LabelGrid out;
    out.spec.dims = {int(d.header.shape[0]), int(d.header.shape[1]), int(d.header.shape[2])};
    out.spec.h = voxelSize;
    out.spec.origin = origin;
    out.labels.resize(d.count);
    toGridOrder(flat, d.header.shape, d.header.fortran, out.labels.data());
    return out;
}

} // namespace mss
