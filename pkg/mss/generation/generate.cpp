#include "mss/generate.hpp"
#include "mss/core/ball_rows.hpp"
#include "mss/core/edt.hpp"
#include "mss/generation/contacts.hpp"
#include "mss/generation/engine/optimized.hpp"
#include "mss/generation/engine/paper.hpp"
#include "mss/generation/estimates.hpp"
#include "mss/generation/tiny_grain.hpp"
#include "mss/options.hpp"
#include "mss/platform/big_vector.hpp"
#include "mss/platform/cores.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <unordered_map>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace mss {

namespace {

using engine::Ball;
using engine::BoundVox;
using engine::Clock;
using engine::Orbit;
using engine::secondsSince;

/// Signed clearance of a point (world units): the exact distance from it to the grain's surface, positive
/// inside, negative outside.
using Clearance = std::function<double(const Vec3&)>;

/// The clearance in a voxel volume: to the nearest background voxel's cube (voxelClearance); outside, minus
/// half a voxel (the distance to the solid is not computed there).
Clearance voxelVolumeClearance(const VoxelGrid& grain, const ScalarGrid& Eg) {
    const double h = grain.spec.h;
    return [&grain, &Eg, h](const Vec3& c) {
        const double e = voxelClearance(grain, Eg, grain.spec.toVoxel(c));
        return e < 0 ? -0.5 * h : e * h; // outside: at least half a voxel from the solid
    };
}

/// Whether a point is inside and its clearance is greater than a value (world units), decided where that is
/// cheaper than the clearance itself; false also where it cannot tell. Empty: never told.
using ClearanceAbove = std::function<bool(const Vec3&, double)>;

/// The constraint on radii in world units: planes (never crossed) and the protrusion bound @p H beyond the
/// clearance (no centre outside); empty when there is none.
std::function<double(const Vec3&)> radiusBound(const Clearance& clearance, double H,
                                               const std::vector<Plane>& planes) {
    if (!std::isfinite(H) && planes.empty()) return {};
    return [clearance, H, &planes](const Vec3& c) {
        double b = std::numeric_limits<double>::infinity();
        for (const Plane& p : planes) b = std::min(b, planeDistance(p, c));
        if (!std::isfinite(H) || b < 0) return b;
        const double e = clearance(c);
        return e < 0 ? -1.0 : std::min(b, e + H);
    };
}

/// Whether the bound of radiusBound() at a point is certainly at least a radius R, by the planes and
/// @p above (without the exact clearance): then min(R, bound) is R. A margin of 1e-9 relative keeps the
/// answer true after the rounding of the bound's own arithmetic and of a change to voxel units.
std::function<bool(const Vec3&, double)> boundAtLeast(const ClearanceAbove& above, double H,
                                                      const std::vector<Plane>& planes) {
    return [above, H, &planes](const Vec3& c, double R) {
        const double margin = 1e-9 * (std::abs(R) + (std::isfinite(H) ? H : 0.0));
        for (const Plane& p : planes)
            if (!(planeDistance(p, c) >= R + margin)) return false;
        if (!std::isfinite(H)) return true;
        return above && above(c, R - H + margin);
    };
}

/// A lock held for a hash lookup: std::mutex puts a waiting thread to sleep in the kernel at once, and the
/// optimiser's threads look the bound up in bursts together (a few per cent of a run with the trial bounds
/// looked up in parallel). After a while it yields, in case the holder lost its core (shared CPUs).
class SpinLock {
public:
    void lock() {
        for (int spins = 0; flag_.exchange(true, std::memory_order_acquire);)
            while (flag_.load(std::memory_order_relaxed))
                if (++spins < 4096)
                    pause();
                else
                    std::this_thread::yield();
    }
    void unlock() { flag_.store(false, std::memory_order_release); }

private:
    static void pause() {
#if defined(__x86_64__) || defined(__i386__)
        __builtin_ia32_pause();
#endif
    }
    std::atomic<bool> flag_{false};
};

/// The constraint in voxel units of @p S, remembering its answers: the optimiser asks again and again at the
/// same points (moves back and forth). Exact at every point asked: an interpolation of the clearance between
/// voxel centres (from E, or from exact values there) with the final clipping putting right what it gets
/// wrong was tried and was 1.5-2x faster but lost fidelity (femur 70, bounded: D 24% higher from E - 1/2, 7%
/// higher from exact values at voxel centres, which is also slower: exact queries on the medial surface,
/// where much of the surface is nearly equidistant, are the dearest).
class CachedBound {
public:
    /// @p atLeast: boundAtLeast(), or empty
    CachedBound(std::function<double(const Vec3&)> world, std::function<bool(const Vec3&, double)> atLeast,
                const GridSpec& g)
        : world_(std::move(world)), atLeast_(std::move(atLeast)), g_(g) {}
    /// min(r, bound(v)): the answer remembered, or else where the cheaper test shows that the bound does not
    /// bind, r without the exact clearance. The greedy's candidates lie on E's ridge, whose radius E is at
    /// most about a voxel beyond the surface: under the default bound of a voxel 22 of the femur's 2490 were
    /// cut (median margin 0.79 voxel), and an exact query from the medial surface is dear there, and dearer
    /// still on the ellipsoid's axis (a ring of triangles all nearly as near).
    double clamp(const Vec3& v, double r) const {
        if (const double* b = find(v)) return std::min(r, *b);
        if (atLeast_ && atLeast_(g_.toWorld(v), r * g_.h)) return r;
        return std::min(r, (*this)(v));
    }
    /// Thread-safe: the optimiser warms the cache for the next points in parallel.
    double operator()(const Vec3& v) const {
        if (const double* b = find(v)) return *b;
        const double b = world_(g_.toWorld(v)) / g_.h; // exact and deterministic: a race computes it twice
        const std::lock_guard<SpinLock> lock(*lock_);
        cache_->emplace(key(v), b);
        return b;
    }

private:
    static std::array<long long, 3> key(const Vec3& v) {
        return {std::llround(v.x() * 65536.0), std::llround(v.y() * 65536.0), std::llround(v.z() * 65536.0)};
    }
    /// The remembered bound at @p v, or null (entries stay where they are: the map is node-based)
    const double* find(const Vec3& v) const {
        const auto k = key(v);
        const std::lock_guard<SpinLock> lock(*lock_);
        auto it = cache_->find(k);
        return it != cache_->end() ? &it->second : nullptr;
    }
    struct KeyHash {
        std::size_t operator()(const std::array<long long, 3>& k) const {
            return std::hash<long long>()(k[0] * 73856093LL ^ k[1] * 19349663LL ^ k[2] * 83492791LL);
        }
    };
    std::function<double(const Vec3&)> world_;
    std::function<bool(const Vec3&, double)> atLeast_;
    GridSpec g_;
    // shared by the copies std::function makes, so that every run of the optimiser uses one cache
    std::shared_ptr<std::unordered_map<std::array<long long, 3>, double, KeyHash>> cache_ =
        std::make_shared<std::unordered_map<std::array<long long, 3>, double, KeyHash>>();
    std::shared_ptr<SpinLock> lock_ = std::make_shared<SpinLock>();
};

/// Where the optimised method starts under a constraint: from nothing under it (cold), from the
/// unconstrained optimum cut down to it and refilled (warm: the paper's "clip, then continue"), or both.
enum class Starts { Cold, Warm, Both };

/// The spheres of the method asked for, in voxel units. Under constraints (clipping with refill, planes) the
/// optimised method may choose twice and keep the set with the lower mismatch on the generation grid: from
/// nothing under the constraint, and from the unconstrained optimum cut down to the constraint and then
/// refilled (greedy for the spheres lost, refinement of all under the constraint). Neither start wins always
/// (clipped, independent grid: ellipsoid 10 spheres 0.0104 cold / 0.0081 warm; octahedron 40: 0.130 /
/// 0.101; ellipsoid 40: 0.00134 / 0.00139; cube 40: 0.0753 / 0.0768).
/// The engine's request: the generation's targets and parameters.
engine::Request request(const GenerateOptions& o) {
    engine::Request r;
    r.nSpheres = o.nSpheres;
    r.eta = o.eta;
    r.dice = o.dice;
    r.rMin = o.rMin;
    r.maxIterations = o.maxIterations;
    r.deltaMin = o.deltaMin;
    r.keepSymmetry = o.keepSymmetry;
    r.planes = o.planes;
    r.polish = o.polish;
    return r;
}

std::vector<Ball> chooseBalls(const VoxelGrid& S, const ScalarGrid& E, const GenerateOptions& opt,
                              const BoundVox& boundVox, Starts starts, Metrics& metrics) {
    const engine::Request req = request(opt);
    engine::Report m{metrics.iterations, metrics.symmetryPlanes, metrics.secondsSelect};
    double secondsRefine = 0.0;
    std::vector<Ball> balls;
    const auto t0 = Clock::now();
    if (opt.method == Method::Paper) {
        balls = engine::runPaper(S, E, req, m, boundVox);
        m.secondsSelect = secondsSince(t0);
    } else if (boundVox && starts == Starts::Warm) {
        std::vector<Orbit> free;
        engine::SharedCandidates shared;
        engine::Report freeM = m;
        engine::runOptimized(S, E, req, BoundVox{}, freeM, secondsRefine, {}, &free, nullptr, &shared);
        balls = engine::runOptimized(S, E, req, boundVox, m, secondsRefine, free, nullptr, nullptr, &shared);
        m.secondsSelect += freeM.secondsSelect;
    } else if (boundVox && starts == Starts::Both) {
        engine::Report warmM = m, coldM = m;
        std::vector<Orbit> free;
        engine::SharedCandidates
            shared; // the three runs share their candidates (on the torus a large part of each run)
        engine::runOptimized(S, E, req, BoundVox{}, warmM, secondsRefine, {}, &free, nullptr, &shared);
        long long warmMismatch = 0, coldMismatch = 0;
        std::vector<Ball> warm = engine::runOptimized(S, E, req, boundVox, warmM, secondsRefine, free,
                                                      nullptr, &warmMismatch, &shared);
        std::vector<Ball> cold = engine::runOptimized(S, E, req, boundVox, coldM, secondsRefine, {}, nullptr,
                                                      &coldMismatch, &shared);
        const double select = warmM.secondsSelect + coldM.secondsSelect;
        // with a quality target (problem (ii)) fewer spheres win first, else less mismatch
        const auto w = std::make_pair(double(warmMismatch), double(warm.size()));
        const auto c = std::make_pair(double(coldMismatch), double(cold.size()));
        const bool useWarm = opt.eta > 0 || opt.dice > 0
                                 ? std::make_pair(w.second, w.first) <= std::make_pair(c.second, c.first)
                                 : w <= c;
        m = useWarm ? warmM : coldM;
        balls = useWarm ? std::move(warm) : std::move(cold);
        m.secondsSelect = select;
    } else {
        balls = engine::runOptimized(S, E, req, boundVox, m, secondsRefine);
    }
    metrics.iterations = m.iterations;
    metrics.symmetryPlanes = m.symmetryPlanes;
    metrics.secondsSelect = m.secondsSelect;
    metrics.secondsRefine = secondsRefine;
    return balls;
}

/// The OpenMP settings of one generation, restored afterwards (the host, YADE say, keeps its own): @p threads
/// if given. Otherwise, unless waiting threads sleep soon (a passive policy, or GOMP_SPINCOUNT of at most a
/// million rounds: the mss command sets one, yade_mss the passive policy), as many threads as cores are free
/// of other processes now (at least one; the host's own spinning threads do not count: they are the team), or
/// where /proc cannot tell, dynamic team sizes. A waiting thread spins by default, and the optimiser's many
/// short parallel regions made two processes of 2 threads on 2 cores each take 17x longer than alone (the
/// fidelity tests under ctest -j2). Dynamic sizes follow the one-minute load average, which lags a load that
/// has just begun: femur 70 under an active policy with 3 busy processes took 2-3.5x as long with them as on
/// one thread.
class OmpScope {
public:
    explicit OmpScope(int threads) {
#ifdef _OPENMP
        threads_ = omp_get_max_threads();
        dynamic_ = omp_get_dynamic();
        if (threads > 0) {
            omp_set_num_threads(threads);
            omp_set_dynamic(0);
        } else if (!waitersSleep()) {
            const long others = othersRunning();
            if (others >= 0) {
                omp_set_num_threads(threadsForFreeCores(usableCores(), others, threads_));
                omp_set_dynamic(0);
            } else {
                omp_set_dynamic(1);
            }
        }
#else
        (void)threads;
#endif
    }
    ~OmpScope() {
#ifdef _OPENMP
        omp_set_num_threads(threads_);
        omp_set_dynamic(dynamic_);
#endif
    }
    OmpScope(const OmpScope&) = delete;
    OmpScope& operator=(const OmpScope&) = delete;

private:
    static bool waitersSleep() {
        // the runtime started before the policy was set (yade_mss inside YADE says so): its waiters spin
        if (std::getenv("MSS_OMP_SPINNING")) return false;
        if (const char* c = std::getenv("GOMP_SPINCOUNT")) {
            char* end = nullptr;
            const double spins = std::strtod(c, &end);
            if (end != c && *end == '\0' && spins >= 0 && spins <= 1e6) return true;
        }
        const char* p = std::getenv("OMP_WAIT_POLICY");
        if (!p) return false;
        std::string s(p);
        for (char& ch : s) ch = char(std::tolower(static_cast<unsigned char>(ch)));
        return s == "passive";
    }
    int threads_ = 1, dynamic_ = 0;

public:
    /// Where waiting threads sleep (yade_mss sets the passive policy) and no thread count was given, a grid
    /// under kOneThreadVoxels runs on one thread: each of the optimiser's short parallel regions then wakes
    /// its team through the kernel, which cost more than the region's work. Femur in Python, 2 cores, best of
    /// 5: resolution 20, 70 spheres 193 ms by default against 42 ms on one thread; resolution 60 (594k
    /// voxels) 223 against 83; resolution 100 (2.6M voxels) 275 against 186, and 159 on two threads. The
    /// result does not depend on the thread count.
    static void forGrid(int threads, std::size_t voxels) {
#ifdef _OPENMP
        constexpr std::size_t kOneThreadVoxels = std::size_t(1) << 20;
        if (threads > 0 || !waitersSleep()) return;
        omp_set_num_threads(voxels < kOneThreadVoxels ? 1 : std::max(1, omp_get_num_procs()));
        omp_set_dynamic(0);
#else
        (void)threads;
        (void)voxels;
#endif
    }
};

/// A criterion left nothing: say which, never return an empty set silently.
[[noreturn]] void noSphereLeft(const ScalarGrid& E, const GenerateOptions& opt) {
    const double h = E.spec.h;
    const double inscribed = E.data.empty() ? 0.0 : h * *std::max_element(E.data.begin(), E.data.end());
    std::ostringstream os;
    if (opt.rMin > 0.0 && opt.rMin > inscribed)
        os << "generate: rMin " << opt.rMin << " (" << opt.rMin / h
           << " voxels) exceeds the largest inscribed "
           << "radius " << inscribed << " (" << inscribed / h
           << " voxels) of the grain: no sphere can be placed";
    else
        os << "generate: no sphere is left" << (opt.rMin > 0.0 ? " at or above rMin" : "")
           << (opt.clip || !opt.planes.empty()          ? " under the clipping constraint"
               : std::isfinite(protrusionLimit(opt, h)) ? " under the protrusion bound"
                                                        : "")
           << " (largest inscribed radius " << inscribed << ")";
    throw std::invalid_argument(os.str());
}

/// The largest protrusion of @p spheres: radius minus the centre's signed clearance, an upper bound (a
/// centre in a background voxel of a volume counts half a voxel).
double largestProtrusion(const SphereSet& spheres, const Clearance& clearance) {
    double worst = 0.0;
    for (std::size_t i = 0; i < spheres.size(); ++i) {
        double e = clearance(spheres.centers[i]);
        worst = std::max(worst, spheres.radii[i] - e);
    }
    return worst;
}

/// @p meshClearance: the mesh's clearance (exact distance to its surface), or empty: then the voxel volume's;
/// @p meshAbove: the mesh's ClearanceAbove, or empty.
Result generateOnGrid(const VoxelGrid& grain, const GenerateOptions& given, Metrics m,
                      Clock::time_point start, Clearance meshClearance = {}, ClearanceAbove meshAbove = {}) {
    if (countSolid(grain) == 0)
        throw std::invalid_argument("generate: the voxelised solid is empty (resolution too coarse?)");
    OmpScope::forGrid(given.threads, grain.size()); // undone by the generation's OmpScope
    GenerateOptions opt = given; // rMinVoxels in world units on this grid: from here on one bound, rMin
    opt.rMin = std::max(opt.rMin, opt.rMinVoxels * grain.spec.h);
    // Constraint planes cut the target as well: the spheres are fitted to, and scored against, the part of
    // the grain on the allowed side of every plane (voxel centres), so that a fragment gets its own D and a
    // quality target it can meet.
    VoxelGrid fragment;
    if (!opt.planes.empty()) {
        fragment = cutVoxelsByPlanes(grain, opt.planes);
        if (countSolid(fragment) == 0)
            throw std::invalid_argument(
                "generate: no part of the solid lies on the allowed side of the planes");
    }
    const VoxelGrid& S = opt.planes.empty() ? grain : fragment;
    const Work work = detail::generationWork(S, opt);
    checkWork("generate", work, opt.maxWork,
              "ask for fewer spheres (the option nSpheres) or a coarser grid (the option resolution)");
    Progress progress("generate", work.seconds);
    const auto t0 = Clock::now();
    const ScalarGrid E = distanceTransform(S); // eq. 8
    m.secondsEdt = secondsSince(t0);
    progress.update(-1.0, "distance transform done");
    const double h = S.spec.h;
    const double H = protrusionLimit(opt, h);
    m.protrusionLimit = H;
    ScalarGrid grainEdt; // the whole grain's, for the voxel clearance when planes cut it
    Clearance clearance = meshClearance;
    if (!clearance) { // stay in the union of the solid voxels' cubes, exactly
        if (!opt.planes.empty()) grainEdt = distanceTransform(grain);
        clearance = voxelVolumeClearance(grain, opt.planes.empty() ? E : grainEdt);
    }
    // a share of 1 is the bound everywhere: the neighbours' clearance, never below the grain's, changes
    // nothing
    std::shared_ptr<NeighbourClearance> near;
    if (opt.neighbourProtrusion < 1.0 && countSolid(opt.neighbours) > 0)
        near = std::make_shared<NeighbourClearance>(opt.neighbours);
    const double share = opt.neighbourProtrusion;
    const auto bound = withNeighbours(radiusBound(clearance, H, opt.planes), near, H, share);
    BoundVox boundVox;
    if (bound && (opt.refill || !std::isfinite(H))) {
        const CachedBound cached(bound, boundAtLeast(meshAbove, H, opt.planes), S.spec);
        boundVox = BoundVox(cached, [cached](const Vec3& v, double r) { return cached.clamp(v, r); });
    }
    // Both starts on tiny grains (under 5000 solid voxels), where one start is also the noisier (a CT grain
    // of 2122 voxels, 12 spheres: D 0.114 warm, 0.120 cold) and three runs cost milliseconds. Under the
    // default bound of one voxel on larger grains the two differ by 0-3% (femur 70: 28816 / 29740 mismatched
    // voxels warm / cold, cube 30 128710 / 127368, ellipsoid 10 equal): one run from nothing under the bound,
    // a third of the time. (A limit of 30000 voxels halved the throughput of bench/batch_scale.py, grains of
    // 3900-8700 voxels: 21.6 grains/s against 41.0, with the same worst D on the specimen of test_batch.)
    constexpr std::size_t kSmallGrain = 5000; // solid voxels
    // Clipping (and any bound under a voxel) on larger grains: the warm start alone. Clipped at resolution
    // 103, its mismatch on the generation grid was the lower of the two on 8 of 10 grains and at most 1.0%
    // above the cold start's on the others (cube 30 0.3%, octahedron 40 1.0%; torus 40: 7% below), and it
    // saves about a third of the time (femur 70, torus 40).
    // Constraint planes on larger grains (fragments: mssSplit's pieces) as clipping: the warm start alone.
    // Pieces at resolution 40 (ellipsoid, femur, octahedron, cube, torus, bunny, each cut by 3 random planes
    // through the centroid): 0.61-0.81x the time of both starts, D at most 1.0% higher on average (6, 10
    // and 20 spheres: 1.0 / 0.5 / 0.1%; worst piece 5.8%); the cold start alone was 1.8% higher at 10.
    const bool small = countSolid(S) < kSmallGrain;
    const Starts starts = small ? Starts::Both : (H < h || !opt.planes.empty() ? Starts::Warm : Starts::Cold);
    const std::vector<Ball> balls = chooseBalls(S, E, opt, boundVox, starts, m);
    Result r;
    r.grid = S.spec;
    const double rMin = std::max(opt.rMin, 1e-9 * h);
    // The clearance at each centre, once and in parallel: the final clipping and the largest protrusion
    // both ask for it, and an exact query is dear (with the final mismatch's counting by slice, the steps
    // after the optimiser about 3x faster).
    std::vector<Vec3> centres(balls.size());
    for (std::size_t q = 0; q < balls.size(); ++q) centres[q] = S.spec.toWorld(balls[q].c);
    std::vector<double> clear(balls.size());
#pragma omp parallel for schedule(dynamic, 1)
    for (int q = 0; q < int(balls.size()); ++q) clear[std::size_t(q)] = clearance(centres[std::size_t(q)]);
    std::map<std::array<double, 3>, double> known;
    for (std::size_t q = 0; q < balls.size(); ++q)
        known.emplace(std::array<double, 3>{centres[q].x(), centres[q].y(), centres[q].z()}, clear[q]);
    const Clearance clearanceAtCentres = [&known, &clearance](const Vec3& c) {
        const auto it = known.find({c.x(), c.y(), c.z()});
        return it != known.end() ? it->second : clearance(c);
    };
    const auto finalBound =
        bound ? withNeighbours(radiusBound(clearanceAtCentres, H, opt.planes), near, H, share) : bound;
    for (std::size_t q = 0; q < balls.size(); ++q) {
        const Vec3& c = centres[q];
        double radius = balls[q].r * h;
        if (finalBound) { // final clipping in world units: the guarantee does not rest on the voxel maths
            const double limit = finalBound(c);
            if (limit < radius) {
                // counted when more than rounding (a voxel-unit radius at its limit, scaled back to world
                // units, lands an ulp or so either side of it)
                if (radius - limit > 1e-9 * h) ++m.clipped;
                radius = limit;
            }
        }
        if (radius >= rMin) r.spheres.add(c, radius);
    }
    if (r.spheres.size() == 0) oneSphereOfItsVolume(S, E, finalBound, rMin, r.spheres, m);
    if (r.spheres.size() == 0) noSphereLeft(E, opt);
    const double inscribed = h * *std::max_element(E.data.begin(), E.data.end());
    if (!opt.contacts.empty()) reachContacts(r.spheres, opt, S, E, clearance, H, near, m);
    m.protrusion = largestProtrusion(r.spheres, clearanceAtCentres);
    m.smallestRadius = *std::min_element(r.spheres.radii.begin(), r.spheres.radii.end());
    m.inscribedRadius = inscribed;
    const Mismatch mm = mismatch(S, r.spheres);
    m.spheres = r.spheres.size();
    m.eta = mm.eta;
    m.dice = mm.dice;
    m.solidVoxels = mm.target;
    m.sphereVoxels = mm.approx;
    m.secondsTotal = secondsSince(start);
    r.metrics = m;
    return r;
}

} // namespace

