// What the engine is asked for and what it reports: its own types, filled and read by the pipeline
// (generate.cpp), so that the engine does not depend on the public options.
#pragma once

#include "mss/core/mesh_query.hpp"

#include <vector>

namespace mss::engine {

/// A generation's targets (section 3.5) and the methods' parameters.
struct Request {
    int nSpheres = 0;        ///< at most this many spheres; 0: no limit
    double eta = 0.0;        ///< stop at this relative mismatch (eq. 7); 0: none
    double dice = 0.0;       ///< stop at this Dice mismatch (eq. 27); 0: none
    double rMin = 0.0;       ///< smallest radius, world units; 0: none
    int maxIterations = 100; ///< iterations (paper) or rounds of refinement (optimized)
    double deltaMin = 1.0;   ///< paper: least distance between centres, voxels (section 3.4)
    bool keepSymmetry = true;
    bool polish = false;       ///< the joint polish (polish.hpp) as the optimised method's last stage
    std::vector<Plane> planes; ///< planes no sphere crosses
};

/// What a run of the engine reports.
struct Report {
    int iterations = 0;
    int symmetryPlanes = 0;
    double secondsSelect = 0.0;
};

} // namespace mss::engine
