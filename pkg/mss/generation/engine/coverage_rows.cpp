// The row kernels of Coverage (coverage.hpp): gains summed four rows at a time on AVX2, and a row's counts
// and prefix changed by SSE2.
#include "mss/generation/engine/coverage_rows.hpp"

#include <algorithm>
#include <cmath>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace mss::engine::rows {

using mss::detail::ceilInt;
using mss::detail::floorInt;

#if MSS_GAIN_AVX2
/// Coverage::gain of up to four balls about one centre c (radii @p radii) on AVX2, each alone, into @p out:
/// four rows (j .. j + 3) of a slice at a time over the union of their rows, the half-widths by one vector
/// square root, the ends by rounding; the prefix at both ends is then read lane by lane (gathers were no
/// faster on an AMD EPYC). The same floating-point operations in the same order as forBallRows (no FMA: AVX2
/// alone is enabled), so the same rows, the same ends and the same integer sums as Coverage::gainRows. Why:
/// the gain is most of selection and refinement (femur 70 on one thread: a third of the run, ~10^4 balls of
/// ~1100 rows each, each row a square root and two dependent loads); four rows at a time made it about 20%
/// faster. Several radii at once, since refinement's trials come in groups about one centre (a move, the
/// move touching the bound, the move sliding along the surface; the radius up and down: femur 70, 10515
/// trials about 5599 centres), and the ends of nearby radii lie on the same cache lines of the prefix.
__attribute__((target("avx2"))) void gainsAvx2(const Vec3& c, const double* radii, int n,
                                               const std::array<int, 3>& d, const std::uint16_t* prefix,
                                               long long* out) {
    constexpr int kMax = kMaxRadii;
    double r2[kMax];
    int k0[kMax], k1[kMax];
    int kLo = INT32_MAX, kHi = INT32_MIN;
    for (int m = 0; m < n; ++m) {
        r2[m] = radii[m] * radii[m];
        k0[m] = std::max(0, ceilInt(c.z() - radii[m]));
        k1[m] = std::min(d[2] - 1, floorInt(c.z() + radii[m]));
        kLo = std::min(kLo, k0[m]);
        kHi = std::max(kHi, k1[m]);
        out[m] = 0;
    }
    const __m256d cx = _mm256_set1_pd(c.x()), cy = _mm256_set1_pd(c.y());
    const __m256d zero = _mm256_setzero_pd(), last = _mm256_set1_pd(double(d[0] - 1));
    const __m256d one = _mm256_set1_pd(1.0), lanes = _mm256_set_pd(3.0, 2.0, 1.0, 0.0);
    const long long stride = d[0] + 1; // a row's prefix: its base, then one entry per voxel
    const __m256d laneRows = _mm256_mul_pd(lanes, _mm256_set1_pd(double(stride)));
    for (int k = kLo; k <= kHi; ++k) {
        const double dz = k - c.z();
        double rz2[kMax];
        int j0[kMax], j1[kMax];
        int jLo = INT32_MAX, jHi = INT32_MIN, live = 0;
        for (int m = 0; m < n; ++m) {
            rz2[m] = r2[m] - dz * dz;
            if (k < k0[m] || k > k1[m] || rz2[m] < 0) {
                j0[m] = 1;
                j1[m] = 0;
                continue;
            }
            const double ry = std::sqrt(rz2[m]);
            j0[m] = std::max(0, ceilInt(c.y() - ry));
            j1[m] = std::min(d[1] - 1, floorInt(c.y() + ry));
            if (j0[m] > j1[m]) continue;
            jLo = std::min(jLo, j0[m]);
            jHi = std::max(jHi, j1[m]);
            ++live;
        }
        if (live == 0) continue;
        for (int j = jLo; j <= jHi; j += 4) {
            const __m256d jv = _mm256_add_pd(_mm256_set1_pd(double(j)), lanes);
            const __m256d dy = _mm256_sub_pd(jv, cy);
            const __m256d dy2 = _mm256_mul_pd(dy, dy);
            const long long jk = j + static_cast<long long>(d[1]) * k;
            const std::uint16_t* p = prefix + jk * stride; // row j's base; row j + l's at l * stride
            for (int m = 0; m < n; ++m) {
                if (j0[m] > j1[m] || j > j1[m] || j + 3 < j0[m]) continue;
                const __m256d rx2 = _mm256_sub_pd(_mm256_set1_pd(rz2[m]), dy2);
                const __m256d rx = _mm256_sqrt_pd(_mm256_max_pd(rx2, zero));
                const __m256d lo = _mm256_max_pd(
                    zero, _mm256_round_pd(_mm256_sub_pd(cx, rx), _MM_FROUND_TO_POS_INF | _MM_FROUND_NO_EXC));
                const __m256d hi = _mm256_min_pd(
                    last, _mm256_round_pd(_mm256_add_pd(cx, rx), _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC));
                const __m256d inRows =
                    _mm256_and_pd(_mm256_cmp_pd(jv, _mm256_set1_pd(double(j1[m])), _CMP_LE_OQ),
                                  _mm256_cmp_pd(jv, _mm256_set1_pd(double(j0[m])), _CMP_GE_OQ));
                const __m256d ok = _mm256_and_pd(_mm256_and_pd(inRows, _mm256_cmp_pd(rx2, zero, _CMP_GE_OQ)),
                                                 _mm256_cmp_pd(lo, hi, _CMP_LE_OQ));
                if (_mm256_movemask_pd(ok) == 0) continue;
                // every lane reads two entries of a row, without a branch: the sum is the entry at hi (base +
                // 1
                // + hi) less the one before lo (base + lo); a lane without voxels reads an entry of row j
                // twice (its start cut to 0..nx: a centre may lie outside the grid), which sums to 0
                const __m256d off = _mm256_and_pd(ok, laneRows);
                const __m256d start = _mm256_min_pd(lo, _mm256_add_pd(last, one)); // lo itself where ok
                const __m256d end = _mm256_blendv_pd(start, _mm256_add_pd(hi, one), ok);
                alignas(16) int los[4], his[4];
                _mm_store_si128(reinterpret_cast<__m128i*>(los),
                                _mm256_cvttpd_epi32(_mm256_add_pd(start, off)));
                _mm_store_si128(reinterpret_cast<__m128i*>(his),
                                _mm256_cvttpd_epi32(_mm256_add_pd(end, off)));
                int total = 0;
                for (int l = 0; l < 4; ++l)
                    total += static_cast<std::int16_t>(static_cast<std::uint16_t>(p[his[l]] - p[los[l]]));
                out[m] += total;
            }
        }
    }
}
#endif

