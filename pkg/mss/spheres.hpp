// Sphere sets: the output of MSS and the input of scoring, with their file formats.
#pragma once

#include "mss/grid.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace mss {

/// A set of spheres in world units; centres[i] and radii[i] describe sphere i.
struct SphereSet {
    std::vector<Vec3> centers;
    std::vector<double> radii;

    std::size_t size() const { return radii.size(); }
    void add(const Vec3& c, double r) {
        centers.push_back(c);
        radii.push_back(r);
    }
};

/// The range sphere sets are computed in (world units): every radius in [kSmallestRadius,
/// kLargestCoordinate], every coordinate within kLargestCoordinate, so that moments of inertia (r^5) and
/// squared distances stay normal doubles.
constexpr double kSmallestRadius = 1e-60;
constexpr double kLargestCoordinate = 1e60;

/// Checks sizes agree, coordinates are finite and radii positive, all within the range above, each radius at
/// least 1e-12 of its centre's distance from the origin (else a double cannot tell its points apart); throws
/// std::invalid_argument naming @p where and the sphere.
void validateSpheres(const SphereSet& s, const std::string& where);

/// The least gap between the spheres of clumps i[n] and j[n], for every n: the least |c_p - c_q| - r_p - r_q
/// over a sphere p of the one and q of the other (negative: they overlap by that much; +inf where a clump has
/// no sphere). The clumps are packed: @p rows holds @p spheres rows x y z r, clump k's are rows offsets[k] ..
/// offsets[k + 1] - 1 (a view: a batch's 10^6 spheres are not copied). A batch's kept contacts and its
/// assembly's pairs (numpy's batched products of padded pairs took ten times as long); OpenMP over the pairs.
/// @throws std::invalid_argument for offsets that do not run from 0 to @p spheres in order, or a clump index
/// out of range, or @p i and @p j of different lengths.
std::vector<double> clumpGaps(const double* rows, std::size_t spheres,
                              const std::vector<std::int64_t>& offsets, const std::vector<std::int64_t>& i,
                              const std::vector<std::int64_t>& j);

} // namespace mss
