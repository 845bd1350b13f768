#include "mss/generation/engine/paper.hpp"
#include "mss/core/edt.hpp"
#include "mss/core/maxima.hpp"
#include "mss/score.hpp"
#include "mss/voxelize.hpp"
#include "mss/work.hpp"

#include <algorithm>
#include <cstdint>

namespace mss::engine {

std::vector<Ball> runPaper(const VoxelGrid& S, const ScalarGrid& E, const Request& opt, Report& m,
                           const BoundVox& bound) {
    const double h = S.spec.h;
    const double rMinVox = opt.rMin / h;
    const std::size_t budget = opt.nSpheres > 0 ? std::size_t(opt.nSpheres) : SIZE_MAX;
    std::vector<Ball> balls;
    auto accept = [&](std::vector<Maximum>& cands) {
        // largest first (a budget takes the largest values), ties in voxel order: deterministic
        std::stable_sort(cands.begin(), cands.end(),
                         [](const Maximum& a, const Maximum& b) { return a.value > b.value; });
        std::size_t added = 0;
        for (const Maximum& c : cands) {
            if (balls.size() >= budget) break;
            tick("iteration " + std::to_string(m.iterations + 1) + ", " + std::to_string(balls.size()) +
                 " spheres");
            if (c.voxelValue < rMinVox)
                continue; // section 3.5: minimal radius (voxelValue holds the radius here)
            bool near = false;
            for (const Ball& b : balls)
                near = near || (b.c - c.position).norm() < opt.deltaMin; // δmin, section 3.4
            if (near) continue;
            double r = c.voxelValue;
            if (bound) r = bound.clamp(c.position, r); // clipped (section 3.5)
            if (r < std::max(rMinVox, 1e-3)) continue;
            balls.push_back({c.position, r});
            ++added;
        }
        return added;
    };
    // Initial representation S~0: spheres at the sub-voxel maxima of E, radius eq. 24.
    std::vector<Maximum> cands;
    for (const auto& v : localMaxima(E, 0.0f)) {
        Maximum mx = refineMaximum(E, v);
        mx.voxelValue = mx.value; // radius
        cands.push_back(mx);
    }
    accept(cands);
    const Targets t{opt.nSpheres > 0 ? opt.nSpheres : INT32_MAX, opt.eta, opt.dice};
    ScalarGrid Et, Estar(S.spec, 0.0f);
    for (m.iterations = 0; m.iterations < opt.maxIterations; ++m.iterations) {
        if (balls.size() >= budget) break;
        SphereSet world;
        for (const Ball& b : balls) world.add(S.spec.toWorld(b.c), b.r * h);
        const VoxelGrid St = voxelizeSpheres(world, S.spec); // step i
        const Mismatch mm = mismatch(S, St);
        if (t.met(mm.eta, mm.dice)) break;
        distanceTransform(St, Et);                 // step ii
        for (std::size_t q = 0; q < S.size(); ++q) // step iii, eq. 25, on the target's voxels
            Estar.data[q] = S.data[q] ? 2.0f * E.data[q] - Et.data[q] : 0.0f;
        cands.clear();
        for (const auto& v : localMaxima(Estar, 0.0f)) {
            Maximum mx = refineMaximum(Estar, v);
            mx.voxelValue = interpolateAxes(E, v, mx.position); // step iv: radius from E
            cands.push_back(mx);
        }
        if (accept(cands) == 0) break;
    }
    return balls;
}

} // namespace mss::engine
