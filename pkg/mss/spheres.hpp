// Sphere sets: the output of MSS and the input of scoring, with their file formats.
#pragma once

#include "mss/grid.hpp"

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

} // namespace mss
