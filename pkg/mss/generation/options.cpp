#include "mss/options.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>

namespace mss {

namespace {

constexpr double kIntMax = 2147483647.0;
constexpr double kInt64Max = 9223372036854775807.0;

using T = OptionType;
namespace c = command;

std::string numberText(double v) {
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    std::ostringstream os;
    os.precision(15);
    os << v;
    return os.str();
}

std::string commandName(unsigned cmd) {
    switch (cmd) {
    case c::Generate:
        return "generate";
    case c::Compare:
        return "compare";
    case c::Info:
        return "info";
    case c::Batch:
        return "batch";
    case c::Preview:
        return "preview";
    case c::Curve:
        return "curve";
    case c::Ochart:
        return "ochart";
    case c::Export:
        return "export";
    case c::Surface:
        return "surface";
    case c::Spheropolygon:
        return "spheropolygon";
    case c::Triaxial:
        return "triaxial";
    default:
        return "options";
    }
}

std::vector<double> numbers(const std::string& text) {
    std::vector<double> out;
    std::string t = text;
    for (char& ch : t)
        if (ch == ',') ch = ' ';
    std::istringstream is(t);
    std::string word;
    while (is >> word) {
        char* end = nullptr;
        const double v = std::strtod(word.c_str(), &end);
        if (end == word.c_str() || *end != '\0') return {};
        out.push_back(v);
    }
    return out;
}

} // namespace

std::size_t editDistance(const std::string& a, const std::string& b) {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diag = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t up = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] != b[j - 1])});
            diag = up;
        }
    }
    return row[b.size()];
}

const OptionSpec* findOption(const std::string& name, unsigned cmd) {
    for (const OptionSpec& s : optionTable())
        if (name == s.name && (cmd == 0 || (s.commands & cmd))) return &s;
    return nullptr;
}

std::string optionRange(const OptionSpec& s) {
    if (s.type != T::Integer && s.type != T::Number) return "";
    const bool lowEnd = std::isfinite(s.low), highEnd = std::isfinite(s.high) && s.high < kInt64Max &&
                                                        !(s.type == T::Integer && s.high >= kIntMax);
    if (lowEnd && highEnd)
        return "in " + std::string(s.lowOpen ? "(" : "[") + numberText(s.low) + ", " + numberText(s.high) +
               (s.highOpen ? ")" : "]");
    // an open end at infinity: infinity itself is refused
    if (lowEnd) return (s.lowOpen ? "> " : ">= ") + numberText(s.low) + (s.highOpen ? " and finite" : "");
    if (highEnd) return (s.highOpen ? "< " : "<= ") + numberText(s.high);
    return "";
}

OptionValue parseOption(const OptionSpec& s, const std::string& text) {
    const std::string where = "options";
    auto bad = [&](const std::string& what) {
        return OptionError(where, s.name, ": '" + text + "' " + what);
    };
    switch (s.type) {
    case T::Integer: {
        errno = 0;
        char* end = nullptr;
        const long long v = std::strtoll(text.c_str(), &end, 10);
        if (text.empty() || end == text.c_str() || *end != '\0' || errno == ERANGE)
            throw bad("is not an integer");
        checkOption(s, v);
        return v;
    }
    case T::Number: {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (text.empty() || end == text.c_str() || *end != '\0') throw bad("is not a number");
        checkOption(s, v);
        return v;
    }
    case T::Flag:
        if (text == "true" || text == "1" || text == "yes") return true;
        if (text == "false" || text == "0" || text == "no") return false;
        throw bad("is not true or false");
    case T::Choice:
        checkOption(s, text);
        return text;
    case T::Text:
        if (text.empty()) throw bad("is empty");
        return text;
    case T::Point: {
        const std::vector<double> v = numbers(text);
        if (v.size() != 3) throw bad("is not X,Y,Z (3 numbers)");
        const Vec3 p(v[0], v[1], v[2]);
        checkOption(s, p);
        return p;
    }
    case T::Point2: {
        const std::vector<double> v = numbers(text);
        if (v.size() != 2) throw bad("is not X,Y (2 numbers)");
        const Vec3 p(v[0], v[1], 0.0);
        checkOption(s, p);
        return p;
    }
    case T::Planes: {
        const std::vector<double> v = numbers(text);
        if (v.size() != 6) throw bad("is not PX,PY,PZ,NX,NY,NZ (6 numbers)");
        Plane p;
        p.point = Vec3(v[0], v[1], v[2]);
        p.normal = Vec3(v[3], v[4], v[5]);
        std::vector<Plane> planes{p};
        checkOption(s, planes);
        return planes;
    }
    case T::Files:
        return std::vector<std::string>{text};
    }
    throw bad("has a type the table does not know");
}

