// check_intersections: no two triangles of a surface meet other than in a shared
// vertex or a shared edge. Candidate pairs come from CGAL's box_self_intersection_d
// (closed boxes, so touching triangles are candidates too); every candidate is decided
// by the exact predicate triangles_intersect_improperly with the shared-corner mapping.
#include <CGAL/box_intersection_d.h>
#include <sys/mman.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <new>
#include <set>

#include "bpm/check.h"
#include "bpm/predicates.h"
#include "check/check_internal.h"
#include "check/improper_pair.h"

namespace bpm {

namespace {
// A triangle's bounding box in float, with the triangle's index as the box's id: 28
// bytes instead of CGAL's Box_with_info_d<double, 3, int32_t> (64 bytes with its explicit
// id), which halves the memory the box intersection sorts and scans (measured on
// armadillo + 1x Loop, 208k triangles, the box part alone: 0.25 -> 0.17 CPU s).
// Rounding to the nearest float and clamping are monotone, so two boxes that touch or
// overlap in double still do in float: the candidates are a superset of the exact ones
// (a few more pairs, decided by the same exact predicates).
struct Box {
    using NT = float;
    using ID = int32_t;
    float lo[3], hi[3];
    int32_t triangle;
    static int dimension() { return 3; }
    int32_t id() const { return triangle; }
    float min_coord(int d) const { return lo[d]; }
    float max_coord(int d) const { return hi[d]; }
    // CGAL's segment tree uses +-FLT_MAX as sentinels: stay inside them.
    static float to_float(double x) {
        constexpr double limit = double(std::numeric_limits<float>::max()) / 2;
        return float(std::clamp(x, -limit, limit));
    }
};

// The two box arrays come straight from mmap. Freed through malloc, blocks of 128 kB to
// 32 MB raise glibc's dynamic mmap threshold to their size; the simplifier's and the
// writer's large blocks that follow then come from the heap and stay resident: with the
// 28-byte boxes, bpm-simplify on the 832k-triangle armadillo + 2x Loop peaked at 536
// instead of 501 MB (both 497 MB with a fixed MALLOC_MMAP_THRESHOLD_; 505 MB with this
// allocator, the rest being the writer's larger image).
template <class T>
struct PageAllocator {
    using value_type = T;
    PageAllocator() = default;
    template <class U>
    PageAllocator(const PageAllocator<U>&) {}
    T* allocate(size_t n) {
        if (n == 0) return nullptr;
        void* p = mmap(nullptr, n * sizeof(T), PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (p == MAP_FAILED) throw std::bad_alloc();
        return static_cast<T*>(p);
    }
    void deallocate(T* p, size_t n) {
        if (p) munmap(p, n * sizeof(T));
    }
    friend bool operator==(const PageAllocator&, const PageAllocator&) { return true; }
    friend bool operator!=(const PageAllocator&, const PageAllocator&) { return false; }
};
using Boxes = std::vector<Box, PageAllocator<Box>>;

}  // namespace

CheckResult check_intersections(const Surface& surface, const CheckOptions& options, const Context& context,
                                const std::string& name) {
    CheckResult r;
    r.name = name;
    r.add_count("triangles", surface.num_triangles());
    if (auto why = detail::surface_unsafe(surface)) {
        detail::refuse(r, *why);
        return r;
    }
    context.report(0.0, "checking self-intersections");
    const int32_t nt = surface.num_triangles();
    const auto& V = surface.vertices;
    const auto& T = surface.triangles;

    // Degenerate triangles (repeated corner or collinear corners) intersect every
    // neighbour by the predicate's convention; report them once and leave them out.
    std::vector<uint8_t> degenerate(nt, 0);
    int64_t degenerate_count = 0;
    Boxes boxes;
    boxes.reserve(nt);
    for (int32_t t = 0; t < nt; ++t) {
        const Tri& tri = T[t];
        const bool repeated = tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2];
        if (repeated || collinear3d(V[tri[0]], V[tri[1]], V[tri[2]])) {
            degenerate[t] = 1;
            ++degenerate_count;
            r.add_problem({{{"triangle", t}}, repeated ? "repeated corner" : "degenerate (collinear corners, zero area)"},
                          options.max_problems);
            continue;
        }
        Box& box = boxes.emplace_back();
        for (int d = 0; d < 3; ++d) {
            box.lo[d] = Box::to_float(std::min({V[tri[0]][d], V[tri[1]][d], V[tri[2]][d]}));
            box.hi[d] = Box::to_float(std::max({V[tri[0]][d], V[tri[1]][d], V[tri[2]][d]}));
        }
        box.triangle = t;
    }

    // Keep the smallest pairs (by index) so the reported ones do not depend on the
    // order in which the box intersection enumerates candidates.
    int64_t candidates = 0, intersecting = 0;
    std::set<std::pair<int32_t, int32_t>> first_pairs;
    const size_t keep = options.max_problems;
    auto callback = [&](const Box& ba, const Box& bb) {
        ++candidates;
        int32_t ta = ba.triangle, tb = bb.triangle;
        if (ta > tb) std::swap(ta, tb);
        // Degenerate triangles have no box (above).
        if (!detail::surface_triangles_meet_improperly(V, T[ta], T[tb])) return;
        ++intersecting;
        first_pairs.insert({ta, tb});
        if (first_pairs.size() > keep) first_pairs.erase(std::prev(first_pairs.end()));
    };
    // A larger cutoff than CGAL's default (10) lets the segment tree stop splitting
    // earlier; measured 2.5x faster on a million triangles.
    // What CGAL::box_self_intersection_d does (the second range is a copy: the two are
    // sorted independently), with the copy from PageAllocator too.
    Boxes copy(boxes.begin(), boxes.end());
    CGAL::box_intersection_d<CGAL::Sequential_tag>(boxes.begin(), boxes.end(), copy.begin(), copy.end(), callback,
                                                   std::ptrdiff_t(2000), CGAL::Box_intersection_d::CLOSED,
                                                   CGAL::Box_intersection_d::COMPLETE);

    for (auto [ta, tb] : first_pairs) {
        const Tri& A = T[ta];
        const Tri& B = T[tb];
        int count = 0;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) count += A[i] == B[j];
        const std::string how = count == 0   ? "the triangles intersect"
                                : count == 1 ? "the triangles share a vertex and also meet elsewhere"
                                : count == 2 ? "the triangles share an edge and overlap (coplanar fold)"
                                             : "the triangles have the same three vertices";
        if (r.problems.size() < keep) r.problems.push_back({{{"triangle", ta}, {"other_triangle", tb}}, how});
    }
    // Degenerate triangles are listed first, then the pairs in index order.
    r.problem_count = degenerate_count + intersecting;
    r.passed = r.problem_count == 0;
    r.add_count("candidate_pairs", candidates);
    r.add_count("intersecting_pairs", intersecting);
    r.add_count("degenerate_triangles", degenerate_count);
    r.summary = std::to_string(nt) + " triangles, " + std::to_string(intersecting) + " intersecting pairs";
    if (degenerate_count) r.summary += ", " + std::to_string(degenerate_count) + " degenerate triangles";
    context.report(1.0, "checking self-intersections");
    return r;
}

}  // namespace bpm
