// mss: command-line front end of the yade-mss core.
#include "mss.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

const char* kUsage = R"(mss: multi-sphere shape generator (MSS) for DEM clumps

usage:
  mss generate INPUT [options] -o OUT     spheres for a mesh (.stl .obj .off .ply) or voxels (.npy)
  mss compare INPUT SPHERES [options]     score a sphere file against the target
  mss info INPUT                          what was read

generate options (termination: give at least one of --spheres, --eta, --dice, --rmin):
  --spheres N          at most N spheres (problem (i) of the paper)
  --eta X              stop at relative mismatch eta <= X (eq. 7; problem (ii))
  --dice X             stop at Dice mismatch D <= X (eq. 27)
  --rmin R             no sphere of radius below R (world units)
  --voxel-size H       voxel edge in world units, or
  --resolution N       N voxels along the shortest bounding-box edge (default 100; the paper uses 205)
  --supersample K      K^3 samples per voxel when voxelising a mesh (default 1: voxel centres)
  --method M           optimized (default) or paper (the published procedure)
  --delta-min D        minimal centre distance in voxels, paper mode (default 1)
  --no-symmetry        do not detect and keep mirror planes
  --clip               no sphere protrudes from the grain (exact distance to the mesh; voxel faces for .npy)
  --no-refill          with --clip: shrink the spheres afterwards instead of choosing them under the constraint
  --plane P,N          PX,PY,PZ,NX,NY,NZ: no sphere crosses this plane (spheres stay on the normal's side);
                       may repeat
  --max-iterations N   iteration cap (default 100)
  --threads T          OpenMP threads (result is the same for any T)
  --memory-limit GIB   refuse grids needing more (default 8)
  -o, --output OUT     .csv (x,y,z,r), .txt (YADE text clump: x y z r clumpId) or .vtk (ParaView)
voxel input (.npy) options:
  --npy-voxel-size H   voxel edge of the array (default 1)     --origin X,Y,Z  centre of voxel (0,0,0)
  --label L            solid = voxels equal to L (labelled volumes; default: non-zero)
compare options:
  --resolution N       scoring grid: N voxels along the shortest edge (default 100)
  --offset F           shift of the scoring grid, in voxels (default 0.37)
  --clump ID           the clump with this id, when SPHERES is a YADE text file of several
  --plane PX,PY,PZ,NX,NY,NZ   score against the part of the target on the normal's side (a fragment)
)";

struct Args {
    std::vector<std::string> positional;
    std::vector<std::string> planes; // --plane may repeat
    std::map<std::string, std::string> opts;
    bool has(const std::string& k) const { return opts.count(k) != 0; }
};

const std::map<std::string, bool> kOptions = {{"--spheres", true},
                                              {"--eta", true},
                                              {"--dice", true},
                                              {"--rmin", true},
                                              {"--voxel-size", true},
                                              {"--resolution", true},
                                              {"--supersample", true},
                                              {"--method", true},
                                              {"--delta-min", true},
                                              {"--no-symmetry", false},
                                              {"--max-iterations", true},
                                              {"--threads", true},
                                              {"--memory-limit", true},
                                              {"-o", true},
                                              {"--output", true},
                                              {"--npy-voxel-size", true},
                                              {"--origin", true},
                                              {"--label", true},
                                              {"--offset", true},
                                              {"--help", false},
                                              {"-h", false},
                                              {"--clip", false},
                                              {"--no-refill", false},
                                              {"--plane", true},
                                              {"--clump", true}};

Args parse(int argc, char** argv, int from) {
    Args a;
    for (int i = from; i < argc; ++i) {
        std::string s = argv[i];
        if (s.size() > 1 && s[0] == '-' &&
            !(s.size() > 1 && (std::isdigit(static_cast<unsigned char>(s[1])) || s[1] == '.'))) {
            auto it = kOptions.find(s);
            if (it == kOptions.end()) throw std::invalid_argument("unknown option '" + s + "'");
            if (it->second) {
                if (i + 1 >= argc) throw std::invalid_argument("option " + s + " needs a value");
                if (s == "--plane")
                    a.planes.push_back(argv[++i]);
                else
                    a.opts[s == "-o" ? "--output" : s] = argv[++i];
            } else {
                a.opts[s] = "";
            }
        } else {
            a.positional.push_back(s);
        }
    }
    return a;
}

double number(const Args& a, const std::string& key, double fallback) {
    auto it = a.opts.find(key);
    if (it == a.opts.end()) return fallback;
    char* end = nullptr;
    const double v = std::strtod(it->second.c_str(), &end);
    if (end == it->second.c_str() || *end != '\0')
        throw std::invalid_argument(key + ": '" + it->second + "' is not a number");
    return v;
}

int integer(const Args& a, const std::string& key, int fallback) {
    auto it = a.opts.find(key);
    if (it == a.opts.end()) return fallback;
    char* end = nullptr;
    const long v = std::strtol(it->second.c_str(), &end, 10);
    if (end == it->second.c_str() || *end != '\0' || v < -2147483647L || v > 2147483647L)
        throw std::invalid_argument(key + ": '" + it->second + "' is not an integer");
    return static_cast<int>(v);
}

