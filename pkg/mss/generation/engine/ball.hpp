// The engine's shared vocabulary (internal to generate): balls in voxel units of the generation grid, the
// constraint on their radii, termination targets, timing.
#pragma once

#include "mss/grid.hpp"

#include <algorithm>
#include <chrono>
#include <climits>
#include <functional>
#include <type_traits>
#include <utility>

namespace mss::engine {

using Clock = std::chrono::steady_clock;
inline double secondsSince(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

/// Largest radius allowed for a sphere centred at a point (clipping, constraint planes); negative where no
/// centre may be; +inf without constraint. Voxel coordinates and units of the generation grid. Empty: no
/// constraint.
class BoundVox {
public:
    BoundVox() = default;
    /// The bound alone: clamp() asks it every time.
    template <class F, class = std::enable_if_t<!std::is_same_v<std::decay_t<F>, BoundVox> &&
                                                std::is_invocable_r_v<double, const F&, const Vec3&>>>
    BoundVox(F bound) : bound_(std::move(bound)) {}
    /// The bound, and @p clamp: min(r, bound(c)) exactly, from a cheaper test where it can tell that the
    /// bound does not bind.
    BoundVox(std::function<double(const Vec3&)> bound, std::function<double(const Vec3&, double)> clamp)
        : bound_(std::move(bound)), clamp_(std::move(clamp)) {}
    explicit operator bool() const { return bool(bound_); }
    double operator()(const Vec3& c) const { return bound_(c); }
    /// The radius @p r cut down to the bound at @p c: min(r, bound(c)).
    double clamp(const Vec3& c, double r) const { return clamp_ ? clamp_(c, r) : std::min(r, bound_(c)); }

private:
    std::function<double(const Vec3&)> bound_;
    std::function<double(const Vec3&, double)> clamp_;
};

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
