#include "mss/generation/engine/coverage.hpp"
#include "mss/generation/engine/coverage_rows.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace mss::engine {

using mss::detail::ceilInt;
using mss::detail::floorInt;
using namespace rows;
static_assert(Coverage::kMaxRadii == rows::kMaxRadii);

long long Coverage::gain(const Ball& b) const {
#if MSS_GAIN_AVX2
    static const bool kAvx2 = __builtin_cpu_supports("avx2");
    if (kAvx2) {
        long long g = 0;
        gainsAvx2(b.c, &b.r, 1, S_.spec.dims, prefix_.data(), &g);
        return g;
    }
#endif
    return gainRows(b);
}

void Coverage::gains(const Vec3& c, const double* radii, int n, long long* out) const {
    if (n < 1 || n > kMaxRadii) throw std::invalid_argument("Coverage::gains: 1 to 4 radii");
#if MSS_GAIN_AVX2
    static const bool kAvx2 = __builtin_cpu_supports("avx2");
    if (kAvx2) {
        gainsAvx2(c, radii, n, S_.spec.dims, prefix_.data(), out);
        return;
    }
#endif
    for (int m = 0; m < n; ++m) out[m] = gainRows(Ball{c, radii[m]});
}

Coverage::Coverage(const VoxelGrid& target, std::size_t maxBalls)
    : S_(target), nx_(target.nx()), maxBalls_(maxBalls) {
    if (nx_ > 32767)
        throw std::invalid_argument("Coverage: the grid is " + std::to_string(nx_) +
                                    " voxels along x; rows of more than 32767 voxels are not supported "
                                    "(a coarser resolution)");
    if (maxBalls > 65535)
        throw std::invalid_argument("Coverage: at most 65535 balls (16-bit counts), asked for " +
                                    std::to_string(maxBalls));
    if (maxBalls_ <= 255)
        cover8_.assign(target.size(), 0);
    else
        cover16_.assign(target.size(), 0);
    prefix_.resize(target.size() / std::size_t(nx_) * std::size_t(nx_ + 1));
    solid_ = countSolid(target);
    mismatch_ = static_cast<long long>(solid_);
    const long long rows = static_cast<long long>(target.size() / std::size_t(nx_));
#pragma omp parallel for schedule(static)
    for (long long row = 0; row < rows; ++row) {
        rowPrefix(std::size_t(row))[-1] = 0;
        rebuildRow(std::size_t(row), 0);
    }
}

long long Coverage::gain(const std::vector<Ball>& balls, bool mirrored) const {
    bool independent = true;
    for (std::size_t p = 0; p < balls.size() && independent; ++p)
        for (std::size_t q = p + 1; q < balls.size(); ++q)
            if ((balls[p].c - balls[q].c).norm() <= balls[p].r + balls[q].r + 1.0) {
                independent = false;
                break;
            }
    if (independent && mirrored) return gain(balls[0]) * static_cast<long long>(balls.size());
    if (independent) {
        long long total = 0;
        for (const Ball& b : balls) total += gain(b);
        return total;
    }
#if MSS_GAIN_AVX2
    static const bool kAvx2 = __builtin_cpu_supports("avx2");
    long long product = 0;
    if (kAvx2 && gainOfProduct(balls, mirrored, product)) return product;
#endif
    // Images that differ only in x (mirror plane normal to x) share their rows: one root per row.
    bool sameRows = true;
    for (const Ball& b : balls)
        sameRows = sameRows && b.r == balls[0].r && b.c.y() == balls[0].c.y() && b.c.z() == balls[0].c.z();
    if (sameRows && balls.size() == 2) return gainRowPair(balls, mirrored);
    return gainMerged(balls, mirrored);
}

