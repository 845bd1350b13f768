// .txt sphere files: YADE's text clump "x y z r clumpId" (ymport.textClumps). One row of io/formats.cpp.
#include "mss/io/sphere_writers.hpp"

#include <iomanip>
#include <sstream>

namespace mss::detail {

std::string formatYadeText(const SphereSet& s) {
    std::ostringstream out;
    out << std::setprecision(17) << "# x y z r clumpId (yade-mss; read with ymport.textClumps)\n";
    for (std::size_t i = 0; i < s.size(); ++i)
        out << s.centers[i].x() << ' ' << s.centers[i].y() << ' ' << s.centers[i].z() << ' ' << s.radii[i]
            << " 0\n";
    return out.str();
}

} // namespace mss::detail
