// Reading numpy .npy voxel volumes.
#pragma once

#include "mss/grid.hpp"

#include <string>

namespace mss {

/// Reads a 3-D boolean or integer .npy array as a binary volume: voxel (i, j, k) is a[i, j, k], so numpy's
/// first axis is x. With @p label >= 0 a voxel is solid when it equals the label (a labelled CT volume), else
/// when it is non-zero. The grid gets voxel size @p voxelSize and voxel (0, 0, 0) centred at @p origin.
/// @throws std::invalid_argument naming the file and the problem (not .npy, truncated, not 3-D, empty,
///         floating point or other unsupported dtype, label absent).
VoxelGrid readNpy(const std::string& path, double voxelSize = 1.0, const Vec3& origin = Vec3::Zero(),
                  long long label = -1);

} // namespace mss
