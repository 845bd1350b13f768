// The boundary of a union of spheres, meshed by CGAL's Skin_surface_3 (shrink factor 1: the union of balls).
#include "mss/surface.hpp"
#include "mss/mass.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polyhedron_3.h>
#include <CGAL/Skin_surface_traits_3.h>
#include <CGAL/Union_of_balls_3.h>
#include <CGAL/mesh_union_of_balls_3.h>
#include <CGAL/subdivide_union_of_balls_mesh_3.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace mss {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Traits = CGAL::Skin_surface_traits_3<Kernel>;
using Union = CGAL::Union_of_balls_3<Traits>;
using Polyhedron = CGAL::Polyhedron_3<Kernel>;

double meshVolume(const Polyhedron& p) {
    double v = 0.0;
    for (auto f = p.facets_begin(); f != p.facets_end(); ++f) {
        const auto h = f->halfedge();
        const auto& a = h->vertex()->point();
        const auto& b = h->next()->vertex()->point();
        const auto& c = h->next()->next()->vertex()->point();
        v += CGAL::to_double(CGAL::determinant(a - CGAL::ORIGIN, b - CGAL::ORIGIN, c - CGAL::ORIGIN)) / 6.0;
    }
    return v;
}

double longestEdge(const Polyhedron& p) {
    double e = 0.0;
    for (auto h = p.edges_begin(); h != p.edges_end(); ++h)
        e = std::max(e, CGAL::to_double(
                            CGAL::squared_distance(h->vertex()->point(), h->opposite()->vertex()->point())));
    return std::sqrt(e);
}

/// The frame CGAL meshes in, the same whatever the spheres' units: centred on their box and scaled so that
/// its longest edge is 100. In the spheres' own frame the mesh depended on their units: the femur's 70
/// spheres in metres gave another triangulation than in millimetres, with 5 self-intersecting pairs in its
/// STL where the millimetres had none.
struct Frame {
    Vec3 centre;
    double scale = 1.0;

    explicit Frame(const SphereSet& spheres) {
        Vec3 lo = spheres.centers[0], hi = lo;
        for (std::size_t i = 0; i < spheres.size(); ++i) {
            lo = lo.cwiseMin(spheres.centers[i] - Vec3::Constant(spheres.radii[i]));
            hi = hi.cwiseMax(spheres.centers[i] + Vec3::Constant(spheres.radii[i]));
        }
        centre = 0.5 * (lo + hi);
        scale = 100.0 / (hi - lo).maxCoeff();
    }

    std::vector<Union::Weighted_point> balls(const SphereSet& spheres) const {
        std::vector<Union::Weighted_point> out;
        out.reserve(spheres.size());
        for (std::size_t i = 0; i < spheres.size(); ++i) {
            const Vec3 c = scale * (spheres.centers[i] - centre);
            const double r = scale * spheres.radii[i];
            out.emplace_back(Union::Bare_point(c.x(), c.y(), c.z()), r * r);
        }
        return out;
    }
};

/// CGAL's mesh back in the spheres' frame, as an indexed mesh; @p smallest gets its smallest angle (degrees).
TriangleMesh toMesh(const Polyhedron& p, const Frame& frame, double& smallest) {
    TriangleMesh mesh;
    std::map<Polyhedron::Vertex_const_handle, int> index;
    for (auto v = p.vertices_begin(); v != p.vertices_end(); ++v) {
        index[v] = int(mesh.vertices.size());
        const auto& q = v->point();
        const Vec3 x(CGAL::to_double(q.x()), CGAL::to_double(q.y()), CGAL::to_double(q.z()));
        mesh.vertices.push_back(frame.centre + x / frame.scale);
    }
    smallest = 180.0;
    for (auto f = p.facets_begin(); f != p.facets_end(); ++f) {
        const auto h = f->halfedge();
        if (h->next()->next()->next() != h)
            throw std::logic_error("unionSurface: CGAL's mesh has a facet that is not a triangle");
        const std::array<int, 3> t = {index[h->vertex()], index[h->next()->vertex()],
                                      index[h->next()->next()->vertex()]};
        mesh.triangles.push_back(t);
        for (int k = 0; k < 3; ++k) {
            const Vec3 a = mesh.vertices[std::size_t(t[std::size_t(k)])];
            const Vec3 u = mesh.vertices[std::size_t(t[std::size_t((k + 1) % 3)])] - a;
            const Vec3 w = mesh.vertices[std::size_t(t[std::size_t((k + 2) % 3)])] - a;
            smallest =
                std::min(smallest, std::atan2(u.cross(w).norm(), u.dot(w)) * 180.0 / 3.14159265358979323846);
        }
    }
    return mesh;
}

} // namespace