std::vector<mss::Plane> planes(const Args& a) {
    std::vector<mss::Plane> out;
    for (const std::string& text : a.planes) {
        std::string t = text;
        for (char& c : t)
            if (c == ',') c = ' ';
        std::istringstream is(t);
        mss::Plane p;
        if (!(is >> p.point.x() >> p.point.y() >> p.point.z() >> p.normal.x() >> p.normal.y() >>
              p.normal.z()))
            throw std::invalid_argument("--plane: expected PX,PY,PZ,NX,NY,NZ, got '" + text + "'");
        out.push_back(p);
    }
    return out;
}

mss::Vec3 vec3(const Args& a, const std::string& key) {
    auto it = a.opts.find(key);
    if (it == a.opts.end()) return mss::Vec3::Zero();
    std::string s = it->second;
    for (char& c : s)
        if (c == ',') c = ' ';
    std::istringstream is(s);
    mss::Vec3 v;
    if (!(is >> v.x() >> v.y() >> v.z())) throw std::invalid_argument(key + ": expected X,Y,Z");
    return v;
}

bool isVoxelFile(const std::string& path) {
    return mss::fileExtension(path) == ".npy";
}

mss::VoxelGrid readVoxels(const Args& a, const std::string& path) {
    return mss::readNpy(path, number(a, "--npy-voxel-size", 1.0), vec3(a, "--origin"),
                        a.has("--label") ? integer(a, "--label", -1) : -1);
}

mss::Resolution resolution(const Args& a) {
    mss::Resolution r;
    r.memoryLimit = static_cast<std::size_t>(number(a, "--memory-limit", 8.0) * 1073741824.0);
    if (a.has("--voxel-size") && a.has("--resolution"))
        throw std::invalid_argument("give either --voxel-size or --resolution, not both");
    if (a.has("--voxel-size"))
        r.voxelSize = number(a, "--voxel-size", 0.0);
    else
        r.resolution = integer(a, "--resolution", 100);
    if (a.has("--resolution") && r.resolution < 1)
        throw std::invalid_argument("--resolution must be >= 1 voxel along the shortest edge, got " +
                                    a.opts.at("--resolution"));
    if (a.has("--voxel-size") && !(r.voxelSize > 0)) throw std::invalid_argument("--voxel-size must be > 0");
    return r;
}

void printMetrics(const mss::Result& r) {
    const auto& m = r.metrics;
    std::cout << std::setprecision(6);
    std::cout << "grid        " << r.grid.dims[0] << " x " << r.grid.dims[1] << " x " << r.grid.dims[2]
              << "  voxel size " << r.grid.h << "\n";
    std::cout << "spheres     " << m.spheres << "\n";
    std::cout << "eta         " << m.eta << "   (relative mismatch, eq. 7, generation grid)\n";
    std::cout << "dice        " << m.dice << "   (Dice mismatch, eq. 27, generation grid)\n";
    std::cout << "iterations  " << m.iterations << "   symmetry planes kept " << m.symmetryPlanes << "\n";
    if (m.clipped) std::cout << "clipped     " << m.clipped << " spheres shrunk by the final clipping\n";
    std::cout << std::setprecision(3) << "seconds     read " << m.secondsRead << "  voxelize "
              << m.secondsVoxelize << "  edt " << m.secondsEdt << "  select " << m.secondsSelect
              << "  refine " << m.secondsRefine << "  total " << m.secondsTotal << "\n";
}

int cmdGenerate(const Args& a) {
    if (a.positional.size() != 1) throw std::invalid_argument("generate needs one INPUT file");
    if (!a.has("--output")) throw std::invalid_argument("generate needs -o OUT (.csv, .txt or .vtk)");
    const std::string in = a.positional[0], out = a.opts.at("--output");
    {
        const std::string ext = mss::fileExtension(out);
        if (ext != ".csv" && ext != ".txt" && ext != ".vtk")
            throw std::invalid_argument(out + ": unknown output extension '" + ext +
                                        "' (expected .csv, .txt or .vtk)");
    }
    mss::GenerateOptions o;
    o.nSpheres = integer(a, "--spheres", 0);
    if (a.has("--spheres") && o.nSpheres < 1)
        throw std::invalid_argument("--spheres must be >= 1, got " + a.opts.at("--spheres"));
    o.eta = number(a, "--eta", 0.0);
    o.dice = number(a, "--dice", 0.0);
    o.rMin = number(a, "--rmin", 0.0);
    o.deltaMin = number(a, "--delta-min", 1.0);
    o.maxIterations = integer(a, "--max-iterations", 100);
    o.threads = integer(a, "--threads", 0);
    o.keepSymmetry = !a.has("--no-symmetry");
    o.clip = a.has("--clip");
    o.refill = !a.has("--no-refill");
    o.planes = planes(a);
    const std::string method = a.has("--method") ? a.opts.at("--method") : "optimized";
    if (method == "optimized")
        o.method = mss::Method::Optimized;
    else if (method == "paper")
        o.method = mss::Method::Paper;
    else
        throw std::invalid_argument("--method must be optimized or paper, got '" + method + "'");
    mss::validateOptions(o);
    const auto t0 = std::chrono::steady_clock::now();
    mss::Result r;
    if (isVoxelFile(in)) {
        const mss::VoxelGrid v = readVoxels(a, in);
        const double tRead = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        r = mss::generate(v, o);
        r.metrics.secondsRead = tRead;
    } else {
        const mss::TriangleMesh mesh = mss::readMesh(in);
        const double tRead = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        r = mss::generate(mesh, resolution(a), o, integer(a, "--supersample", 1));
        r.metrics.secondsRead = tRead;
    }
    for (const std::string& w : r.metrics.warnings)
        std::cerr << "mss generate: warning: " << in << ": " << w << "\n";
    mss::writeSpheres(r.spheres, out);
    r.metrics.secondsTotal = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    printMetrics(r);
    std::cout << "wrote       " << out << "\n";
    return 0;
}

