// Self-intersections of a mesh (mss info): pairs of triangles that cross without sharing a vertex, through an
// AABB tree with exact predicates, the work bounded by the triangle-triangle tests it makes.
#include "mss/core/mesh_query.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <array>
#include <stdexcept>
#include <vector>

namespace mss {

namespace {
/// CGAL's listing traversal (all_intersected_primitives) with a budget on the triangle-triangle tests: a
/// query that meets many boxes but few triangles (triangles stacked in parallel tilted planes, whose boxes
/// all overlap) costs its tests, not its hits, so the tests are what the budget counts. Exact predicates
/// here: the layers of a mesh's coplanar neighbours (a flat face cut into triangles) are where rounding would
/// call two disjoint triangles crossing (Simple_cartesian counted 8 such pairs among 100 flat layers of 5).
using EK = CGAL::Exact_predicates_inexact_constructions_kernel;
using ExactTri = EK::Triangle_3;
using ExactTree = CGAL::AABB_tree<
    CGAL::AABB_traits<EK, CGAL::AABB_triangle_primitive<EK, std::vector<ExactTri>::const_iterator>>>;

class BudgetedListing {
public:
    using Traits = ExactTree::AABB_traits;
    using Primitive = Traits::Primitive;
    using Node = CGAL::AABB_node<Traits>;

    BudgetedListing(std::vector<ExactTree::Primitive_id>& out, const Traits& traits, std::size_t& tests,
                    std::size_t budget)
        : out_(out), traits_(traits), tests_(tests), budget_(budget) {}
    bool go_further() const { return tests_ <= budget_; }
    void intersection(const ExactTri& query, const Primitive& p) {
        ++tests_;
        if (traits_.do_intersect_object()(query, p)) out_.push_back(p.id());
    }
    bool do_intersect(const ExactTri& query, const Node& node) const {
        return traits_.do_intersect_object()(query, node.bbox());
    }

private:
    std::vector<ExactTree::Primitive_id>& out_;
    const Traits& traits_;
    std::size_t& tests_;
    std::size_t budget_;
};

} // namespace

std::size_t countSelfIntersections(const TriangleMesh& mesh, std::size_t limit) {
    validateMesh(mesh, "countSelfIntersections");
    std::vector<ExactTri> tris;
    std::vector<std::array<int, 3>> ids;
    for (const auto& t : mesh.triangles) {
        const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
        if ((b - a).cross(c - a).squaredNorm() == 0.0) continue;
        tris.emplace_back(EK::Point_3(a.x(), a.y(), a.z()), EK::Point_3(b.x(), b.y(), b.z()),
                          EK::Point_3(c.x(), c.y(), c.z()));
        ids.push_back(t);
    }
    ExactTree tree(tris.begin(), tris.end());
    // the triangle-triangle tests, hits or not: a few seconds of them at most
    constexpr std::size_t kMaxTests = 20000000;
    std::size_t count = 0, tests = 0;
    std::vector<ExactTree::Primitive_id> hits;
    for (std::size_t i = 0; i < tris.size() && count < limit; ++i) {
        hits.clear();
        BudgetedListing listing(hits, tree.traits(), tests, kMaxTests);
        tree.traversal(tris[i], listing);
        if (tests > kMaxTests)
            throw std::invalid_argument(
                "countSelfIntersections: over 20000000 tests of triangles whose boxes "
                "overlap (triangles piled on each other: repeated faces, or layers "
                "stacked closer than their size?); not counted");
        for (const auto& h : hits) {
            const std::size_t j = static_cast<std::size_t>(h - tris.begin());
            if (j <= i) continue;
            bool shared = false;
            for (int a : ids[i])
                for (int b : ids[j]) shared = shared || a == b;
            if (!shared) ++count;
        }
    }
    return count;
}

} // namespace mss
