// Coverage of the target by a union of balls, with the exact mismatch gains (MSS paper eq. 2 on voxels).
#pragma once

#include "mss/core/ball_rows.hpp"
#include "mss/generation/engine/ball.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace mss::engine {

/// Coverage of the target by a union of balls, with the exact change of the mismatch |S Δ S~| (eq. 2 on
/// voxels) that adding balls would make. Per voxel: the number of balls covering it; per x-row the prefix sum
/// of g = (S ? 1 : -1) over the uncovered voxels, from a base per row (only differences are ever used). The
/// gain of a ball is then a sum over its (y, z) columns of O(1) interval sums: O(r^2) for radius r in
/// voxels. Adding or removing a ball rebuilds the prefix of a row over the ball's interval from its first
/// voxel whose coverage flips, and shifts whichever side of the interval is shorter (the base with the
/// left side): on long rows (torus, 416 voxels) the shift was most of the cost.
class Coverage {
public:
    /// @p maxBalls: the most balls ever placed at once (at most 65535, else std::invalid_argument); up to 255
    /// the counts take a byte a voxel (femur 70: peak memory about 8% lower, and a change moves half the
    /// counts' bytes). Placing more, or removing a ball when none is placed, is a std::logic_error.
    explicit Coverage(const VoxelGrid& target, std::size_t maxBalls = 65535);

    /// Decrease of the mismatch if @p b were added (negative if it would add more outside than inside). On a
    /// CPU with AVX2, four rows at a time (gainRows: the same voxels and sum).
    long long gain(const Ball& b) const;
    /// gain(b) row by row, portable: what the vector path must equal (the tests compare them).
    long long gainRows(const Ball& b) const {
        long long total = 0;
        forColumns(b, [&](std::size_t r, int i0, int i1) { total += sum(r, i0, i1); });
        return total;
    }
    static constexpr int kMaxRadii = 4;
    /// gain() of the @p n (1 to kMaxRadii) balls of centre @p c and radii @p radii, each alone, into @p out:
    /// one pass over their rows (the same sums as gain() of each).
    void gains(const Vec3& c, const double* radii, int n, long long* out) const;
    /// Decrease of the mismatch if all @p balls were added together (they may overlap each other).
    /// @p mirrored: the balls are mirror images of the first under planes that map the target and the
    /// coverage onto themselves, so apart from each other they all gain the same.
    long long gain(const std::vector<Ball>& balls, bool mirrored = false) const;
    /// Mirror planes (normal to x, y, z, through the grid centre) that map the target onto itself exactly.
    void setMirrorPlanes(const std::array<bool, 3>& planes) { mirror_ = planes; }
    void add(const Ball& b) { change(b, +1); }
    void remove(const Ball& b) { change(b, -1); }
    /// add() / remove() of each of @p balls (an orbit's images): the same counts and mismatch; two that
    /// differ only in x (mirror images under the x plane: the same rows) are changed in one pass over the
    /// union of their runs.
    void add(const std::vector<Ball>& balls) { change(balls, +1); }
    void remove(const std::vector<Ball>& balls) { change(balls, -1); }

