// Sphere files: writeSpheres by the format table (io/formats.cpp), readSpheres of any generator's text.
#include "mss/io.hpp"
#include "mss/io/atomic_file.hpp"
#include "mss/io/input_file.hpp"
#include "mss/io/template_spheres.hpp"
#include "mss/mesh.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <set>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

namespace mss {

std::string formatSpheres(const SphereSet& s, const std::string& path) {
    validateSpheres(s, "writeSpheres");
    const FileFormat* f = findFormat(path, FileKind::Spheres);
    if (!f || !f->formatSpheres)
        throw std::invalid_argument("writeSpheres: " + path + ": unknown extension '" + fileExtension(path) +
                                    "' (expected " + formatList(FileKind::Spheres, true) + ")");
    return f->formatSpheres(s);
}

void writeSpheres(const SphereSet& s, const std::string& path) {
    const std::string text = formatSpheres(s, path);
    detail::writeFileAtomically("writeSpheres", path, text);
}

namespace {
/// The integer in @p tok (a clump id), or -1 when it is not one.
long long clumpIdOf(const std::string& tok) {
    char* end = nullptr;
    const double v = std::strtod(tok.c_str(), &end);
    if (end == tok.c_str() || *end != '\0' || !(v >= 0.0) || v > 9e15 || v != std::floor(v)) return -1;
    return static_cast<long long>(v);
}
/// The columns a header line names: x, y, z, r (or radius) and a clump id (clumpId, clump_id, clump, id),
/// in any order, case aside. A header that names none of them is text, the columns by position; one that
/// names some but not all four is refused, naming what it lacks (reading by position would mix them up).
std::array<int, 5> headerColumns(const std::string& line, const std::string& path, std::size_t lineNo) {
    std::array<int, 5> at{-1, -1, -1, -1, -1};
    std::istringstream words(line);
    int k = 0;
    for (std::string w; words >> w; ++k) {
        std::transform(w.begin(), w.end(), w.begin(), [](unsigned char c) { return std::tolower(c); });
        const int slot = w == "x"                                                           ? 0
                         : w == "y"                                                         ? 1
                         : w == "z"                                                         ? 2
                         : (w == "r" || w == "radius" || w == "rad")                        ? 3
                         : (w == "clumpid" || w == "clump_id" || w == "clump" || w == "id") ? 4
                                                                                            : -1;
        if (slot < 0) continue;
        if (at[std::size_t(slot)] >= 0)
            throw std::invalid_argument("readSpheres: " + path + ": line " + std::to_string(lineNo) +
                                        ": the header names '" + w + "' twice");
        at[std::size_t(slot)] = k;
    }
    const int named = int(at[0] >= 0) + int(at[1] >= 0) + int(at[2] >= 0) + int(at[3] >= 0);
    if (named == 0) return {0, 1, 2, 3, 4};
    if (named < 4) {
        std::string lacks;
        const char* names[4] = {"x", "y", "z", "r (or radius)"};
        for (int c = 0; c < 4; ++c)
            if (at[std::size_t(c)] < 0) lacks += (lacks.empty() ? "" : ", ") + std::string(names[c]);
        throw std::invalid_argument("readSpheres: " + path + ": line " + std::to_string(lineNo) +
                                    ": the header names no column " + lacks +
                                    " (a sphere file's columns: x, y, z, r, any order, named in its header)");
    }
    return at;
}
} // namespace

SphereSet readSpheres(const std::string& path, long long clumpId) {
    {
        SphereSet t; // another DEM code's template (mss export): one clump, no ids
        if (detail::readTemplateSpheres(path, t)) {
            if (clumpId >= 0)
                throw std::invalid_argument("readSpheres: " + path +
                                            ": a clump template holds one clump: no clump id to choose");
            validateSpheres(t, "readSpheres: " + path);
            return t;
        }
    }
    detail::requireRegularFile("readSpheres", path);
    std::ifstream in(path);
    if (!in) throw std::invalid_argument("readSpheres: " + path + ": cannot open file");
    {
        char head[5] = {};
        in.read(head, 5);
        if (in.gcount() == 5 && std::string(head, 5) == "# vtk") return readVtkSpheres(path);
        in.clear();
        in.seekg(0);
    }
    SphereSet s;
    std::vector<long long> ids; // clump id of each sphere read, -1 without one
    std::set<long long> distinct;
    std::string line;
    std::size_t lineNo = 0;
    std::array<int, 5> columns{0, 1, 2, 3, 4}; // x, y, z, r and the clump id (-1: none), by position
    while (std::getline(in, line)) {
        ++lineNo;
        if (lineNo == 1 && line.compare(0, 3, "\xEF\xBB\xBF") == 0)
            line.erase(0, 3); // a UTF-8 byte order mark
        const auto hash = line.find('#');
        if (hash != std::string::npos) line.resize(hash);
        for (char& c : line)
            if (c == ',' || c == ';' || c == '\t' || c == '\r') c = ' ';
        std::istringstream ls(line);
        std::string first;
        if (!(ls >> first)) continue;
        // a header line (x,y,z,r) is allowed before any data: one whose first word is not a number ('nan' and
        // 'inf' are numbers, refused below, never a header); where it names the columns, they are read by
        // name
        if (s.size() == 0) {
            char* end = nullptr;
            std::strtod(first.c_str(), &end);
            if (end == first.c_str() || *end != '\0') {
                columns = headerColumns(line, path, lineNo);
                continue;
            }
        }
        std::vector<std::string> toks;
        {
            std::istringstream all(line);
            for (std::string tok; all >> tok;) toks.push_back(tok);
        }
        const std::size_t need = std::size_t(*std::max_element(columns.begin(), columns.begin() + 4)) + 1;
        if (toks.size() < need)
            throw std::invalid_argument(
                "readSpheres: " + path + ": line " + std::to_string(lineNo) + ": expected x y z r" +
                (need > 4 ? " (in columns " + std::to_string(columns[0] + 1) + ", " +
                                std::to_string(columns[1] + 1) + ", " + std::to_string(columns[2] + 1) +
                                ", " + std::to_string(columns[3] + 1) + " as the header names them)"
                          : std::string()));
        double v[4];
        for (int c = 0; c < 4; ++c) {
            double& x = v[c];
            const std::string& tok = toks[std::size_t(columns[std::size_t(c)])];
            char* end = nullptr;
            x = std::strtod(tok.c_str(), &end);
            if (end == tok.c_str() || *end != '\0')
                throw std::invalid_argument("readSpheres: " + path + ": line " + std::to_string(lineNo) +
                                            ": '" + tok + "' is not a number");
            if (!std::isfinite(x))
                throw std::invalid_argument("readSpheres: " + path + ": line " + std::to_string(lineNo) +
                                            ": '" + tok + "' is not a finite number");
        }
        std::string fifth;
        long long id = -1;
        const int idColumn = columns[4];
        if (idColumn >= 0 && std::size_t(idColumn) < toks.size()) fifth = toks[std::size_t(idColumn)];
        if (!fifth.empty()) { // a clump id: never merged with another by rounding or by being dropped
            id = clumpIdOf(fifth);
            if (id < 0)
                throw std::invalid_argument("readSpheres: " + path + ": line " + std::to_string(lineNo) +
                                            ": clump id '" + fifth +
                                            "' is not an integer in [0, 9e15] (ids are never rounded)");
            distinct.insert(id);
        }
        s.add(Vec3(v[0], v[1], v[2]), v[3]);
        ids.push_back(id);
    }
    if (s.size() == 0) throw std::invalid_argument("readSpheres: " + path + ": no spheres in file");
    auto idList = [&] {
        std::ostringstream os;
        int k = 0;
        for (long long id : distinct) {
            if (k++ == 20) {
                os << ", ...";
                break;
            }
            os << (k > 1 ? ", " : "") << id;
        }
        return os.str();
    };
    if (clumpId >= 0) {
        SphereSet one;
        for (std::size_t i = 0; i < s.size(); ++i)
            if (ids[i] == clumpId) one.add(s.centers[i], s.radii[i]);
        if (one.size() == 0)
            throw std::invalid_argument(
                "readSpheres: " + path + ": no clump with id " + std::to_string(clumpId) +
                (distinct.empty() ? " (the file has no clump ids)" : " (clump ids: " + idList() + ")"));
        s = std::move(one);
    } else if (distinct.size() > 1) {
        throw std::invalid_argument("readSpheres: " + path + ": the file holds " +
                                    std::to_string(distinct.size()) + " clumps (ids " + idList() +
                                    "): choose one with the option clumpId");
    }
    validateSpheres(s, "readSpheres: " + path);
    return s;
}

} // namespace mss