#if MSS_GAIN_AVX2
/// The weighted sum of four rows j .. j + 3 (where @p row is set; each row's prefix @p p + l * stride) over
/// the union of the runs of half-width @p rx about x = @p xa and @p xb (xa <= xb), as two disjoint pieces
/// [a0, a1] and [m, b1], m = max(b0, a1 + 1) (b1 >= a1 and b0 >= a0: one half-width), each without a branch.
/// A lane off the rows, or an empty piece, reads the entry before its start twice (lanes off the rows read
/// row j's entries; the starts cut to 0..nx, as a centre may lie outside the grid). Weight: twice off the
/// middle row
/// (@p twiceY), times @p weightK.
__attribute__((target("avx2"))) inline long long unionOfRuns(__m256d rx, __m256d row, __m256d xa, __m256d xb,
                                                             const std::array<int, 3>& d, int j,
                                                             const std::uint16_t* p, bool twiceY,
                                                             long long weightK) {
    constexpr int kUp = _MM_FROUND_TO_POS_INF | _MM_FROUND_NO_EXC;
    constexpr int kDown = _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC;
    const __m256d zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1.0),
                  last = _mm256_set1_pd(double(d[0] - 1));
    const __m256d laneRows =
        _mm256_mul_pd(_mm256_set_pd(3.0, 2.0, 1.0, 0.0), _mm256_set1_pd(double(d[0] + 1)));
    const __m256d a0 = _mm256_max_pd(zero, _mm256_round_pd(_mm256_sub_pd(xa, rx), kUp));
    const __m256d a1 = _mm256_min_pd(last, _mm256_round_pd(_mm256_add_pd(xa, rx), kDown));
    const __m256d b0 = _mm256_max_pd(zero, _mm256_round_pd(_mm256_sub_pd(xb, rx), kUp));
    const __m256d b1 = _mm256_min_pd(last, _mm256_round_pd(_mm256_add_pd(xb, rx), kDown));
    const __m256d okA = _mm256_and_pd(row, _mm256_cmp_pd(a0, a1, _CMP_LE_OQ));
    const __m256d m = _mm256_min_pd(_mm256_max_pd(b0, _mm256_add_pd(a1, one)), _mm256_add_pd(last, one));
    const __m256d okB = _mm256_and_pd(row, _mm256_cmp_pd(m, b1, _CMP_LE_OQ));
    const __m256d off = _mm256_and_pd(row, laneRows);
    const __m256d s1 = _mm256_min_pd(a0, _mm256_add_pd(last, one)); // a0 itself where the row has voxels
    const __m256d start2 = _mm256_blendv_pd(s1, m, row);
    alignas(16) int is1[4], ie1[4], is2[4], ie2[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(is1), _mm256_cvttpd_epi32(_mm256_add_pd(s1, off)));
    _mm_store_si128(
        reinterpret_cast<__m128i*>(ie1),
        _mm256_cvttpd_epi32(_mm256_add_pd(_mm256_blendv_pd(s1, _mm256_add_pd(a1, one), okA), off)));
    _mm_store_si128(reinterpret_cast<__m128i*>(is2), _mm256_cvttpd_epi32(_mm256_add_pd(start2, off)));
    _mm_store_si128(
        reinterpret_cast<__m128i*>(ie2),
        _mm256_cvttpd_epi32(_mm256_add_pd(_mm256_blendv_pd(start2, _mm256_add_pd(b1, one), okB), off)));
    long long total = 0;
    for (int l = 0; l < 4; ++l) {
        const int g = static_cast<std::int16_t>(static_cast<std::uint16_t>(p[ie1[l]] - p[is1[l]])) +
                      static_cast<std::int16_t>(static_cast<std::uint16_t>(p[ie2[l]] - p[is2[l]]));
        total += (twiceY && 2 * (j + l) != d[1] - 1 ? 2 : 1) * weightK * g;
    }
    return total;
}
#endif

