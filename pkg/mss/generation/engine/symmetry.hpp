// Mirror symmetries of the voxelised grain and the orbits of spheres under them (paper section 4.2 values a
// symmetric sphere set for a symmetric grain).
#pragma once

#include "mss/generation/engine/ball.hpp"

#include <array>
#include <vector>

namespace mss::engine {

/// Mirror planes through the grid centre, normal to x, y or z, under which the volume is invariant up to a
/// tolerance (a voxelised mesh of a symmetric grain can differ in a few voxels where the surface passes
/// exactly through voxel centres). @p exact: whether the volume is invariant exactly under all planes found.
std::array<bool, 3> mirrorAxes(const VoxelGrid& S, std::size_t solid, bool& exact);

/// Candidate or chosen sphere with its mirror images: the orbit under the detected mirror planes.
struct Orbit {
    Vec3 c;
    double r;
    std::array<bool, 3> onPlane{false, false, false};
    bool broken = false;  ///< placed alone: its images did not fit the sphere budget
    bool bounded = false; ///< radius already reduced to what the constraints (clipping, planes) allow
};

/// The mirror planes a sphere set keeps (normal to x, y, z through the grid centre), and orbits under them.
class Symmetry {
public:
    Symmetry(const GridSpec& g, std::array<bool, 3> axes) : axes_(axes) {
        for (int a = 0; a < 3; ++a) mid_[a] = 0.5 * (g.dims[a] - 1);
    }
    int planes() const { return int(axes_[0]) + int(axes_[1]) + int(axes_[2]); }
    const std::array<bool, 3>& axes() const { return axes_; }
    /// Snaps coordinates within half a voxel of a plane onto it (on a grid of even size the voxels next to
    /// the plane are half a voxel off it); those stay on it.
    Orbit make(const Vec3& c, double r) const {
        Orbit o{c, r};
        for (int a = 0; a < 3; ++a) {
            if (axes_[a] && std::abs(c[a] - mid_[a]) <= 0.5 + 1e-9) {
                o.c[a] = mid_[a];
                o.onPlane[a] = true;
            }
        }
        return o;
    }
    /// The orbit's balls: the sphere and its mirror images (one ball for a broken orbit).
    std::vector<Ball> images(const Orbit& o) const;
    /// The representative with every symmetric coordinate in the lower half, so that an orbit has one key.
    Vec3 canonical(Vec3 c) const {
        for (int a = 0; a < 3; ++a)
            if (axes_[a] && c[a] > mid_[a]) c[a] = 2.0 * mid_[a] - c[a];
        return c;
    }

private:
    std::array<bool, 3> axes_;
    Vec3 mid_;
};

} // namespace mss::engine