TriangleMesh unionSurface(const SphereSet& spheres, const SurfaceOptions& options, SurfaceReport* report) {
    validateSpheres(spheres, "unionSurface");
    if (spheres.size() == 0) throw std::invalid_argument("unionSurface: no spheres: the union is empty");
    if (!(options.tolerance > 0.0 && options.tolerance < 0.5))
        throw std::invalid_argument("unionSurface: tolerance must be in (0, 0.5), got " +
                                    std::to_string(options.tolerance));
    if (!(options.maxEdge >= 0.0) || !std::isfinite(options.maxEdge))
        throw std::invalid_argument("unionSurface: maxEdge must be >= 0 and finite, got " +
                                    std::to_string(options.maxEdge));
    if (options.maxTriangles < 1) throw std::invalid_argument("unionSurface: maxTriangles must be >= 1");
    if (!(options.maxWork > 0.0))
        throw std::invalid_argument("unionSurface: maxWork must be > 0, got " +
                                    std::to_string(options.maxWork));
    const Frame frame(spheres);
    const double scale = frame.scale, volumeScale = 1.0 / (scale * scale * scale);
    const std::vector<Union::Weighted_point> balls = frame.balls(spheres);
    // measured on a 2-core machine: 0.7 ms a sphere for the first mesh (1000 spheres 0.73 s, 10,000 6.8 s),
    // and about 15 us a triangle of the subdivisions (300 random spheres: 5 million triangles in 65 s)
    constexpr double kSecondsPerSphere = 1e-3, kSecondsPerTriangle = 1.5e-5;
    // before the first mesh, what it and its subdivisions should cost: about 90 triangles a sphere, whose
    // volume is some 10% off, then fourfold less a subdivision (measured: 93 on the femur's 300 spheres); the
    // progress line counts against the whole of it
    const int expected = std::max(0, int(std::ceil(std::log(0.1 / options.tolerance) / std::log(4.0))));
    const double expectedTriangles = 90.0 * double(spheres.size()) * std::pow(4.0, double(expected));
    std::ostringstream what;
    what.precision(3);
    what << spheres.size() << " spheres, whose mesh should need about " << expected << " subdivisions, "
         << expectedTriangles << " triangles";
    const Work expectedWork{what.str(), kSecondsPerSphere * double(spheres.size()) +
                                            kSecondsPerTriangle * expectedTriangles};
    checkWork("unionSurface", expectedWork, options.maxWork,
              "give fewer spheres or loosen the option tolerance");
    Progress progress("unionSurface", expectedWork.seconds);
    progress.update(0.0, "the first mesh");
    const Union uob(balls.begin(), balls.end());
    Polyhedron p;
    CGAL::mesh_union_of_balls_3(uob, p);
    if (p.size_of_facets() > options.maxTriangles)
        throw std::invalid_argument(
            "unionSurface: the first mesh of the union has " + std::to_string(p.size_of_facets()) +
            " triangles, more than maxTriangles (" + std::to_string(options.maxTriangles) + ")");
    const double exact = sphereUnionVolume(spheres);
    const double maxEdge = options.maxEdge * scale; // in CGAL's frame
    // Subdivision moves the new vertices onto the boundary, so the mesh's volume tends to the union's (its
    // error falls about fourfold a subdivision); the exact volume says when to stop.
    double volume = meshVolume(p) * volumeScale;
    {
        // each subdivision makes four triangles of one, falls the volume's error about fourfold and halves
        // the edges: what the bounds need is known before the first
        const double error = std::abs(exact - volume) / exact;
        int need = error > options.tolerance
                       ? int(std::ceil(std::log(error / options.tolerance) / std::log(4.0)))
                       : 0;
        const double longest = longestEdge(p);
        if (maxEdge > 0.0 && longest > maxEdge)
            need = std::max(need, int(std::ceil(std::log2(longest / maxEdge))));
        const double triangles = double(p.size_of_facets()) * std::pow(4.0, double(need));
        std::ostringstream bounds;
        bounds.precision(3);
        bounds << "the bounds (tolerance " << options.tolerance << ", maxEdge " << options.maxEdge
               << ") need about " << need << " subdivisions of " << p.size_of_facets() << " triangles, "
               << triangles << " triangles";
        if (triangles > double(options.maxTriangles))
            throw std::invalid_argument("unionSurface: " + bounds.str() + ", more than maxTriangles (" +
                                        std::to_string(options.maxTriangles) +
                                        "): loosen them or raise the option maxTriangles");
        checkWork("unionSurface", {bounds.str(), kSecondsPerTriangle * triangles * 4.0 / 3.0},
                  options.maxWork, "loosen the option tolerance or the option maxEdge");
    }
    int subdivisions = 0;
    while (std::abs(exact - volume) > options.tolerance * exact ||
           (maxEdge > 0.0 && longestEdge(p) > maxEdge)) {
        if (4 * p.size_of_facets() > options.maxTriangles) {
            std::ostringstream m;
            m << "unionSurface: the bounds (tolerance " << options.tolerance << ", maxEdge "
              << options.maxEdge << ") need more than " << options.maxTriangles
              << " triangles: loosen them or raise maxTriangles";
            throw std::invalid_argument(m.str());
        }
        progress.update(-1.0, "subdivision " + std::to_string(subdivisions + 1));
        CGAL::subdivide_union_of_balls_mesh_3(uob, p);
        ++subdivisions;
        volume = meshVolume(p) * volumeScale;
    }
    double smallest = 180.0;
    TriangleMesh mesh = toMesh(p, frame, smallest);
    if (report) {
        report->subdivisions = subdivisions;
        report->volume = volume;
        report->unionVolume = exact;
        report->longestEdge = longestEdge(p) / scale;
        report->smallestAngle = smallest;
    }
    return mesh;
}

} // namespace mss