#if MSS_GAIN_AVX2
/// Coverage::gainMerged on AVX2 for images that are a product set: one radius @p r, x centres @p xa <= @p xb
/// (equal for one), and the (y, z) positions @p ys, @p zs (@p n of them, at most 8): every x with every
/// (y, z). Balls about one x centre have nested runs in a row, so the row's union is the runs about xa and
/// xb of the largest half-width: rx^2 the largest of r^2 - dz^2 - dy^2 over the positions (as gainMerged
/// computes each ball's), then the two runs as two disjoint pieces (unionOfRuns). Rows @p j0..j1 of
/// slices @p k0..k1 (gainMerged's box), each counted twice off the middle row (@p twiceY) and the middle
/// slice (@p twiceZ): Coverage::weight.
__attribute__((target("avx2"))) long long gainProductAvx2(double r, double xa, double xb, const double* ys,
                                                          const double* zs, int n,
                                                          const std::array<int, 3>& d, int j0, int j1, int k0,
                                                          int k1, const std::uint16_t* prefix, bool twiceY,
                                                          bool twiceZ) {
    const __m256d vxa = _mm256_set1_pd(xa), vxb = _mm256_set1_pd(xb);
    const __m256d zero = _mm256_setzero_pd(), lanes = _mm256_set_pd(3.0, 2.0, 1.0, 0.0);
    const __m256d none = _mm256_set1_pd(-1.0);
    const long long stride = d[0] + 1;
    const __m256d vj1 = _mm256_set1_pd(double(j1));
    const double r2 = r * r;
    long long total = 0;
    for (int k = k0; k <= k1; ++k) {
        double rz2[8];
        for (int q = 0; q < n; ++q) {
            const double dz = k - zs[q];
            rz2[q] = r2 - dz * dz;
        }
        const long long weightK = twiceZ && 2 * k != d[2] - 1 ? 2 : 1;
        for (int j = j0; j <= j1; j += 4) {
            const __m256d jv = _mm256_add_pd(_mm256_set1_pd(double(j)), lanes);
            __m256d rx2 = none; // the largest r^2 - dz^2 - dy^2 that is >= 0, else negative
            for (int q = 0; q < n; ++q) {
                const __m256d dy = _mm256_sub_pd(jv, _mm256_set1_pd(ys[q]));
                rx2 = _mm256_max_pd(rx2, _mm256_sub_pd(_mm256_set1_pd(rz2[q]), _mm256_mul_pd(dy, dy)));
            }
            const __m256d row =
                _mm256_and_pd(_mm256_cmp_pd(jv, vj1, _CMP_LE_OQ), _mm256_cmp_pd(rx2, zero, _CMP_GE_OQ));
            if (_mm256_movemask_pd(row) == 0) continue;
            const __m256d rx = _mm256_sqrt_pd(_mm256_max_pd(rx2, zero));
            total += unionOfRuns(rx, row, vxa, vxb, d, j,
                                 prefix + (j + static_cast<long long>(d[1]) * k) * stride, twiceY, weightK);
        }
    }
    return total;
}
#endif

