#include "mss/spheres.hpp"

#include <cmath>
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
    }
}

} // namespace mss
