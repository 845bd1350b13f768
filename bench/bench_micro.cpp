// Micro-benchmarks of the EDT and the voxeliser on the femur (paper benchmark 2).
// Reports voxels per second as items_per_second. Run: build/mss_bench [--benchmark_filter=Edt]
#include "mss.hpp"
#include "mss/core/edt.hpp"
#include "mss/core/maxima.hpp"
#include "mss/core/mesh_query.hpp"

#include <benchmark/benchmark.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#ifndef MSS_BENCH_DATA
#define MSS_BENCH_DATA "tests/data"
#endif

namespace {
const mss::TriangleMesh& femur() {
    static const mss::TriangleMesh m = mss::readMesh(std::string(MSS_BENCH_DATA) + "/human_femur.stl");
    return m;
}

void setThreads(int t) {
#ifdef _OPENMP
    omp_set_num_threads(t);
#endif
}

void BM_Edt(benchmark::State& state) {
    setThreads(int(state.range(1)));
    mss::Resolution res;
    res.resolution = int(state.range(0));
    const mss::VoxelGrid v = mss::voxelizeMesh(femur(), res);
    mss::ScalarGrid e;
    for (auto _ : state) {
        mss::distanceTransform(v, e);
        benchmark::DoNotOptimize(e.data.data());
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(v.size()));
    state.counters["voxels"] = double(v.size());
}
BENCHMARK(BM_Edt)->Args({103, 1})->Args({103, 2})->Args({205, 1})->Args({205, 2})->Unit(
    benchmark::kMillisecond);

void BM_Voxelize(benchmark::State& state) {
    setThreads(int(state.range(2)));
    mss::Resolution res;
    res.resolution = int(state.range(0));
    std::size_t n = 0;
    for (auto _ : state) {
        const mss::VoxelGrid v = mss::voxelizeMesh(femur(), res, int(state.range(1)));
        n = v.size();
        benchmark::DoNotOptimize(v.data.data());
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(n));
}
BENCHMARK(BM_Voxelize)
    ->Args({103, 1, 1})
    ->Args({103, 1, 2})
    ->Args({205, 1, 2})
    ->Args({103, 3, 2})
    ->Unit(benchmark::kMillisecond);
} // namespace

BENCHMARK_MAIN();