namespace {
/// The counts of one run of a row, @p c[i0..i1], change by @p d (+-1, +-2); @p flips and @p inside count the
/// voxels whose coverage flips (count 0 before when adding, -d when removing), all and those in S (@p s);
/// @p first: the first flip, if none before (-1).
template <class Count>
void countRun(Count* c, const std::uint8_t* s, int i0, int i1, int d, int& flips, int& inside, int& first) {
    const auto flipAt = static_cast<Count>(d > 0 ? 0 : -d);
    int i = i0;
#if defined(__SSE2__)
    if constexpr (sizeof(Count) == 1) {
        // 16 voxels at a time, the counts of flips in byte lanes (summed every 255 blocks); the loop the
        // compiler made widened each byte to 32 bits for the sums (ellipsoid 10: changes were a fifth of the
        // run)
        const __m128i at = _mm_set1_epi8(static_cast<char>(flipAt)), dv = _mm_set1_epi8(static_cast<char>(d));
        const __m128i zero = _mm_setzero_si128();
        while (i + 16 <= i1 + 1) {
            __m128i fAcc = zero, iAcc = zero;
            for (int b = 0; b < 255 && i + 16 <= i1 + 1; ++b, i += 16) {
                const __m128i cv = _mm_loadu_si128(reinterpret_cast<const __m128i*>(c + i));
                const __m128i sv = _mm_loadu_si128(reinterpret_cast<const __m128i*>(s + i));
                const __m128i eq = _mm_cmpeq_epi8(cv, at);
                if (first < 0)
                    if (const int mask = _mm_movemask_epi8(eq)) first = i + __builtin_ctz(unsigned(mask));
                fAcc = _mm_sub_epi8(fAcc, eq);
                iAcc = _mm_sub_epi8(iAcc, _mm_andnot_si128(_mm_cmpeq_epi8(sv, zero), eq));
                _mm_storeu_si128(reinterpret_cast<__m128i*>(c + i), _mm_add_epi8(cv, dv));
            }
            const __m128i fs = _mm_sad_epu8(fAcc, zero), is = _mm_sad_epu8(iAcc, zero);
            flips += _mm_cvtsi128_si32(fs) + _mm_extract_epi16(fs, 4);
            inside += _mm_cvtsi128_si32(is) + _mm_extract_epi16(is, 4);
        }
        if (i + 8 <= i1 + 1) { // 8 more (most runs are short: the rest one at a time was most of the time)
            const __m128i cv = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(c + i));
            const __m128i sv = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(s + i));
            const __m128i eq = _mm_and_si128(_mm_cmpeq_epi8(cv, at), _mm_set_epi64x(0, -1));
            if (first < 0)
                if (const int mask = _mm_movemask_epi8(eq)) first = i + __builtin_ctz(unsigned(mask));
            const __m128i fs = _mm_sad_epu8(_mm_sub_epi8(zero, eq), zero);
            const __m128i is =
                _mm_sad_epu8(_mm_sub_epi8(zero, _mm_andnot_si128(_mm_cmpeq_epi8(sv, zero), eq)), zero);
            flips += _mm_cvtsi128_si32(fs);
            inside += _mm_cvtsi128_si32(is);
            _mm_storel_epi64(reinterpret_cast<__m128i*>(c + i), _mm_add_epi8(cv, dv));
            i += 8;
        }
    } else {
        // 16-bit counts (more than 255 balls: a quality target without a cap), 8 voxels at a time; a lane's
        // flips stay under 2^16 (a row has at most 32767 voxels)
        const __m128i at = _mm_set1_epi16(static_cast<short>(flipAt)),
                      dv = _mm_set1_epi16(static_cast<short>(d));
        const __m128i zero = _mm_setzero_si128();
        __m128i fAcc = zero, iAcc = zero;
        for (; i + 8 <= i1 + 1; i += 8) {
            const __m128i cv = _mm_loadu_si128(reinterpret_cast<const __m128i*>(c + i));
            const __m128i sv =
                _mm_unpacklo_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(s + i)), zero);
            const __m128i eq = _mm_cmpeq_epi16(cv, at);
            if (first < 0)
                if (const int mask = _mm_movemask_epi8(eq)) first = i + __builtin_ctz(unsigned(mask)) / 2;
            fAcc = _mm_sub_epi16(fAcc, eq);
            iAcc = _mm_sub_epi16(iAcc, _mm_andnot_si128(_mm_cmpeq_epi16(sv, zero), eq));
            _mm_storeu_si128(reinterpret_cast<__m128i*>(c + i), _mm_add_epi16(cv, dv));
        }
        alignas(16) std::uint16_t fl[8], in[8];
        _mm_store_si128(reinterpret_cast<__m128i*>(fl), fAcc);
        _mm_store_si128(reinterpret_cast<__m128i*>(in), iAcc);
        for (int l = 0; l < 8; ++l) {
            flips += fl[l];
            inside += in[l];
        }
    }