int cmdCompare(const Args& a) {
    const std::vector<mss::Plane> cuts = planes(a);
    if (a.positional.size() != 2) throw std::invalid_argument("compare needs INPUT and SPHERES files");
    const mss::SphereSet s =
        mss::readSpheres(a.positional[1], a.has("--clump") ? integer(a, "--clump", -1) : -1);
    mss::Score sc;
    if (isVoxelFile(a.positional[0])) {
        sc = mss::scoreSpheres(readVoxels(a, a.positional[0]), s, cuts);
    } else {
        const int res = integer(a, "--resolution", 100);
        sc = mss::scoreSpheres(mss::readMesh(a.positional[0]), s, res, number(a, "--offset", 0.37),
                               integer(a, "--supersample", 1), cuts);
    }
    std::cout << std::setprecision(6);
    std::cout << "grid          " << sc.grid.dims[0] << " x " << sc.grid.dims[1] << " x " << sc.grid.dims[2]
              << "  voxel size " << sc.grid.h << "\n";
    std::cout << "spheres       " << s.size() << "\n";
    std::cout << "dice          " << sc.dice << "\n";
    std::cout << "eta           " << sc.eta << "\n";
    std::cout << "volume_ratio  " << sc.volumeRatio << "\n";
    std::cout << "coverage      " << sc.coverage << "\n";
    std::cout << "outside       " << sc.outside << "\n";
    return 0;
}

int cmdInfo(const Args& a) {
    if (a.positional.size() != 1) throw std::invalid_argument("info needs one INPUT file");
    const std::string in = a.positional[0];
    std::cout << std::setprecision(8);
    if (isVoxelFile(in)) {
        const mss::VoxelGrid v = readVoxels(a, in);
        std::cout << "voxels        " << v.nx() << " x " << v.ny() << " x " << v.nz() << "\n";
        std::cout << "solid         " << mss::countSolid(v) << "\n";
        std::cout << "voxel size    " << v.spec.h << "\n";
        std::cout << "volume        " << double(mss::countSolid(v)) * v.spec.h * v.spec.h * v.spec.h << "\n";
        return 0;
    }
    const mss::TriangleMesh mesh = mss::readMesh(in);
    const mss::MeshInfo i = mss::analyzeMesh(mesh);
    std::cout << "vertices      " << i.vertices << "\n";
    std::cout << "triangles     " << i.triangles << "\n";
    std::cout << "closed        " << (i.closed ? "yes" : "no") << "\n";
    std::cout << "boundary_edges " << i.boundaryEdges << "\n";
    std::cout << "nonmanifold_edges " << i.nonManifoldEdges << "\n";
    std::cout << "inconsistent_edges " << i.inconsistentEdges << "\n";
    std::cout << "oriented      " << (i.consistentlyOriented ? "yes" : "no")
              << (i.signedVolume < 0 ? " (inside out)" : "") << "\n";
    std::cout << "degenerate    " << i.degenerateTriangles << "\n";
    std::cout << "self_intersections " << mss::countSelfIntersections(mesh) << "\n";
    std::cout << "volume        " << std::abs(i.signedVolume) << "\n";
    std::cout << "bbox_min      " << i.lower.x() << " " << i.lower.y() << " " << i.lower.z() << "\n";
    std::cout << "bbox_max      " << i.upper.x() << " " << i.upper.y() << " " << i.upper.z() << "\n";
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::cerr << kUsage;
        return 2;
    }
    const std::string cmd = argv[1];
    if (cmd == "-h" || cmd == "--help" || cmd == "help") {
        std::cout << kUsage;
        return 0;
    }
    try {
        const Args a = parse(argc, argv, 2);
        if (a.has("--help") || a.has("-h")) {
            std::cout << kUsage;
            return 0;
        }
        if (cmd == "generate") return cmdGenerate(a);
        if (cmd == "compare") return cmdCompare(a);
        if (cmd == "info") return cmdInfo(a);
        std::cerr << "mss: unknown command '" << cmd << "'\n" << kUsage;
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "mss " << cmd << ": error: " << e.what() << "\n";
        return 1;
    }
}
