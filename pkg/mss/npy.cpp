#include "mss/npy.hpp"

#include <cmath>
#include <cstring>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <stdexcept>

namespace mss {

namespace {
[[noreturn]] void fail(const std::string& path, const std::string& what) {
    throw std::invalid_argument("readNpy: " + path + ": " + what);
}
} // namespace

namespace {

/// What a .npy header says (NumPy format versions 1-3), checked: a 3-D boolean or integer array.
struct NpyHeader {
    std::vector<long long> shape;
    bool fortran = false;
    char kind = 0;
    int width = 0;
    std::size_t dataOffset = 0; ///< bytes before the data
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
    std::string header(headerLen, '\0');
    in.read(header.data(), static_cast<std::streamsize>(headerLen));
    std::smatch mDescr, mOrder, mShape;
    if (!std::regex_search(header, mDescr, std::regex("'descr'\\s*:\\s*'([^']*)'")) ||
        !std::regex_search(header, mOrder, std::regex("'fortran_order'\\s*:\\s*(True|False)")) ||
        !std::regex_search(header, mShape, std::regex("'shape'\\s*:\\s*\\(([^)]*)\\)")))
        fail(path, "malformed header");
    const std::string descr = mDescr[1];
    const bool fortran = mOrder[1] == "True";
    std::vector<long long> shape;
    {
        std::string s = mShape[1];
        std::stringstream ss(s);
        std::string tok;
        while (std::getline(ss, tok, ',')) {
            if (tok.find_first_not_of(" \t") == std::string::npos) continue;
            try {
                shape.push_back(std::stoll(tok));
            } catch (...) {
                fail(path, "malformed shape");
            }
        }
    }
    if (shape.size() != 3) fail(path, "array must be 3-D, got " + std::to_string(shape.size()) + "-D");
    for (long long d : shape)
        if (d <= 0) fail(path, "array is empty (shape has a zero)");
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
    if (endian == '>' && width > 1) fail(path, "big-endian arrays are not supported");
    NpyHeader h;
    h.shape = shape;
    h.fortran = fortran;
    h.kind = kind;
    h.width = width;
    h.dataOffset = pre + headerLen;
    return h;
}

} // namespace

VoxelGrid readNpy(const std::string& path, double voxelSize, const Vec3& origin, long long label) {
    if (!(voxelSize > 0.0) || !std::isfinite(voxelSize)) {
        std::ostringstream os;
        os << "voxel size must be > 0 and finite, got " << voxelSize;
        fail(path, os.str());
    }
    if (!origin.allFinite()) fail(path, "origin is not finite");
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) fail(path, "cannot open file");
    const std::streamoff size = in.tellg();
    in.seekg(0);
    const NpyHeader h = readNpyHeader(path, in, size);
    const std::vector<long long>& shape = h.shape;
    const bool fortran = h.fortran;
    const char kind = h.kind;
    const int width = h.width;
    checkGridSize("readNpy", {shape[0], shape[1], shape[2]}, 1, std::size_t(1) << 40);
    const std::size_t count = static_cast<std::size_t>(shape[0] * shape[1] * shape[2]);
    if (static_cast<std::uintmax_t>(size) < h.dataOffset + count * static_cast<std::size_t>(width))
        fail(path, "truncated data: expected " + std::to_string(count * width) +
                       " bytes after the header, file has " +
                       std::to_string(size - static_cast<std::streamoff>(h.dataOffset)));
    std::vector<char> raw(count * static_cast<std::size_t>(width));
    in.read(raw.data(), static_cast<std::streamsize>(raw.size()));
    if (static_cast<std::size_t>(in.gcount()) != raw.size()) fail(path, "truncated data");

    GridSpec g;
    g.dims = {static_cast<int>(shape[0]), static_cast<int>(shape[1]), static_cast<int>(shape[2])};
    g.h = voxelSize;
    g.origin = origin;
    VoxelGrid out(g, 0);
    auto value = [&](std::size_t q) -> long long {
        const char* p = raw.data() + q * width;
        switch (width) {
        case 1:
            return kind == 'i' ? static_cast<long long>(static_cast<std::int8_t>(*p))
                               : static_cast<unsigned char>(*p);
        case 2: {
            std::int16_t v;
            std::memcpy(&v, p, 2);
            return kind == 'u' ? static_cast<std::uint16_t>(v) : v;
        }
        case 4: {
            std::int32_t v;
            std::memcpy(&v, p, 4);
            return kind == 'u' ? static_cast<std::uint32_t>(v) : v;
        }
        default: {
            std::int64_t v;
            std::memcpy(&v, p, 8);
            return v;
        }
        }
    };
    std::size_t solid = 0;
    // without a label, a volume holding several labels would merge its grains into one solid: refuse it
    std::set<long long> labels;
    for (long long a = 0; a < shape[0]; ++a)
        for (long long b = 0; b < shape[1]; ++b)
            for (long long c = 0; c < shape[2]; ++c) {
                const std::size_t q = fortran ? static_cast<std::size_t>(a + shape[0] * (b + shape[1] * c))
                                              : static_cast<std::size_t>(c + shape[2] * (b + shape[1] * a));
                const long long v = value(q);
                const bool on = label >= 0 ? v == label : v != 0;
                if (label < 0 && on && kind != 'b' && labels.size() < 64) labels.insert(v);
                out(static_cast<int>(a), static_cast<int>(b), static_cast<int>(c)) = on;
                solid += on;
            }
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
        os << "): choose one grain with --label L (label= in Python)";
        fail(path, os.str());
    }
    if (solid == 0)
        fail(path,
             label >= 0 ? "no voxel has label " + std::to_string(label) : "the volume has no solid voxel");
    return out;
}

} // namespace mss