    long long mismatch() const { return mismatch_; }
    std::size_t solid() const { return solid_; }
    std::size_t covered() const { return covered_; }
    double eta() const { return solid_ ? double(mismatch_) / double(solid_) : 0.0; }
    double dice() const { return (solid_ + covered_) ? double(mismatch_) / double(solid_ + covered_) : 0.0; }

private:
    // A mirrored union of images under a symmetric coverage gains the same in rows (j, k) and their mirror
    // images under the y and z planes: only the lower half is visited, rows off the plane counted twice.
    int halfEnd(bool mirrored, int axis) const {
        const int n = S_.spec.dims[axis];
        return mirrored && mirror_[axis] ? (n - 1) / 2 : n - 1;
    }
    long long weight(bool mirrored, int j, int k) const {
        long long w = 1;
        if (mirrored && mirror_[1] && 2 * j != S_.spec.dims[1] - 1) w *= 2;
        if (mirrored && mirror_[2] && 2 * k != S_.spec.dims[2] - 1) w *= 2;
        return w;
    }
    /// The prefix of row @p r (j + ny k): entry i is the sum before voxel i + 1, entry -1 the row's base.
    const std::uint16_t* rowPrefix(std::size_t r) const {
        return prefix_.data() + r * std::size_t(nx_ + 1) + 1;
    }
    std::uint16_t* rowPrefix(std::size_t r) { return prefix_.data() + r * std::size_t(nx_ + 1) + 1; }
    /// Sum of g over the uncovered voxels i0..i1 of row @p r
    long long sum(std::size_t r, int i0, int i1) const {
        const std::uint16_t* p = rowPrefix(r);
        return static_cast<std::int16_t>(static_cast<std::uint16_t>(p[i1] - p[i0 - 1]));
    }
    std::size_t rowOf(int j, int k) const {
        return std::size_t(j) + std::size_t(S_.spec.dims[1]) * std::size_t(k);
    }
    void rebuildRow(std::size_t row, int from);
    template <class F> void forColumns(const Ball& b, F&& f) const {
        mss::detail::forBallRows(b.c, b.r, S_.spec.dims, 0, S_.spec.dims[2] - 1,
                                 [&](int j, int k, int i0, int i1) { f(rowOf(j, k), i0, i1); });
    }
    void change(const Ball& b, int delta);
    void change(const std::vector<Ball>& balls, int delta);
    /// @p other: null, or the x-mirror partner of @p b (the same y, z and radius), changed with it
    void changeSlice(const Ball& b, const Ball* other, int delta, int k, long long& dMismatch,
                     long long& dCovered);
    void countBalls(int delta);
    /// The rows (j, k) of slice @p k, j <= @p jEnd, of ball @p b and its partner at x = @p x (the same y, z
    /// and radius): f(j, a0, a1, b0, b1) with the runs of the one nearer x = 0 (a) and of the other (b), each
    /// as forBallRows gives it for that ball alone (either may be empty: a0 > a1).
    template <class F> void forPairRows(const Ball& b, double x, int k, int jEnd, F&& f) const {
        using mss::detail::ceilInt;
        using mss::detail::floorInt;
        const double dz = k - b.c.z(), rz2 = b.r * b.r - dz * dz;
        if (rz2 < 0) return;
        const double ry = std::sqrt(rz2);
        const int j0 = std::max(0, ceilInt(b.c.y() - ry)), j1 = std::min(jEnd, floorInt(b.c.y() + ry));
        const double xa = std::min(b.c.x(), x), xb = std::max(b.c.x(), x);
        const int last = S_.spec.dims[0] - 1;
        for (int j = j0; j <= j1; ++j) {
            const double dy = j - b.c.y();
            const double rx2 = rz2 - dy * dy;
            if (rx2 < 0) continue;
            const double rx = std::sqrt(rx2);
            f(j, std::max(0, ceilInt(xa - rx)), std::min(last, floorInt(xa + rx)),
              std::max(0, ceilInt(xb - rx)), std::min(last, floorInt(xb + rx)));
        }
    }
    // gain() of two images that differ only in x (they share rows), and of any overlapping images
    long long gainRowPair(const std::vector<Ball>& balls, bool mirrored) const;
    /// gain() of an orbit's images that overlap, four rows at a time on AVX2 (coverage_rows: an x pair is one
    /// too): false, and @p out untouched, where @p balls are not every x centre with every (y, z) position
    bool gainOfProduct(const std::vector<Ball>& balls, bool mirrored, long long& out) const;
    long long gainMerged(const std::vector<Ball>& balls, bool mirrored) const;

    const VoxelGrid& S_;
    BigVector<std::uint8_t> cover8_;   ///< the counts, when at most 255 balls (else empty)
    BigVector<std::uint16_t> cover16_; ///< the counts, else
    // prefix sums modulo 2^16: only differences within a row are ever used, and they are at most the row's
    // length, which is checked to be under 2^15 (half the bytes of int32: the prefix is read at both ends of
    // every row of every ball evaluated, and written where coverage flips). Per row nx + 1 entries: first the
    // base (the prefix before the row's first voxel), then one per voxel, so that every interval's sum is
    // two loads without a branch (the gain's inner loop about 20% faster than with one).
    BigVector<std::uint16_t> prefix_;
    std::array<bool, 3> mirror_{false, false, false};
    int nx_;
    std::size_t maxBalls_, balls_ = 0;
    std::size_t solid_ = 0, covered_ = 0;
    long long mismatch_ = 0;
};

} // namespace mss::engine
