#include "mss/spheres.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace mss {

void validateSpheres(const SphereSet& s, const std::string& where) {
    if (s.centers.size() != s.radii.size())
        throw std::invalid_argument(where + ": " + std::to_string(s.centers.size()) + " centres but " +
                                    std::to_string(s.radii.size()) + " radii");
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (!s.centers[i].allFinite())
            throw std::invalid_argument(where + ": sphere " + std::to_string(i) + " has a non-finite centre");
        if (!(s.radii[i] > 0.0) || !std::isfinite(s.radii[i])) {
            std::ostringstream os;
            os << where << ": sphere " << i << " has radius " << s.radii[i] << " (must be > 0 and finite)";
            throw std::invalid_argument(os.str());
        }
        // Volumes (r^3), squared distances and the surface mesher's weights (r^2) must stay normal doubles:
        // a radius of 1e300 overflowed them into a floating-point exception, a denormal one underflowed them
        // into a refinement that never met its tolerance.
        const double far = s.centers[i].cwiseAbs().maxCoeff();
        if (s.radii[i] < kSmallestRadius || s.radii[i] > kLargestCoordinate || far > kLargestCoordinate ||
            s.radii[i] < 1e-12 * far) {
            std::ostringstream os;
            os << where << ": sphere " << i << " (radius " << s.radii[i] << ", centre " << s.centers[i].x()
               << "," << s.centers[i].y() << "," << s.centers[i].z()
               << ") is outside the range this code computes in: radii in [" << kSmallestRadius << ", "
               << kLargestCoordinate << "], coordinates within " << kLargestCoordinate
               << ", and a radius at least 1e-12 of its centre's distance from the origin; rescale the set "
                  "or move "
                  "it near the origin";
            throw std::invalid_argument(os.str());
        }
    }
}

} // namespace mss
