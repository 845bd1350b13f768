// Estimates of the generation's heavy steps, for the work limit (mss/work.hpp): internal.
#pragma once

#include "mss/generate.hpp"
#include "mss/work.hpp"

namespace mss::detail {

/// A generation's estimated work on the padded grid @p S with @p o.
Work generationWork(const VoxelGrid& S, const GenerateOptions& o);

/// Exact scoring's estimated work: @p samples points against a mesh of @p triangles and @p spheres spheres.
Work exactScoreWork(std::size_t samples, std::size_t triangles, std::size_t spheres);

} // namespace mss::detail
