#include "mss/generation/estimates.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace mss::detail {

/// A generation's estimated work on @p S. Measured on a 2-core machine (ellipsoid 2:1:1, resolutions 100 to
/// 400, 10 to 65535 spheres): about 7e-8 s a grid voxel for a few spheres, growing as the log of the count
/// (0.6 s at resolution 100 and 3000 spheres, 50 s at resolution 400 and 65535); the paper's method costs a
/// voxelisation and a distance transform an iteration; the polish 2-5 times the time. A quality target's
/// count is unknown before: taken as 1000.
Work generationWork(const VoxelGrid& S, const GenerateOptions& o) {
    const double voxels = double(S.size());
    const double n = o.nSpheres > 0 ? double(o.nSpheres) : 1000.0;
    double seconds = 0.0;
    if (o.method == Method::Paper)
        seconds = 6e-8 * voxels * (1.0 + std::min(double(o.maxIterations), n));
    else
        seconds = 8e-8 * voxels * (1.0 + 0.5 * std::log1p(n)) * (o.polish ? 4.0 : 1.0);
    std::ostringstream what;
    what.precision(3);
    what << "a grid of " << S.nx() << "x" << S.ny() << "x" << S.nz() << " voxels (" << voxels << ") and ";
    if (o.nSpheres > 0)
        what << o.nSpheres << " spheres";
    else
        what << "a quality target (taken as 1000 spheres)";
    return {what.str(), seconds};
}

/// Measured on a 2-core machine: 1.0e-6 s a point for the ellipsoid (2,000 triangles, 10 spheres), 1.5e-6 for
/// the femur (13,752 triangles, 300 spheres), the winding number's tree query growing as the log of the
/// triangles and the spheres' grid as their count.
Work exactScoreWork(std::size_t samples, std::size_t triangles, std::size_t spheres) {
    const double perPoint = 1.0e-6 * (1.0 + double(triangles) / 1e5 + double(spheres) / 1e4);
    std::ostringstream what;
    what.precision(3);
    what << double(samples) << " exact-score points against " << triangles << " triangles and " << spheres
         << " spheres";
    return {what.str(), double(samples) * perPoint};
}

} // namespace mss::detail
