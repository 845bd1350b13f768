// The row kernels of Coverage (internal to coverage.cpp): sums of a coverage's prefix over the rows of balls,
// four rows at a time on AVX2, and one row's counts and prefix changed by SSE2. Prefix layout: per row nx + 1
// entries, the row's base (the prefix before its first voxel), then one per voxel.
#pragma once

#include "mss/core/ball_rows.hpp"

#include <array>
#include <cstdint>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define MSS_GAIN_AVX2 1
#endif

namespace mss::engine::rows {

constexpr int kMaxRadii = 4; ///< Coverage::kMaxRadii

#if MSS_GAIN_AVX2
/// Coverage::gain of the @p n (at most 4) balls of centre @p c and radii @p radii, each alone, into @p out.
void gainsAvx2(const Vec3& c, const double* radii, int n, const std::array<int, 3>& d,
               const std::uint16_t* prefix, long long* out);
/// Coverage::gainMerged of an orbit's images: every x of @p xa, @p xb with every (y, z) of @p ys, @p zs (an
/// x pair: one (y, z)).
long long gainProductAvx2(double r, double xa, double xb, const double* ys, const double* zs, int n,
                          const std::array<int, 3>& d, int j0, int j1, int k0, int k1,
                          const std::uint16_t* prefix, bool twiceY, bool twiceZ);
#endif

/// The prefix @p p[i0..i1] of a row from @p acc (the sum before i0): g = (S ? 1 : -1) where the count @p c
/// is 0, modulo 2^16. Count: std::uint8_t or std::uint16_t.
template <class Count>
void prefixRun(const Count* c, const std::uint8_t* s, std::uint16_t* p, int i0, int i1, std::uint16_t acc);

/// One row of a coverage change: the counts @p c of voxels u0..u1 change by @p delta, and those of o0..o1
/// (within, or empty: o0 > o1) by 2 delta more; the prefix @p p (p[-1]: the base) follows; the changes of
/// the mismatch and of the covered count are added to @p dMismatch and @p dCovered.
template <class Count>
void changeRow(Count* c, const std::uint8_t* s, std::uint16_t* p, int nx, int u0, int u1, int o0, int o1,
               int delta, long long& dMismatch, long long& dCovered);

} // namespace mss::engine::rows
