// .csv sphere files: "x,y,z,r" (CLUMP's columns). One row of io/formats.cpp.
#include "mss/io/sphere_writers.hpp"

#include <iomanip>
#include <sstream>

namespace mss::detail {

std::string formatCsv(const SphereSet& s) {
    std::ostringstream out;
    out << std::setprecision(17) << "x,y,z,r\n";
    for (std::size_t i = 0; i < s.size(); ++i)
        out << s.centers[i].x() << ',' << s.centers[i].y() << ',' << s.centers[i].z() << ',' << s.radii[i]
            << '\n';
    return out.str();
}

} // namespace mss::detail
