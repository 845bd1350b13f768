// .csv sphere files: "x,y,z,r" (CLUMP's columns). One row of io/formats.cpp.
#include "mss/io/sphere_writers.hpp"

#include <array>
#include <charconv>
#include <string>

namespace mss::detail {

std::string formatCsv(const SphereSet& s) {
    // std::to_chars is printf's "%.17g" (what an ostream at precision 17 wrote) at a fifth of the cost: a
    // batch writes a file a grain
    std::string out = "x,y,z,r\n";
    out.reserve(out.size() + 100 * s.size());
    std::array<char, 32> buf{};
    const auto put = [&](double v, char end) {
        const std::to_chars_result r =
            std::to_chars(buf.data(), buf.data() + buf.size(), v, std::chars_format::general, 17);
        out.append(buf.data(), r.ptr);
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
