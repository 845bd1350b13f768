// The engine's shared vocabulary (internal to generate): balls in voxel units of the generation grid, the
// constraint on their radii, termination targets, timing.
#pragma once

#include "mss/grid.hpp"

#include <chrono>
#include <climits>
#include <functional>

namespace mss::engine {

using Clock = std::chrono::steady_clock;
inline double secondsSince(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

/// Largest radius allowed for a sphere centred at a point (clipping, constraint planes); negative where no
/// centre may be; +inf without constraint. BoundVox: voxel coordinates and units of the generation grid.
using BoundVox = std::function<double(const Vec3&)>;

/// A sphere in continuous voxel coordinates of the generation grid.
struct Ball {
    Vec3 c;
    double r;
};

/// Termination (paper section 3.5): a sphere budget and quality targets (0: none).
struct Targets {
    int budget; // max spheres, or INT_MAX
    double eta, dice;
    /// Whether a mismatch with these relative values meets a quality target.
    bool met(double etaNow, double diceNow) const {
        return (eta > 0 && etaNow <= eta) || (dice > 0 && diceNow <= dice);
    }
    bool hasQuality() const { return eta > 0 || dice > 0; }
};

} // namespace mss::engine
