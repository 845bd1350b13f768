// Exact Euclidean distance transform (MSS paper section 3.2, eq. 8).
#pragma once

#include "mss/grid.hpp"

namespace mss {

/// Exact Euclidean distance transform of a binary volume (eq. 8): for every solid voxel the distance, in
/// voxel units, from its centre to the centre of the nearest background voxel; 0 on background voxels.
///
/// Felzenszwalb and Huttenlocher, "Distance Transforms of Sampled Functions", Theory of Computing 8 (2012),
/// doi:10.4086/toc.2012.v008a019: a 1-D binary scan along x, then the lower envelope of parabolas along y and
/// z. O(N) time for N voxels, O(N) memory (the output) plus one block of lines per thread. Parallel with
/// OpenMP over lines; every line is computed the same way whatever the thread count, so the result is
/// bit-identical.
/// @throws std::invalid_argument if the volume has no background voxel (the distance would be undefined).
ScalarGrid distanceTransform(const VoxelGrid& solid);

/// As above, writing into @p out (resized to the volume's grid); lets the generator reuse its buffers.
void distanceTransform(const VoxelGrid& solid, ScalarGrid& out);

} // namespace mss
