#include "mss/core/edt.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <vector>

namespace mss {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr int kBlock = 16; // lines processed together so that strided passes read whole cache lines

/// 1-D squared distance transform of sampled function f (length n) into d, FH 2012 algorithm 1:
/// d(q) = min_p (q - p)^2 + f(p). Entries f = inf are not parabolas; the others are squared distances, whole
/// numbers (exact in float up to 2^24). v is scratch of n, zn and zd of n + 1.
/// Departure from FH: the intersections z are kept as fractions zn / (2 zd) of whole numbers and compared
/// by multiplying out, not divided (a division's latency sat on the loop's dependency chain: BM_Edt about
/// 15-20% faster). The same envelope at every sample: the float
/// quotient FH computes rounds monotonically, so it can only make two different intersections equal, and two
/// parabolas whose intersections differ by less than a rounding take the same whole value at every sample.
void envelope1d(const float* f, float* d, int n, int* v, long long* zn, long long* zd) {
    // Background (f = 0) before the first and after the last other entry is its own transform, and of its
    // parabolas only the one next to that entry can be lowest beyond it: the envelope runs on the rest
    // (a line of background only, common around a grain, costs a scan).
    int q0 = 0;
    while (q0 < n && f[q0] == 0.0f) ++q0;
    if (q0 == n) {
        std::fill(d, d + n, 0.0f);
        return;
    }
    int q1 = n - 1;
    while (f[q1] == 0.0f) --q1;
    const int lo = std::max(0, q0 - 1), hi = std::min(n - 1, q1 + 1);
    std::fill(d, d + lo, 0.0f);
    std::fill(d + hi + 1, d + n, 0.0f);
    f += lo;
    d += lo;
    n = hi - lo + 1;
    // parabola p: (q - p)^2 + f(p) = q^2 - 2 p q + (f(p) + p^2); two meet at q = (h(q) - h(p)) / (2 (q - p))
    // with h(p) = f(p) + p^2, kept as zn = h(q) - h(p) over zd = q - p > 0 (the factor 2 on the compared
    // side)
    int k = -1;
    for (int q = 0; q < n; ++q) {
        if (f[q] == kInf) continue;
        const long long hq = static_cast<long long>(f[q]) + static_cast<long long>(q) * q;
        long long sn = 0, sd = 1;
        while (k >= 0) {
            const int p = v[k];
            const long long hp = static_cast<long long>(f[p]) + static_cast<long long>(p) * p;
            sn = hq - hp;
            sd = q - p;
            // s > z[k] (z[0] = -inf): sn / sd > zn / zd
            if (k == 0 || sn * zd[k] > zn[k] * sd) break;
            --k;
        }
        ++k;
        v[k] = q;
        zn[k] = sn;
        zd[k] = sd;
    }
    if (k < 0) {
        std::fill(d, d + n, kInf);
        return;
    }
    // sample q lies beyond z[j + 1] when 2 q zd > zn
    int j = 0;
    for (int q = 0; q < n; ++q) {
        while (j < k && zn[j + 1] < 2LL * q * zd[j + 1]) ++j;
        const float dq = static_cast<float>(q - v[j]);
        d[q] = dq * dq + f[v[j]];
    }
}

/// Runs envelope1d on the lines of a strided pass: lines start at base + b (b < count, consecutive x), step
/// `stride` between samples, samples q0..q1 of each (every sample outside that window is background: 0, and
/// stays 0).
void strided(float* data, std::size_t base, int count, std::size_t stride, int q0, int q1,
             std::vector<float>& buf, std::vector<float>& out, std::vector<int>& v,
             std::vector<long long>& zn, std::vector<long long>& zd, bool takeRoot) {
    const int n = q1 - q0 + 1;
    data += base + static_cast<std::size_t>(q0) * stride;
    for (int q = 0; q < n; ++q) {
        const float* src = data + static_cast<std::size_t>(q) * stride;
        for (int b = 0; b < count; ++b) buf[static_cast<std::size_t>(b) * n + q] = src[b];
    }
    for (int b = 0; b < count; ++b)
        envelope1d(buf.data() + static_cast<std::size_t>(b) * n, out.data() + static_cast<std::size_t>(b) * n,
                   n, v.data(), zn.data(), zd.data());
    for (int q = 0; q < n; ++q) {
        float* dst = data + static_cast<std::size_t>(q) * stride;
        if (takeRoot)
            for (int b = 0; b < count; ++b) dst[b] = std::sqrt(out[static_cast<std::size_t>(b) * n + q]);
        else
            for (int b = 0; b < count; ++b) dst[b] = out[static_cast<std::size_t>(b) * n + q];
    }
}

/// The box of the solid in a plane of the grid: x from i0 to i1, the other axis from q0 to q1 (empty: i0 >
/// i1).
struct PlaneBox {
    int i0 = INT32_MAX, i1 = INT32_MIN, q0 = INT32_MAX, q1 = INT32_MIN;
    void add(int ia, int ib, int q) {
        i0 = std::min(i0, ia);
        i1 = std::max(i1, ib);
        q0 = std::min(q0, q);
        q1 = std::max(q1, q);
    }
};

} // namespace

