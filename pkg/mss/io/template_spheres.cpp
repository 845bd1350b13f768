// Sphere sets read back from other DEM codes' clump templates, as `mss export` writes them: a LIGGGHTS
// include file (fix particletemplate/multisphere, spheres inline), a Kratos cluster (.clu), a MercuryDPM
// clump folder, a PFC data file (clump template create with its pebbles) and a yade-mss clumps file. A
// template holds the spheres in its own frame (the centre of mass at the origin); where the header says where
// the grain was generated (c and R, a point p at c + R p), the spheres go back there, so that `mss compare`
// scores them against the grain they came from.
#include "mss/io/template_spheres.hpp"

#include "mss/io.hpp"
#include "mss/io/input_file.hpp"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <sys/stat.h>

namespace mss::detail {

namespace {

constexpr std::size_t kMaxTemplateBytes = std::size_t(1) << 28; // 256 MiB: a template of millions of spheres

[[noreturn]] void fail(const std::string& path, const std::string& what) {
    throw std::invalid_argument("readSpheres: " + path + ": " + what);
}

std::string readWhole(const std::string& path) {
    requireRegularFile("readSpheres", path);
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(path, "cannot open file");
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    if (size < 0 || std::size_t(size) > kMaxTemplateBytes)
        fail(path, "a template file of " + std::to_string(size) + " bytes (at most 256 MiB are read)");
    in.seekg(0);
    std::string text(std::size_t(size), '\0');
    in.read(text.data(), size);
    return text;
}

double number(const std::string& path, const std::string& tok, const char* what) {
    char* end = nullptr;
    const double v = std::strtod(tok.c_str(), &end);
    if (tok.empty() || end == tok.c_str() || *end != '\0' || !std::isfinite(v))
        fail(path, std::string(what) + ": '" + tok + "' is not a finite number");
    return v;
}

std::vector<std::string> words(const std::string& line) {
    std::istringstream is(line);
    std::vector<std::string> out;
    std::string w;
    while (is >> w) out.push_back(w);
    return out;
}

/// Where the grain was generated, from a header line "c = x y z" and "R = a b c ; d e f ; g h i (rows)" after
/// the comment mark @p mark; false where the header does not say (another program's template).
bool placement(const std::string& path, const std::string& text, const std::string& mark, Vec3& c,
               Eigen::Matrix3d& R) {
    bool haveC = false, haveR = false;
    std::istringstream is(text);
    std::string line;
    while (std::getline(is, line)) {
        if (line.compare(0, mark.size(), mark) != 0) continue;
        std::vector<std::string> w = words(line.substr(mark.size()));
        if (w.size() == 5 && w[0] == "c" && w[1] == "=") {
            for (int i = 0; i < 3; ++i) c[i] = number(path, w[std::size_t(2 + i)], "the header's c");
            haveC = true;
        } else if (w.size() == 14 && w[0] == "R" && w[1] == "=" && w[5] == ";" && w[9] == ";") {
            const std::size_t at[3] = {2, 6, 10};
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j)
                    R(i, j) = number(path, w[at[i] + std::size_t(j)], "the header's R");
            haveR = true;
        }
    }
    if (haveC != haveR) fail(path, "the header gives c or R but not both");
    if (!haveR) return false;
    if (!((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-9) ||
        R.determinant() < 0)
        fail(path, "the header's R is not a rotation");
    return true;
}

void place(SphereSet& s, const Vec3& c, const Eigen::Matrix3d& R) {
    for (Vec3& p : s.centers) p = c + R * p;
}

/// A command file's commands: from @p comment to the end of a line dropped, a line ending in @p more joined
/// with the next, and with @p vectors a vector's parentheses and commas made spaces.
std::vector<std::string> commandsOf(const std::string& text, char comment, const std::string& more,
                                    bool vectors) {
    std::vector<std::string> out;
    std::istringstream is(text);
    std::string line, command;
    while (std::getline(is, line)) {
        const auto at = line.find(comment);
        if (at != std::string::npos) line.resize(at);
        while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t'))
            line.pop_back();
        const bool joined =
            line.size() >= more.size() && line.compare(line.size() - more.size(), more.size(), more) == 0;
        if (joined) line.resize(line.size() - more.size());
        if (vectors)
            for (char& ch : line)
                if (ch == '(' || ch == ')' || ch == ',') ch = ' ';
        command += line + " ";
        if (!joined) {
            out.push_back(command);
            command.clear();
        }
    }
    if (!command.empty()) out.push_back(command);
    return out;
}

/// The LIGGGHTS input file's commands, as LIGGGHTS reads them: '#' comments, '&' continuations.
std::vector<std::string> liggghtsCommands(const std::string& text) {
    return commandsOf(text, '#', "&", false);
}

SphereSet liggghtsSpheres(const std::string& path, const std::string& text) {
    std::vector<std::vector<std::string>> found;
    for (const std::string& c : liggghtsCommands(text)) {
        std::vector<std::string> w = words(c);
        if (w.size() > 3 && w[0] == "fix" && w[3] == "particletemplate/multisphere") found.push_back(w);
    }
    if (found.size() != 1)
        fail(path, "the file holds " + std::to_string(found.size()) +
                       " fix particletemplate/multisphere commands (one is read)");
    const std::vector<std::string>& w = found[0];
    long long n = -1;
    std::size_t at = 0;
    for (std::size_t i = 4; i + 1 < w.size(); ++i) {
        if (w[i] == "nspheres") {
            const double v = number(path, w[i + 1], "nspheres");
            if (!(v >= 1 && v <= 1e8 && v == std::floor(v))) fail(path, "nspheres must be an integer >= 1");
            n = static_cast<long long>(v);
        } else if (w[i] == "spheres" && at == 0) {
            at = i + 1;
        }
    }
    if (n < 0 || at == 0) fail(path, "the template has no nspheres or no spheres keyword");
    if (w[at] == "file")
        fail(path, "the template's spheres are in the file " +
                       (at + 1 < w.size() ? w[at + 1] : std::string("?")) +
                       ": read that file (x y z r a line)");
    if (at + std::size_t(4 * n) > w.size())
        fail(path, "nspheres " + std::to_string(n) + " but fewer numbers follow spheres");
    SphereSet s;
    for (long long k = 0; k < n; ++k) {
        const std::size_t q = at + std::size_t(4 * k);
        s.add(Vec3(number(path, w[q], "a sphere's x"), number(path, w[q + 1], "a sphere's y"),
                   number(path, w[q + 2], "a sphere's z")),
              number(path, w[q + 3], "a sphere's radius"));
    }
    Vec3 c;
    Eigen::Matrix3d R;
    if (placement(path, text, "#", c, R)) place(s, c, R);
    return s;
}

SphereSet kratosSpheres(const std::string& path, const std::string& text) {
    std::vector<std::string> lines;
    {
        std::istringstream is(text);
        std::string line;
        while (std::getline(is, line)) {
            if (!line.empty() && line.back() == '\r') line.pop_back();
            if (line.compare(0, 2, "//") != 0) lines.push_back(line);
        }
    }
    SphereSet s;
    Vec3 center = Vec3::Zero();
    bool inside = false, ended = false;
    for (std::size_t i = 0; i < lines.size(); ++i) {
        const std::string& l = lines[i];
        if (l.compare(0, 23, "Begin centers_and_radii") == 0) {
            inside = true;
        } else if (l.compare(0, 21, "End centers_and_radii") == 0) {
            inside = false;
            ended = true;
        } else if (inside) {
            std::vector<std::string> w = words(l);
            if (w.empty()) continue;
            if (w.size() != 4) fail(path, "a line of centers_and_radii must be x y z r: '" + l + "'");
            s.add(Vec3(number(path, w[0], "x"), number(path, w[1], "y"), number(path, w[2], "z")),
                  number(path, w[3], "r"));
        } else if (l.compare(0, 28, "Particle_center_and_diameter") == 0 && i + 1 < lines.size()) {
            std::vector<std::string> w = words(lines[i + 1]);
            if (w.size() < 3) fail(path, "Particle_center_and_diameter needs x y z diameter");
            center = Vec3(number(path, w[0], "the centre's x"), number(path, w[1], "the centre's y"),
                          number(path, w[2], "the centre's z"));
        }
    }
    if (!ended) fail(path, "no End centers_and_radii");
    for (Vec3& p : s.centers) p -= center; // as Kratos reads a cluster: relative to that centre
    Vec3 c;
    Eigen::Matrix3d R;
    if (placement(path, text, "//", c, R)) place(s, c, R);
    return s;
}

/// The PFC data file's commands: ';' comments, '...' continuations, vectors "(x,y,z)" read as "x y z" (PFC
/// takes both).
std::vector<std::string> pfcCommands(const std::string& text) {
    return commandsOf(text, ';', "...", true);
}

std::string lower(std::string w) {
    for (char& ch : w) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    return w;
}

SphereSet pfcSpheres(const std::string& path, const std::string& text) {
    std::vector<std::vector<std::string>> found;
    for (const std::string& c : pfcCommands(text)) {
        std::vector<std::string> w = words(c);
        if (w.size() > 3 && lower(w[0]) == "clump" && lower(w[1]) == "template" && lower(w[2]) == "create")
            found.push_back(w);
    }
    if (found.size() != 1)
        fail(path, "the file holds " + std::to_string(found.size()) +
                       " clump template create commands (one is read)");
    const std::vector<std::string>& w = found[0];
    SphereSet s;
    Vec3 at = Vec3::Zero();
    bool havePebbles = false;
    for (std::size_t i = 3; i < w.size(); ++i) {
        const std::string k = lower(w[i]);
        if (k == "pebbles" && !havePebbles && i + 1 < w.size()) {
            const double v = number(path, w[i + 1], "pebbles");
            if (!(v >= 1 && v <= 1e8 && v == std::floor(v))) fail(path, "pebbles must be an integer >= 1");
            const auto n = static_cast<std::size_t>(v);
            if (i + 2 + 4 * n > w.size())
                fail(path, "pebbles " + std::to_string(n) + " but fewer numbers follow");
            for (std::size_t k2 = 0; k2 < n; ++k2) {
                const std::size_t q = i + 2 + 4 * k2;
                const double r = number(path, w[q], "a pebble's radius");
                s.add(Vec3(number(path, w[q + 1], "a pebble's x"), number(path, w[q + 2], "a pebble's y"),
                           number(path, w[q + 3], "a pebble's z")),
                      r);
            }
            havePebbles = true;
            i += 1 + 4 * n;
        } else if (k == "position" && i + 3 < w.size()) {
            at = Vec3(number(path, w[i + 1], "the position's x"), number(path, w[i + 2], "the position's y"),
                      number(path, w[i + 3], "the position's z"));
            i += 3;
        }
    }
    if (!havePebbles)
        fail(path,
             "the clump template has no pebbles keyword (a bubblepack or surface template: its pebbles are "
             "made by PFC)");
    Vec3 c;
    Eigen::Matrix3d R;
    if (placement(path, text, ";", c, R)) { // PFC's template: the pebbles about the centroid at the position
        for (Vec3& p : s.centers) p -= at;
        place(s, c, R);
    }
    return s;
}

/// A clumps file written by mss export --format yade: "x y z r clumpId" rows (one clump) about the centre of
/// mass, put back where the header says the grain was generated.
SphereSet yadeExportSpheres(const std::string& path, const std::string& text) {
    SphereSet s;
    std::istringstream is(text);
    std::string line;
    while (std::getline(is, line)) {
        const auto hash = line.find('#');
        if (hash != std::string::npos) line.resize(hash);
        std::vector<std::string> w = words(line);
        if (w.empty()) continue;
        if (w.size() != 5) fail(path, "a sphere line must be x y z r clumpId: '" + line + "'");
        s.add(Vec3(number(path, w[0], "x"), number(path, w[1], "y"), number(path, w[2], "z")),
              number(path, w[3], "r"));
    }
    Vec3 c;
    Eigen::Matrix3d R;
    if (placement(path, text, "#", c, R)) place(s, c, R);
    return s;
}

} // namespace

bool readTemplateSpheres(const std::string& path, SphereSet& out) {
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) {
        const std::string pebbles = path + "/Clump/Clump.txt";
        struct stat ps {};
        if (::stat(pebbles.c_str(), &ps) != 0) return false; // not a MercuryDPM clump: a directory, refused
        out = readSpheres(pebbles);
        const std::string about = path + "/mss_export.txt";
        struct stat as {};
        if (::stat(about.c_str(), &as) == 0) {
            Vec3 c;
            Eigen::Matrix3d R;
            if (placement(about, readWhole(about), "", c, R)) place(out, c, R);
        }
        return true;
    }
    std::string head;
    {
        requireRegularFile("readSpheres", path);
        std::ifstream in(path, std::ios::binary);
        if (!in) return false;
        head.resize(65536);
        in.read(head.data(), std::streamsize(head.size()));
        head.resize(std::size_t(in.gcount()));
    }
    if (head.find("particletemplate/multisphere") != std::string::npos) {
        out = liggghtsSpheres(path, readWhole(path));
        return true;
    }
    if (head.find("mss export --format yade") != std::string::npos) {
        out = yadeExportSpheres(path, readWhole(path));
        return true;
    }
    if (lower(head).find("clump template create") != std::string::npos) {
        out = pfcSpheres(path, readWhole(path));
        return true;
    }
    if (head.find("Begin centers_and_radii") != std::string::npos) {
        out = kratosSpheres(path, readWhole(path));
        return true;
    }
    return false;
}

} // namespace mss::detail