#endif
    for (; i <= i1; ++i) {
        const bool flip = c[i] == flipAt;
        if (flip && first < 0) first = i;
        flips += flip;
        inside += flip & (s[i] != 0);
        c[i] = static_cast<Count>(c[i] + d);
    }
}

/// The prefix @p p[i0..i1] of a row from @p acc (the sum before i0): g = (S ? 1 : -1) where the count @p c
/// is 0, modulo 2^16.
} // namespace

template <class Count>
void prefixRun(const Count* c, const std::uint8_t* s, std::uint16_t* p, int i0, int i1, std::uint16_t acc) {
    int i = i0;
#if defined(__SSE2__)
    // 8 voxels at a time: the sums within the vector by three shifted adds, then the carry (the serial loop's
    // one add a voxel was its dependency chain)
    const __m128i zero = _mm_setzero_si128(), one = _mm_set1_epi16(1);
    for (; i + 8 <= i1 + 1; i += 8) {
        __m128i c16;
        if constexpr (sizeof(Count) == 1)
            c16 = _mm_unpacklo_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(c + i)), zero);
        else
            c16 = _mm_loadu_si128(reinterpret_cast<const __m128i*>(c + i));
        const __m128i s16 = _mm_unpacklo_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(s + i)), zero);
        // g: 1 in S, 0xFFFF (-1) outside, where uncovered; 0 where covered
        __m128i x = _mm_and_si128(_mm_or_si128(_mm_cmpeq_epi16(s16, zero), one), _mm_cmpeq_epi16(c16, zero));
        x = _mm_add_epi16(x, _mm_slli_si128(x, 2));
        x = _mm_add_epi16(x, _mm_slli_si128(x, 4));
        x = _mm_add_epi16(x, _mm_slli_si128(x, 8));
        x = _mm_add_epi16(x, _mm_set1_epi16(static_cast<short>(acc)));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(p + i), x);
        acc = static_cast<std::uint16_t>(_mm_extract_epi16(x, 7));
    }