ScalarGrid distanceTransform(const VoxelGrid& solid) {
    ScalarGrid out;
    distanceTransform(solid, out);
    return out;
}

void distanceTransform(const VoxelGrid& solid, ScalarGrid& out) {
    const int nx = solid.nx(), ny = solid.ny(), nz = solid.nz();
    if (solid.data.size() != solid.spec.size() || solid.data.empty())
        throw std::invalid_argument("distanceTransform: the volume is empty");
    out.spec = solid.spec;
    out.data.resize(solid.data.size());
    float* d = out.data.data();
    const std::uint8_t* s = solid.data.data();
    bool anyBackground = false;

    // Pass 1, along x: squared distance to the nearest background voxel in the row (two scans), between the
    // row's first and last solid voxels; background around them is 0 (a row of background only, most of a
    // slender grain's grid, is found 8 bytes at a time and filled: the pass about 3x faster on the femur).
    std::vector<int> rowFirst(static_cast<std::size_t>(ny) * nz), rowLast(rowFirst.size());
#pragma omp parallel for schedule(static) reduction(|| : anyBackground)
    for (int row = 0; row < ny * nz; ++row) {
        const std::size_t o = static_cast<std::size_t>(row) * nx;
        const std::uint8_t* sr = s + o;
        float* dr = d + o;
        int first = 0;
        for (std::uint64_t word = 0; first + 8 <= nx; first += 8) {
            std::memcpy(&word, sr + first, 8);
            if (word != 0) break;
        }
        while (first < nx && !sr[first]) ++first;
        rowFirst[std::size_t(row)] = first < nx ? first : INT32_MAX;
        rowLast[std::size_t(row)] = INT32_MIN;
        if (first == nx) { // no solid
            std::fill(dr, dr + nx, 0.0f);
            anyBackground = true;
            continue;
        }
        int lastSolid = nx - 1;
        while (!sr[lastSolid]) --lastSolid;
        rowLast[std::size_t(row)] = lastSolid;
        std::fill(dr, dr + first, 0.0f);
        std::fill(dr + lastSolid + 1, dr + nx, 0.0f);
        if (first > 0 || lastSolid < nx - 1) anyBackground = true;
        int last = first - 1; // the nearest background to the left (-1: none)
        for (int i = first; i <= lastSolid; ++i) {
            if (!sr[i]) {
                last = i;
                anyBackground = true;
            }
            dr[i] = last < 0 ? kInf : static_cast<float>(i - last);
        }
        last = lastSolid + 1 < nx ? lastSolid + 1 : -1; // to the right
        for (int i = lastSolid; i >= first; --i) {
            if (!sr[i]) last = i;
            if (last >= 0) dr[i] = std::min(dr[i], static_cast<float>(last - i));
            dr[i] = dr[i] * dr[i];
        }
    }
    if (!anyBackground)
        throw std::invalid_argument("distanceTransform: the volume has no background voxel; pad it first");

    // The solid's box in each slice k (x, y) and each plane j (x, z), from the rows' first and last solid
    // voxels: the strided passes run only on the lines through it and only between its ends widened by one
    // (the nearest background); everything outside is background, whose transform is 0 (femur at resolution
    // 103: a slice's box is a fifth of the slice).
    std::vector<PlaneBox> slice(static_cast<std::size_t>(nz)), plane(static_cast<std::size_t>(ny));
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j) {
            const std::size_t row = static_cast<std::size_t>(k) * ny + j;
            if (rowFirst[row] > rowLast[row]) continue;
            slice[std::size_t(k)].add(rowFirst[row], rowLast[row], j);
            plane[std::size_t(j)].add(rowFirst[row], rowLast[row], k);
        }
    const std::size_t sy = static_cast<std::size_t>(nx), sz = static_cast<std::size_t>(nx) * ny;
    // Pass 2, along y, and pass 3, along z: lower envelope of parabolas, blocks of kBlock x-adjacent lines.
#pragma omp parallel
    {
        const int longest = std::max(ny, nz);
        std::vector<float> buf(static_cast<std::size_t>(kBlock) * longest), res(buf.size());
        std::vector<long long> zn(longest + 1), zd(longest + 1);
        std::vector<int> v(longest);
        // the lines through each plane's box (plane p starts at p * outer; n samples a line, stride apart)
        auto pass = [&](const std::vector<PlaneBox>& boxes, std::size_t outer, std::size_t stride, int n,
                        bool takeRoot) {
#pragma omp for schedule(dynamic, 4)
            for (int p = 0; p < int(boxes.size()); ++p) {
                const PlaneBox& b = boxes[std::size_t(p)];
                for (int i0 = b.i0; i0 <= b.i1; i0 += kBlock)
                    strided(d, std::size_t(p) * outer + std::size_t(i0), std::min(kBlock, b.i1 + 1 - i0),
                            stride, std::max(0, b.q0 - 1), std::min(n - 1, b.q1 + 1), buf, res, v, zn, zd,
                            takeRoot);
            }
        };
        pass(slice, sz, sy, ny, false);
        pass(plane, sy, sz, nz, true);
    }
}

} // namespace mss
