#include "mss/spheres.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
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

std::vector<double> clumpGaps(const double* rows, std::size_t spheres,
                              const std::vector<std::int64_t>& offsets, const std::vector<std::int64_t>& i,
                              const std::vector<std::int64_t>& j) {
    if (offsets.empty() || offsets.front() != 0 || offsets.back() != std::int64_t(spheres) ||
        !std::is_sorted(offsets.begin(), offsets.end()))
        throw std::invalid_argument("clumpGaps: the offsets must run from 0 to the number of spheres (" +
                                    std::to_string(spheres) + "), in order");
    if (i.size() != j.size())
        throw std::invalid_argument("clumpGaps: " + std::to_string(i.size()) + " first clumps but " +
                                    std::to_string(j.size()) + " second ones");
    const std::int64_t clumps = std::int64_t(offsets.size()) - 1;
    for (const std::vector<std::int64_t>* v : {&i, &j})
        for (std::int64_t k : *v)
            if (k < 0 || k >= clumps)
                throw std::invalid_argument("clumpGaps: clump " + std::to_string(k) + " of " +
                                            std::to_string(clumps));
    std::vector<double> out(i.size());
    const long long n = static_cast<long long>(i.size());
#pragma omp parallel for schedule(static)
    for (long long x = 0; x < n; ++x) {
        const std::size_t a = std::size_t(i[std::size_t(x)]), b = std::size_t(j[std::size_t(x)]);
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t p = std::size_t(offsets[a]); p < std::size_t(offsets[a + 1]); ++p) {
            const double* P = rows + 4 * p;
            for (std::size_t q = std::size_t(offsets[b]); q < std::size_t(offsets[b + 1]); ++q) {
                const double* Q = rows + 4 * q;
                // the square root only where this pair could beat the best: most cannot
                const double reach = best + P[3] + Q[3];
                const double dx = P[0] - Q[0], dy = P[1] - Q[1], dz = P[2] - Q[2];
                const double d2 = dx * dx + dy * dy + dz * dz;
                if (reach <= 0 || d2 >= reach * reach) continue; // it cannot go under best
                best = std::min(best, std::sqrt(d2) - P[3] - Q[3]);
            }
        }
        out[std::size_t(x)] = best;
    }
    return out;
}

} // namespace mss
