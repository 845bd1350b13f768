// libFuzzer harnesses: every file reader (STL, OBJ, OFF, PLY, .npy) and the generator on small voxel grids.
// One source, one target per MSS_FUZZ_* definition. A bad input must end in std::invalid_argument, never in a
// crash, a sanitizer report, a hang or another exception. Built by -DMSS_BUILD_FUZZ=ON (clang); the same code
// with fuzz/driver.cpp replays the seed corpus and every past crash in ctest (fuzz/regressions).
#include "mss.hpp"

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>
#include <unistd.h>

namespace {

#if defined(MSS_FUZZ_STL) || defined(MSS_FUZZ_OBJ) || defined(MSS_FUZZ_OFF) || defined(MSS_FUZZ_PLY) ||      \
    defined(MSS_FUZZ_NPY) || defined(MSS_FUZZ_SPHERES)
std::string scratch(const char* ext) {
    const char* dir = std::getenv("TMPDIR");
    return std::string(dir ? dir : "/tmp") + "/mss_fuzz_" + std::to_string(::getpid()) + ext;
}

void writeFile(const std::string& path, const uint8_t* data, size_t size) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
}
#endif

#if defined(MSS_FUZZ_STL) || defined(MSS_FUZZ_OBJ) || defined(MSS_FUZZ_OFF) || defined(MSS_FUZZ_PLY)
#if defined(MSS_FUZZ_STL)
const char* kExt = ".stl";
#elif defined(MSS_FUZZ_OBJ)
const char* kExt = ".obj";
#elif defined(MSS_FUZZ_OFF)
const char* kExt = ".off";
#else
const char* kExt = ".ply";
#endif
void run(const uint8_t* data, size_t size) {
    static const std::string path = scratch(kExt);
    writeFile(path, data, size);
    try {
        const mss::TriangleMesh mesh = mss::readMesh(path);
        const mss::MeshInfo info = mss::analyzeMesh(mesh);
        if (info.triangles > 5000) return; // keep an execution short
        mss::Resolution res;
        res.resolution = 6;
        res.memoryLimit = std::size_t(64) << 20;
        const mss::VoxelGrid v = mss::voxelizeMesh(mesh, res);
        (void)mss::countSolid(v);
    } catch (const std::invalid_argument&) {
    }
}
#elif defined(MSS_FUZZ_NPY)
void run(const uint8_t* data, size_t size) {
    static const std::string path = scratch(".npy");
    writeFile(path, data, size);
    try {
        const mss::VoxelGrid v = mss::readNpy(path);
        if (v.size() > 4096) return;
        mss::GenerateOptions o;
        o.nSpheres = 2;
        (void)mss::generate(v, o);
    } catch (const std::invalid_argument&) {
    }
}
#elif defined(MSS_FUZZ_SPHERES)
// sphere files: legacy VTK (ASCII, binary), CSV and YADE text; all clumps, then clump 0
void run(const uint8_t* data, size_t size) {
    static const std::string path = scratch(".vtk");
    writeFile(path, data, size);
    for (long long clump : {-1LL, 0LL}) {
        try {
            const mss::SphereSet s = mss::readSpheres(path, clump);
            mss::validateSpheres(s, "fuzz");
        } catch (const std::invalid_argument&) {
        }
    }
}
#elif defined(MSS_FUZZ_GENERATE)
// bytes: nx, ny, nz (3..14), sphere budget, flags (paper, clip, symmetry, a plane through the centre whose
// normal the next bits pick, the joint polish), then the voxels' bits
void run(const uint8_t* data, size_t size) {
    if (size < 5) return;
    mss::GridSpec g;
    g.dims = {3 + data[0] % 12, 3 + data[1] % 12, 3 + data[2] % 12};
    g.h = 0.5;
    mss::VoxelGrid v(g, 0);
    for (std::size_t q = 0; q < v.size(); ++q) {
        const std::size_t byte = 5 + q / 8;
        v.data[q] = byte < size ? (data[byte] >> (q % 8)) & 1 : 0;
    }
    mss::GenerateOptions o;
    o.nSpheres = 1 + data[3] % 8;
    o.method = (data[4] & 1) ? mss::Method::Paper : mss::Method::Optimized;
    o.clip = (data[4] & 2) != 0;
    o.keepSymmetry = (data[4] & 4) != 0;
    o.maxIterations = 5;
    o.polish = (data[4] & 128) != 0;
    if (data[4] & 8) {
        mss::Plane p;
        p.point = g.toWorld(0.5 * mss::Vec3(g.dims[0] - 1, g.dims[1] - 1, g.dims[2] - 1));
        p.normal =
            mss::Vec3((data[4] & 16) ? 1.0 : 0.3, (data[4] & 32) ? -1.0 : 0.0, (data[4] & 64) ? 0.5 : 0.0);
        o.planes.push_back(p);
    }
    try {
        const mss::Result r = mss::generate(v, o);
        if (r.spheres.size() > std::size_t(o.nSpheres)) __builtin_trap(); // the budget is a promise
        for (std::size_t i = 0; i < r.spheres.size(); ++i) {
            if (!(r.spheres.radii[i] > 0) || !r.spheres.centers[i].allFinite()) __builtin_trap();
            for (const mss::Plane& p : o.planes) // no sphere crosses a plane
                if (mss::planeDistance(p, r.spheres.centers[i]) < r.spheres.radii[i] - 1e-9) __builtin_trap();
        }
    } catch (const std::invalid_argument&) {
    }
}
#else
#error "define one of MSS_FUZZ_STL, _OBJ, _OFF, _PLY, _NPY, _GENERATE"
#endif

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    run(data, size);
    return 0;
}