void validateOptions(const GenerateOptions& o) {
    // the ranges of the option table (mss/options.hpp), with its messages
    auto check = [](const char* name, const OptionValue& v) {
        try {
            checkOption(*findOption(name, command::Generate), v);
        } catch (const OptionError& e) {
            throw OptionError("generate", e.option(), e.detail());
        }
    };
    if (o.nSpheres != 0) check("nSpheres", (long long)o.nSpheres); // 0: no limit
    check("eta", o.eta);
    check("dice", o.dice);
    check("rMin", o.rMin);
    check("rMinVoxels", o.rMinVoxels);
    check("neighbourProtrusion", o.neighbourProtrusion);
    check("maxIterations", (long long)o.maxIterations);
    check("deltaMin", o.deltaMin);
    check("maxWork", o.maxWork);
    // more threads than libgomp can start end in "Thread creation failed" (2000) or overflow its stacks
    check("threads", (long long)o.threads);
    if (o.maxProtrusion) check("maxProtrusion", *o.maxProtrusion);
    if (o.clip && o.maxProtrusion && *o.maxProtrusion != 0.0)
        throw OptionError("generate", "clip", " means maxProtrusion 0: give one of them");
    check("planes", o.planes);
    for (const ContactPoint& c : o.contacts)
        if (!c.point.allFinite() || !c.inward.allFinite() || !(c.inward.norm() > 0))
            throw std::invalid_argument(
                "generate: a contact point needs a finite point and a non-zero normal");
    if (o.nSpheres == 0 && o.eta == 0.0 && o.dice == 0.0 && o.rMin == 0.0 && o.rMinVoxels == 0.0)
        throw std::invalid_argument(
            "generate: give at least one termination criterion (nSpheres, eta, dice, rMin or rMinVoxels)");
}