#if MSS_GAIN_AVX2
bool Coverage::gainOfProduct(const std::vector<Ball>& balls, bool mirrored, long long& out) const {
    // an orbit's images: one radius, every x centre (at most two) with every (y, z) position (at most 8)
    if (balls.size() > 16) return false;
    double xs[2], ys[8], zs[8];
    int nx = 0, nyz = 0;
    for (const Ball& b : balls) {
        if (b.r != balls[0].r) return false;
        int q = 0;
        while (q < nx && xs[q] != b.c.x()) ++q;
        if (q == nx) {
            if (nx == 2) return false;
            xs[nx++] = b.c.x();
        }
        q = 0;
        while (q < nyz && (ys[q] != b.c.y() || zs[q] != b.c.z())) ++q;
        if (q == nyz) {
            if (nyz == 8) return false;
            ys[nyz] = b.c.y();
            zs[nyz++] = b.c.z();
        }
    }
    // as many balls as the product has, none twice
    if (balls.size() != std::size_t(nx * nyz)) return false;
    for (std::size_t p = 0; p < balls.size(); ++p)
        for (std::size_t q = p + 1; q < balls.size(); ++q)
            if (balls[p].c == balls[q].c) return false;
    Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300); // gainMerged's box
    for (const Ball& b : balls) {
        lo = lo.cwiseMin(b.c - Vec3::Constant(b.r));
        hi = hi.cwiseMax(b.c + Vec3::Constant(b.r));
    }
    const int k0 = std::max(0, ceilInt(lo.z())), k1 = std::min(halfEnd(mirrored, 2), floorInt(hi.z()));
    const int j0 = std::max(0, ceilInt(lo.y())), j1 = std::min(halfEnd(mirrored, 1), floorInt(hi.y()));
    out = gainProductAvx2(balls[0].r, std::min(xs[0], xs[nx - 1]), std::max(xs[0], xs[nx - 1]), ys, zs, nyz,
                          S_.spec.dims, j0, j1, k0, k1, prefix_.data(), mirrored && mirror_[1],
                          mirrored && mirror_[2]);
    return true;
}
#endif

long long Coverage::gainRowPair(const std::vector<Ball>& balls, bool mirrored) const {
    const Ball& b = balls[0];
    long long total = 0;
    const int k0 = std::max(0, ceilInt(b.c.z() - b.r)),
              k1 = std::min(halfEnd(mirrored, 2), floorInt(b.c.z() + b.r));
    for (int k = k0; k <= k1; ++k)
        forPairRows(b, balls[1].c.x(), k, halfEnd(mirrored, 1), [&](int j, int a0, int a1, int b0, int b1) {
            const std::size_t row = rowOf(j, k);
            const bool hasA = a0 <= a1, hasB = b0 <= b1;
            long long g;
            if (hasA && hasB && b0 <= a1 + 1)
                g = sum(row, a0, std::max(a1, b1));
            else
                g = (hasA ? sum(row, a0, a1) : 0) + (hasB ? sum(row, b0, b1) : 0);
            total += weight(mirrored, j, k) * g;
        });
    return total;
}

long long Coverage::gainMerged(const std::vector<Ball>& balls, bool mirrored) const {
    const auto& d = S_.spec.dims;
    // Overlapping images: per row of the union's bounding box, merge the balls' intervals (at most 8).
    Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
    for (const Ball& b : balls) {
        lo = lo.cwiseMin(b.c - Vec3::Constant(b.r));
        hi = hi.cwiseMax(b.c + Vec3::Constant(b.r));
    }
    const int k0 = std::max(0, ceilInt((lo.z()))), k1 = std::min(halfEnd(mirrored, 2), floorInt((hi.z())));
    const int j0 = std::max(0, ceilInt((lo.y()))), j1 = std::min(halfEnd(mirrored, 1), floorInt((hi.y())));
    long long total = 0;
    std::array<std::pair<int, int>, 8> iv;
    for (int k = k0; k <= k1; ++k)
        for (int j = j0; j <= j1; ++j) {
            int n = 0;
            for (const Ball& b : balls) {
                const double dz = k - b.c.z(), dy = j - b.c.y();
                const double rx2 = b.r * b.r - dz * dz - dy * dy;
                if (rx2 < 0) continue;
                const double rx = std::sqrt(rx2);
                const int i0 = std::max(0, ceilInt((b.c.x() - rx))),
                          i1 = std::min(d[0] - 1, floorInt((b.c.x() + rx)));
                if (i0 > i1) continue;
                int p = n++;
                for (; p > 0 && iv[p - 1].first > i0; --p) iv[p] = iv[p - 1];
                iv[p] = {i0, i1};
            }
            if (n == 0) continue;
            const std::size_t row = rowOf(j, k);
            long long rowTotal = 0;
            int a = iv[0].first, e = iv[0].second;
            for (int p = 1; p < n; ++p) {
                if (iv[p].first <= e + 1) {
                    e = std::max(e, iv[p].second);
                } else {
                    rowTotal += sum(row, a, e);
                    a = iv[p].first;
                    e = iv[p].second;
                }
            }
            rowTotal += sum(row, a, e);
            total += weight(mirrored, j, k) * rowTotal;
        }
    return total;
}