void checkOption(const OptionSpec& s, const OptionValue& value) {
    const std::string where = "options";
    auto fail = [&](const std::string& detail) { throw OptionError(where, s.name, detail); };
    auto range = [&](double v, const std::string& shown) {
        const bool ok = (s.lowOpen ? v > s.low : v >= s.low) && (s.highOpen ? v < s.high : v <= s.high);
        if (!ok) fail(" must be " + optionRange(s) + ", got " + shown);
    };
    switch (s.type) {
    case T::Integer:
        if (const long long* v = std::get_if<long long>(&value)) return range(double(*v), std::to_string(*v));
        fail(" must be an integer");
        break;
    case T::Number:
        if (const double* v = std::get_if<double>(&value)) return range(*v, numberText(*v));
        if (const long long* v = std::get_if<long long>(&value)) return range(double(*v), std::to_string(*v));
        fail(" must be a number");
        break;
    case T::Flag:
        if (!std::holds_alternative<bool>(value)) fail(" must be true or false");
        break;
    case T::Choice: {
        const std::string* v = std::get_if<std::string>(&value);
        if (!v) fail(" must be text");
        std::string all = s.choices;
        std::istringstream is(all);
        std::string word, listed;
        while (std::getline(is, word, '|')) {
            if (word == *v) return;
            listed += (listed.empty() ? "" : ", ") + word;
        }
        fail(" must be one of " + listed + ", got '" + *v + "'");
        break;
    }
    case T::Text:
        if (!std::holds_alternative<std::string>(value)) fail(" must be text");
        break;
    case T::Point: {
        const Vec3* v = std::get_if<Vec3>(&value);
        if (!v) fail(" must be 3 numbers");
        if (!v->allFinite()) fail(" must be 3 finite numbers");
        break;
    }
    case T::Point2: {
        const Vec3* v = std::get_if<Vec3>(&value);
        if (!v) fail(" must be 2 numbers");
        if (!v->allFinite()) fail(" must be 2 finite numbers");
        break;
    }
    case T::Planes: {
        const auto* v = std::get_if<std::vector<Plane>>(&value);
        if (!v) fail(" must be a list of planes (point and normal)");
        for (const Plane& p : *v) try {
                validatePlane(p, s.name);
            } catch (const std::invalid_argument& e) { // "planes: a constraint plane needs ..."
                const std::string what = e.what();
                fail(": " + what.substr(what.find(": ") + 2));
            }
        break;
    }
    case T::Files:
        if (!std::holds_alternative<std::vector<std::string>>(value)) fail(" must be a list of files");
        break;
    }
}