double protrusionLimit(const GenerateOptions& o, double h) {
    return o.clip ? 0.0 : o.maxProtrusion.value_or(h);
}

// Departures from the paper in Method::Optimized, and why:
// - Under a sphere budget MSS takes maxima by value, and a discretised ridge (an elongated grain) gives
// dozens
//   of near-equal maxima next to each other: the budget goes to near-duplicates. Instead each candidate is
//   scored by the exact mismatch it removes given the spheres already placed (a greedy set cover with a
//   penalty for covering background), lazily re-evaluated.
// - The candidates are MSS's maxima of E plus a sampling of the medial surface of E (engine/candidates.cpp:
//   voxels where E has no face neighbour more than half a voxel higher or |grad E| < 0.9, thinned to 10,000
//   by a hash of the position), since the maxima alone are often fewer than the budget and poorly placed for
//   it. E* = 2E - Ẽ (eq. 25) is not needed: the exact gain already measures what a candidate adds beyond the
//   current union.
// - Centres and radii are then tuned by coordinate descent on the voxel mismatch (moves: a centre coordinate,
//   the radius, or a centre coordinate with the radius following E, so a ball can slide along the surface).
//   Radii may exceed the clearance by the discretisation the paper accepts (section 3.5), one voxel, and no
//   more (GenerateOptions::maxProtrusion): without that bound the mismatch is lowest with bumps of several
//   voxels (femur 70: 4.4 voxels, 53 of the 70 spheres beyond one voxel; a cube: 6).
// - Problem (ii) (a quality target): the budget grows in steps with refinement in between (growToTarget in
//   engine/optimized.cpp), since a greedy run to the target overshoots the count a refined set needs.
// - Mirror planes of the voxelised grain through the grid centre are detected; candidates are placed with
//   their mirror images so the sphere set keeps the grain's symmetry (paper section 4.2 values this).
Result generate(const VoxelGrid& volume, const GenerateOptions& options) {
    validateOptions(options);
    const OmpScope omp(options.threads);
    const BigBlockReuse reuse; // the optimiser's runs under a bound reuse each other's coverage blocks
    const auto start = Clock::now();
    Metrics m;
    const VoxelGrid S = padVoxels(volume, 2); // eq. 6
    return generateOnGrid(S, options, m, start);
}