void Coverage::rebuildRow(std::size_t r, int from) {
    std::uint16_t* p = rowPrefix(r);
    const std::size_t v = r * std::size_t(nx_);
    if (cover8_.empty())
        prefixRun(cover16_.data() + v, S_.data.data() + v, p, from, nx_ - 1, p[from - 1]);
    else
        prefixRun(cover8_.data() + v, S_.data.data() + v, p, from, nx_ - 1, p[from - 1]);
}

void Coverage::countBalls(int delta) {
    if (delta > 0 && balls_ + std::size_t(delta) > maxBalls_)
        throw std::logic_error("Coverage: more than " + std::to_string(maxBalls_) + " balls placed");
    if (delta < 0 && balls_ < std::size_t(-delta))
        throw std::logic_error("Coverage: a ball removed where none is placed");
    balls_ = std::size_t(static_cast<long long>(balls_) + delta);
}

void Coverage::change(const Ball& b, int delta) {
    countBalls(delta);
    // rows are independent: a large ball's slices are changed in parallel (the counts summed exactly)
    const int k0 = std::max(0, ceilInt(b.c.z() - b.r)),
              k1 = std::min(S_.spec.dims[2] - 1, floorInt(b.c.z() + b.r));
    long long dMismatch = 0, dCovered = 0;
#pragma omp parallel for schedule(static) reduction(+ : dMismatch, dCovered) if (b.r > 12.0)
    for (int k = k0; k <= k1; ++k) changeSlice(b, nullptr, delta, k, dMismatch, dCovered);
    mismatch_ += dMismatch;
    covered_ = static_cast<std::size_t>(static_cast<long long>(covered_) + dCovered);
}

void Coverage::change(const std::vector<Ball>& balls, int delta) {
    // x-mirror partners (the same rows) in pairs, the rest alone; the result is that of changing each
    std::vector<char> done(balls.size(), 0);
    for (std::size_t p = 0; p < balls.size(); ++p) {
        if (done[p]) continue;
        const Ball& a = balls[p];
        std::size_t q = p + 1;
        while (q < balls.size() && (done[q] || balls[q].r != a.r || balls[q].c.y() != a.c.y() ||
                                    balls[q].c.z() != a.c.z() || balls[q].c.x() == a.c.x()))
            ++q;
        done[p] = 1;
        if (q == balls.size()) {
            change(a, delta);
            continue;
        }
        done[q] = 1;
        countBalls(2 * delta);
        const Ball& b = balls[q];
        const int k0 = std::max(0, ceilInt(a.c.z() - a.r)),
                  k1 = std::min(S_.spec.dims[2] - 1, floorInt(a.c.z() + a.r));
        long long dMismatch = 0, dCovered = 0;
#pragma omp parallel for schedule(static) reduction(+ : dMismatch, dCovered) if (a.r > 12.0)
        for (int k = k0; k <= k1; ++k) changeSlice(a, &b, delta, k, dMismatch, dCovered);
        mismatch_ += dMismatch;
        covered_ = static_cast<std::size_t>(static_cast<long long>(covered_) + dCovered);
    }
}

void Coverage::changeSlice(const Ball& b, const Ball* other, int delta, int k, long long& dMismatch,
                           long long& dCovered) {
    auto row = [&](std::size_t r, int u0, int u1, int o0, int o1) {
        const std::size_t v = r * std::size_t(nx_);
        if (cover8_.empty())
            changeRow(cover16_.data() + v, S_.data.data() + v, rowPrefix(r), nx_, u0, u1, o0, o1, delta,
                      dMismatch, dCovered);
        else
            changeRow(cover8_.data() + v, S_.data.data() + v, rowPrefix(r), nx_, u0, u1, o0, o1, delta,
                      dMismatch, dCovered);
    };
    if (!other) {
        mss::detail::forBallRows(b.c, b.r, S_.spec.dims, k, k,
                                 [&](int j, int kk, int i0, int i1) { row(rowOf(j, kk), i0, i1, 1, 0); });
        return;
    }
    forPairRows(b, other->c.x(), k, S_.spec.dims[1] - 1, [&](int j, int a0, int a1, int b0, int b1) {
        const std::size_t r = rowOf(j, k);
        const bool hasA = a0 <= a1, hasB = b0 <= b1;
        if (hasA && hasB && b0 <= a1) { // overlapping runs: one pass over their union
            row(r, a0, std::max(a1, b1), b0, std::min(a1, b1));
        } else {
            if (hasA) row(r, a0, a1, 1, 0);
            if (hasB) row(r, b0, b1, 1, 0);
        }
    });
}

} // namespace mss::engine
