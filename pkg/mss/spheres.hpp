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

/// Checks sizes agree, coordinates are finite and radii positive; throws std::invalid_argument naming @p
/// where.
void validateSpheres(const SphereSet& s, const std::string& where);

} // namespace mss
