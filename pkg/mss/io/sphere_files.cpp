// Sphere files: writeSpheres by the format table (io/formats.cpp), readSpheres of any generator's text.
#include "mss/io.hpp"
#include "mss/io/atomic_file.hpp"
#include "mss/io/input_file.hpp"
#include "mss/io/template_spheres.hpp"
#include "mss/mesh.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <set>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

namespace mss {

void writeSpheres(const SphereSet& s, const std::string& path) {
    validateSpheres(s, "writeSpheres");
    const FileFormat* f = findFormat(path, FileKind::Spheres);
    if (!f || !f->formatSpheres)
        throw std::invalid_argument("writeSpheres: " + path + ": unknown extension '" + fileExtension(path) +
                                    "' (expected " + formatList(FileKind::Spheres, true) + ")");
    detail::writeFileAtomically("writeSpheres", path, f->formatSpheres(s));
}

namespace {
/// The integer in @p tok (a clump id), or -1 when it is not one.
long long clumpIdOf(const std::string& tok) {
    char* end = nullptr;
    const double v = std::strtod(tok.c_str(), &end);
    if (end == tok.c_str() || *end != '\0' || !(v >= 0.0) || v > 9e15 || v != std::floor(v)) return -1;
    return static_cast<long long>(v);
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
        // 'inf' are numbers, refused below, never a header)
        if (s.size() == 0) {
            char* end = nullptr;
            std::strtod(first.c_str(), &end);
            if (end == first.c_str() || *end != '\0') continue;
        }
        std::istringstream all(line);
        double v[4];
        for (double& x : v) {
            std::string tok;
            if (!(all >> tok))
                throw std::invalid_argument("readSpheres: " + path + ": line " + std::to_string(lineNo) +
                                            ": expected x y z r");
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
        if (all >> fifth) { // a clump id: never merged with another by rounding or by being dropped
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
