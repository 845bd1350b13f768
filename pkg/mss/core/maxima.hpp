// Local maxima of a field on voxels, at voxel and at sub-voxel resolution (MSS paper section 3.3).
#pragma once

#include "mss/grid.hpp"

#include <vector>

namespace mss {

/// A local maximum: the voxel (i*, j*, k*) and its sub-voxel refinement.
struct Maximum {
    std::array<int, 3> voxel{0, 0, 0}; ///< (i*, j*, k*), voxel resolution
    Vec3 position = Vec3::Zero(); ///< (i°, j°, k°), continuous voxel coordinates (eq. 23 before scaling by h)
    double value = 0.0;           ///< refined field value max(Ê^i, Ê^j, Ê^k) (eq. 24 before scaling by h)
    double voxelValue = 0.0;      ///< field value at the voxel
};

/// Voxels whose 3x3x3 neighbourhood holds no larger value (plateaus included, section 3.3), among voxels at
/// least two from the border with value > @p minValue. Sorted by value, largest first, ties by linear index,
/// so the order is deterministic. O(27 N); parallel over z slices.
std::vector<std::array<int, 3>> localMaxima(const ScalarGrid& field, float minValue = 0.0f);

/// Sub-voxel refinement of a voxel-resolution maximum (eq. 11-22 along each axis, centre eq. 23, value eq.
/// 24). Departures from the paper: of the two line pairs the one with the larger Ê is taken (see maxima.cpp
/// at eq. 22); the shift along each axis is clamped to [-0.5, 0.5] voxel, since a shift beyond half a voxel
/// contradicts the voxel being the maximum and only arises from nearly parallel lines.
Maximum refineMaximum(const ScalarGrid& field, const std::array<int, 3>& voxel);

/// Value of @p field at a sub-voxel position near voxel @p voxel by the linear interpolation of section 3.4
/// step iv: along each axis, linear between the voxel and its neighbour towards the position; the largest of
/// the three (as eq. 24). Used for the radius of spheres placed at maxima of E* = 2E - Ẽ.
double interpolateAxes(const ScalarGrid& field, const std::array<int, 3>& voxel, const Vec3& position);

} // namespace mss