namespace {

double asNumber(const OptionValue& v) {
    return std::holds_alternative<long long>(v) ? double(std::get<long long>(v)) : std::get<double>(v);
}

int asInt(const OptionValue& v) {
    return int(std::get<long long>(v));
}

/// Puts one checked value where the core takes it; the front ends' own options (output, workers, ...) are
/// checked, not kept.
void apply(Settings& st, const std::string& name, const OptionValue& v) {
    GenerateOptions& g = st.generate;
    if (name == "nSpheres")
        g.nSpheres = asInt(v);
    else if (name == "eta")
        g.eta = asNumber(v);
    else if (name == "dice")
        g.dice = asNumber(v);
    else if (name == "rMin")
        g.rMin = asNumber(v);
    else if (name == "rMinVoxels")
        g.rMinVoxels = asNumber(v);
    else if (name == "maxIterations")
        g.maxIterations = asInt(v);
    else if (name == "deltaMin")
        g.deltaMin = asNumber(v);
    else if (name == "keepSymmetry")
        g.keepSymmetry = std::get<bool>(v);
    else if (name == "polish")
        g.polish = std::get<bool>(v);
    else if (name == "threads")
        g.threads = asInt(v);
    else if (name == "clip")
        g.clip = std::get<bool>(v);
    else if (name == "contacts")
        st.keepContacts = std::get<bool>(v);
    else if (name == "contactGap")
        st.contactGap = asNumber(v);
    else if (name == "neighbourProtrusion")
        g.neighbourProtrusion = asNumber(v);
    else if (name == "refill")
        g.refill = std::get<bool>(v);
    else if (name == "maxProtrusion")
        g.maxProtrusion = asNumber(v);
    else if (name == "method")
        g.method = std::get<std::string>(v) == "paper" ? Method::Paper : Method::Optimized;
    else if (name == "planes")
        g.planes = st.compare.planes = std::get<std::vector<Plane>>(v);
    else if (name == "voxelSize")
        st.voxelSize = asNumber(v);
    else if (name == "resolution")
        st.resolution.resolution = st.compare.resolution = asInt(v);
    else if (name == "supersample")
        st.supersample = st.compare.supersample = asInt(v);
    else if (name == "memoryLimit")
        st.resolution.memoryLimit = static_cast<std::size_t>(asNumber(v) * 1073741824.0);
    else if (name == "origin")
        st.origin = std::get<Vec3>(v), st.originGiven = true;
    else if (name == "label")
        st.label = std::get<long long>(v);
    else if (name == "offset")
        st.compare.offset = asNumber(v);
    else if (name == "align") {
        st.compare.align = parseAlign(std::get<std::string>(v));
        st.compare.checkFrame = false; // an explicit none scores the set as written
    } else if (name == "clumpId")
        st.clumpId = std::get<long long>(v);
    else if (name == "exact")
        st.compare.exact = std::get<bool>(v);
    else if (name == "samples")
        st.compare.samples = static_cast<std::size_t>(std::get<long long>(v));
    else if (name == "seed")
        st.compare.seed = static_cast<std::uint64_t>(std::get<long long>(v));
    else if (name == "tolerance")
        st.surface.tolerance = asNumber(v);
    else if (name == "maxEdge")
        st.surface.maxEdge = asNumber(v);
    else if (name == "maxTriangles")
        st.surface.maxTriangles = static_cast<std::size_t>(asInt(v));
    else if (name == "scale")
        st.scale = asNumber(v);
    else if (name == "maxWork")
        g.maxWork = st.compare.maxWork = st.surface.maxWork = asNumber(v);
}

} // namespace

Settings settingsFrom(const OptionValues& values, unsigned cmd) {
    const std::string where = commandName(cmd);
    Settings st;
    for (const OptionSpec& s : optionTable()) // the table's defaults first
        if ((s.commands & cmd) && *s.fallback && !values.count(s.name))
            apply(st, s.name, parseOption(s, s.fallback));
    for (const auto& [name, value] : values) {
        const OptionSpec* s = findOption(name, cmd);
        if (!s) {
            std::string best;
            std::size_t bestD = 4; // suggest only what is close
            for (const OptionSpec& o : optionTable())
                if (o.commands & cmd) {
                    const std::size_t d = editDistance(name, o.name);
                    if (d < bestD) bestD = d, best = o.name;
                }
            throw OptionError(where, "'" + name + "'",
                              " is not an option of " + where +
                                  (best.empty() ? "" : " (did you mean '" + best + "'?)"));
        }
        try {
            checkOption(*s, value);
        } catch (const OptionError& e) {
            throw OptionError(where, e.option(), e.detail());
        }
        apply(st, name, value);
    }
    if (values.count("voxelSize") && values.count("resolution") &&
        (cmd & (command::Generate | command::Batch)))
        throw OptionError(where, "voxelSize", " and resolution both given: give one of them");
    if (st.voxelSize > 0) st.resolution.voxelSize = st.voxelSize, st.resolution.resolution = 0;
    return st;
}

} // namespace mss
