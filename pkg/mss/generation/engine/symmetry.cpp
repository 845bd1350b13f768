#include "mss/generation/engine/symmetry.hpp"

#include <cstring>

namespace mss::engine {

std::array<bool, 3> mirrorAxes(const VoxelGrid& S, std::size_t solid, bool& exact) {
    exact = true;
    std::array<bool, 3> sym{false, false, false};
    const int nx = S.nx(), ny = S.ny(), nz = S.nz();
    const std::size_t limit = std::size_t(1e-3 * double(solid));
    auto rowDiff = [&](const std::uint8_t* a, const std::uint8_t* b, bool reversed) {
        std::size_t n = 0;
        if (!reversed && std::memcmp(a, b, std::size_t(nx)) == 0) return n;
        for (int i = 0; i < nx; ++i) n += a[i] != b[reversed ? nx - 1 - i : i];
        return n;
    };
    for (int a = 0; a < 3; ++a) {
        std::size_t diff = 0;
        for (int k = 0; k < nz && diff <= limit; ++k)
            for (int j = 0; j < ny; ++j) {
                const int jm = a == 1 ? ny - 1 - j : j, km = a == 2 ? nz - 1 - k : k;
                diff += rowDiff(&S(0, j, k), &S(0, jm, km), a == 0);
            }
        sym[a] = diff <= limit;
        exact = exact && (!sym[a] || diff == 0);
    }
    return sym;
}

std::vector<Ball> Symmetry::images(const Orbit& o) const {
    std::vector<Ball> out{{o.c, o.r}};
    if (o.broken) return out;
    for (int a = 0; a < 3; ++a) {
        if (!axes_[a] || o.onPlane[a]) continue;
        const std::size_t n = out.size();
        for (std::size_t i = 0; i < n; ++i) {
            Ball b = out[i];
            b.c[a] = 2.0 * mid_[a] - b.c[a];
            out.push_back(b);
        }
    }
    return out;
}

} // namespace mss::engine