#endif
    for (; i <= i1; ++i) {
        acc = static_cast<std::uint16_t>(acc + (c[i] == 0 ? (s[i] ? 1 : 0xFFFF) : 0));
        p[i] = acc;
    }
}

/// One row of Coverage::changeSlice: the counts @p c of voxels u0..u1 change by @p delta, and those of
/// o0..o1 (within, or empty: o0 > o1) by 2 delta more (two mirror images' runs that overlap); the prefix @p p
/// (p[-1]: the row's base) follows where a voxel flips between covered and uncovered.
/// @p Count: the counts' type (8 bits where at most 255 balls are ever placed, else 16; runs by SSE2).
template <class Count>
void changeRow(Count* c, const std::uint8_t* s, std::uint16_t* p, int nx, int u0, int u1, int o0, int o1,
               int delta, long long& dMismatch, long long& dCovered) {
    int flips = 0, inside = 0, first = -1;
    if (o0 > o1) {
        countRun(c, s, u0, u1, delta, flips, inside, first);
    } else {
        countRun(c, s, u0, o0 - 1, delta, flips, inside, first);
        countRun(c, s, o0, o1, 2 * delta, flips, inside, first);
        countRun(c, s, o1 + 1, u1, delta, flips, inside, first);
    }
    if (flips == 0) return; // no voxel changes between covered and uncovered: prefix unchanged
    // from the first flip (a voxel now uncovered, or covered by this change alone) the prefix is recomputed
    // to the end of the change; what follows moves by the change of the interval's sum (each flipped voxel's
    // g comes or goes), or, where the part before is shorter, that part and the base move the other way
    // (modulo 2^16, as the prefix is kept)
    const int sign = delta > 0 ? 1 : -1;
    const auto shift = static_cast<std::uint16_t>(-sign * (2 * inside - flips));
    const bool left = first < nx - 1 - u1;
    prefixRun(c, s, p, first, u1, static_cast<std::uint16_t>(p[first - 1] - (left ? shift : 0)));
    if (left) {
        for (int i = -1; i < first; ++i) p[i] = static_cast<std::uint16_t>(p[i] - shift); // the base too
    } else {
        for (int i = u1 + 1; i < nx; ++i) p[i] = static_cast<std::uint16_t>(p[i] + shift);
    }
    // each flipped voxel inside S changes the mismatch by -1 when covered, +1 when uncovered; outside the
    // other way
    dMismatch -= sign * (2LL * inside - flips);
    dCovered += static_cast<long long>(sign) * flips;
}

template void prefixRun(const std::uint8_t*, const std::uint8_t*, std::uint16_t*, int, int, std::uint16_t);
template void prefixRun(const std::uint16_t*, const std::uint8_t*, std::uint16_t*, int, int, std::uint16_t);
template void changeRow(std::uint8_t*, const std::uint8_t*, std::uint16_t*, int, int, int, int, int, int,
                        long long&, long long&);
template void changeRow(std::uint16_t*, const std::uint8_t*, std::uint16_t*, int, int, int, int, int, int,
                        long long&, long long&);

} // namespace mss::engine::rows
