// .csv sphere files: "x,y,z,r" (CLUMP's columns). One row of io/formats.cpp.
#include "mss/io.hpp"
#include "mss/io/sphere_writers.hpp"

#include <string>

namespace mss::detail {

std::string formatCsv(const SphereSet& s) {
    // appendNumber's printf "%.17g" (std::to_chars: what an ostream at precision 17 wrote, at a fifth of the
    // cost; a batch writes a file a grain)
    std::string out = "x,y,z,r\n";
    out.reserve(out.size() + 100 * s.size());
    const auto put = [&](double v, char end) {
        appendNumber(out, v, NumberText::Precision17);
        out.push_back(end);
    };
    for (std::size_t i = 0; i < s.size(); ++i) {
        put(s.centers[i].x(), ',');
        put(s.centers[i].y(), ',');
        put(s.centers[i].z(), ',');
        put(s.radii[i], '\n');
    }
    return out;
}

} // namespace mss::detail