Result generate(const TriangleMesh& mesh, const Resolution& resolution, const GenerateOptions& options,
                int supersample) {
    validateOptions(options);
    const OmpScope omp(options.threads);
    const BigBlockReuse reuse; // the optimiser's runs under a bound reuse each other's coverage blocks
    const auto start = Clock::now();
    Metrics m;
    auto t0 = Clock::now();
    const VoxelGrid S = voxelizeMesh(mesh, resolution, supersample, &m.warnings, options.maxWork);
    m.secondsVoxelize = secondsSince(t0);
    if (countSolid(S) == 0)
        throw std::invalid_argument(
            "generate: the mesh voxelises to no solid voxel (open mesh or too coarse a "
            "resolution?)");
    // The clearance (paper section 3.5, with the exact distance to the surface instead of the nearest
    // vertex): distance from the centre to the nearest point of any triangle (CGAL AABB tree), positive
    // inside. Inside: the voxel centre nearest to c when the surface is farther from c than that centre (same
    // side), else the generalised winding number.
    const auto query = std::make_shared<MeshQuery>(mesh);
    auto centres = std::make_shared<VoxelGrid>();
    if (supersample != 1) *centres = voxelizeMesh(mesh, S.spec, 1);
    const VoxelGrid& inside = supersample != 1 ? *centres : S;
    const Clearance clearance = [query, centres, &inside, spec = S.spec](const Vec3& c) {
        const double dist = query->distance(c);
        const auto v = spec.voxelOf(c);
        bool in;
        if (spec.contains(v[0], v[1], v[2]) && dist > (c - spec.voxelCenter(v[0], v[1], v[2])).norm())
            in = inside(v[0], v[1], v[2]) != 0;
        else
            in = query->inside(c);
        return in ? dist : -dist;
    };
    // inside and farther than t from the surface: as the clearance decides inside from the voxel where the
    // surface is farther than the voxel's centre
    const ClearanceAbove above = [query, centres, &inside, spec = S.spec](const Vec3& c, double t) {
        const auto v = spec.voxelOf(c);
        if (!spec.contains(v[0], v[1], v[2]) || !inside(v[0], v[1], v[2])) return false;
        return query->fartherThan(c, std::max(t, (c - spec.voxelCenter(v[0], v[1], v[2])).norm()));
    };
    return generateOnGrid(S, options, m, start, clearance, above);
}

} // namespace mss
