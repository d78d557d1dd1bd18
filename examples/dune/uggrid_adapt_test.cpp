// When one UGGrid<3> adapt() goes wrong, and bpm::dune::adapt_uggrid avoiding it
// (bpm/dune/uggrid_adapt.h says why). On the unit cube cut into 2 x 2 x 2 cubes of 6
// tetrahedra each (48), after one tetrahedron T0 was refined (red, its neighbours green):
//   - pairs (a, R): a an irregular child of a green-refined level-0 tetrahedron F, R a
//     regular child of T0 sharing an edge with a child of F. One adapt() with marks on a
//     and R (UG refines F red, and R red, which gives a child of F a closure mark) can abort
//     in UG's DisposeDoubledSideVector or leave a grid that is not conforming (when F's
//     neighbours' closure misses an edge midpoint of F's red refinement). Fails when no
//     pair goes wrong (then UG changed, and uggrid_adapt.h's rule is no longer UG's);
//   - for every pair that goes wrong: a alone and R alone refine correctly (both marks
//     are needed), and adapt_uggrid with a and R (two adapt() calls) refines correctly;
//   - random marks (10 % of the leaves per step, 4 steps, 3 seeds) with adapt_uggrid
//     refine correctly at every step.
// "Correctly": the process survives, every leaf face is shared by two leaves or lies on the
// cube's boundary (no hanging or mismatched faces), and the leaves fill the cube (volume 1).
// Every plain adapt() that may abort runs in a forked child.
//
// Usage: uggrid_adapt_test (exit 0: all checks passed)

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <random>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include <dune/common/parallel/mpihelper.hh>
#include <dune/grid/common/gridfactory.hh>
#include <dune/grid/uggrid.hh>

#include "bpm/dune/uggrid_adapt.h"

namespace {

using Grid = Dune::UGGrid<3>;
using Element = bpm::dune::UGGrid3Element;

std::unique_ptr<Grid> cube_grid() {
    const int n = 2;
    Dune::GridFactory<Grid> factory;
    auto id = [](int i, int j, int k) { return static_cast<unsigned>((i * (n + 1) + j) * (n + 1) + k); };
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j)
            for (int k = 0; k <= n; ++k) factory.insertVertex({double(i) / n, double(j) / n, double(k) / n});
    // Each cube: the 6 tetrahedra along its diagonal from (i, j, k) to (i+1, j+1, k+1), one
    // per order of the axes to step along; positively oriented.
    const int orders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            for (int k = 0; k < n; ++k)
                for (const auto& order : orders) {
                    std::array<int, 3> c{i, j, k};
                    std::vector<unsigned> tet{id(c[0], c[1], c[2])};
                    std::array<std::array<int, 3>, 3> steps{};
                    for (int s = 0; s < 3; ++s) {
                        ++c[order[s]];
                        steps[s] = {0, 0, 0};
                        steps[s][order[s]] = 1;
                        tet.push_back(id(c[0], c[1], c[2]));
                    }
                    // det of the three unit steps (a permutation matrix): its sign.
                    const int det = steps[0][0] * (steps[1][1] * steps[2][2] - steps[1][2] * steps[2][1]) -
                                    steps[0][1] * (steps[1][0] * steps[2][2] - steps[1][2] * steps[2][0]) +
                                    steps[0][2] * (steps[1][0] * steps[2][1] - steps[1][1] * steps[2][0]);
                    if (det < 0) std::swap(tet[2], tet[3]);
                    factory.insertElement(Dune::GeometryTypes::tetrahedron, tet);
                }
    return factory.createGrid();
}

// The leaves fill the unit cube conformingly: every face of a leaf is a face of exactly
// one other leaf, or lies on the cube's boundary; the volumes sum to 1.
bool conforming_cube(const Grid& grid, std::string& why) {
    const auto view = grid.leafGridView();
    const auto& index = view.indexSet();
    std::vector<Dune::FieldVector<double, 3>> x(static_cast<size_t>(view.size(3)));
    for (const auto& v : vertices(view)) x[index.index(v)] = v.geometry().corner(0);
    std::map<std::array<size_t, 3>, int> faces;
    double volume = 0;
    for (const auto& e : elements(view)) {
        volume += e.geometry().volume();
        std::array<size_t, 4> c;
        for (int i = 0; i < 4; ++i) c[i] = index.subIndex(e, i, 3);
        for (int skip = 0; skip < 4; ++skip) {
            std::array<size_t, 3> f;
            int k = 0;
            for (int i = 0; i < 4; ++i)
                if (i != skip) f[k++] = c[i];
            std::sort(f.begin(), f.end());
            ++faces[f];
        }
    }
    for (const auto& [f, count] : faces) {
        if (count > 2) {
            why = "a face of more than two leaves";
            return false;
        }
        if (count == 2) continue;
        bool on_boundary = false;
        for (int axis = 0; axis < 3 && !on_boundary; ++axis)
            for (double side : {0.0, 1.0})
                if (x[f[0]][axis] == side && x[f[1]][axis] == side && x[f[2]][axis] == side) on_boundary = true;
        if (!on_boundary) {
            why = "an interior face of only one leaf (hanging or mismatched)";
            return false;
        }
    }
    if (std::abs(volume - 1) > 1e-12) {
        why = "the leaves' volume is not 1";
        return false;
    }
    return true;
}

// Runs `adapt` (which refines `grid` and returns 0 if the result is right, 1 if not) in a
// forked child with stderr silenced (UG's and Open MPI's messages), so that UG's assertion
// cannot end the test: 0 or 1 as `adapt` returned, 2 = the child died.
template <class Adapt>
int adapt_in_child(Adapt adapt) {
    std::cout.flush();
    std::cerr.flush();
    const pid_t pid = fork();
    if (pid < 0) {
        std::perror("fork");
        std::exit(2);
    }
    if (pid == 0) {
        if (!std::freopen("/dev/null", "w", stderr)) _exit(3);
        _exit(adapt());
    }
    int status = 0;
    if (waitpid(pid, &status, 0) != pid) return 2;
    if (WIFEXITED(status) && WEXITSTATUS(status) <= 1) return WEXITSTATUS(status);
    return 2;
}

// One plain adapt() of `marks` in a forked child: 0 = correct, 1 = not conforming,
// 2 = the child died (UG's assertion).
int plain_adapt_in_child(Grid& grid, const std::vector<Element>& marks) {
    return adapt_in_child([&] {
        for (const auto& e : marks) grid.mark(1, e);
        grid.preAdapt();
        grid.adapt();
        grid.postAdapt();
        std::string why;
        return conforming_cube(grid, why) ? 0 : 1;
    });
}

// adapt_uggrid of `marks` in a forked child: true if it refines correctly.
bool adapt_uggrid_in_child(Grid& grid, const std::vector<Element>& marks) {
    return adapt_in_child([&] {
               const bpm::dune::UGGridAdaptResult result = bpm::dune::adapt_uggrid(grid, marks, [] {});
               std::string why;
               return result.adapts == 2 && conforming_cube(grid, why) ? 0 : 1;
           }) == 0;
}

bool share_edge(const Element& a, const Element& b) {
    int shared = 0;
    const auto ga = a.geometry(), gb = b.geometry();
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            if (ga.corner(i) == gb.corner(j)) ++shared;
    return shared >= 2;
}

int failures = 0;
void check(bool ok, const std::string& what) {
    std::cout << (ok ? "ok   " : "FAIL ") << what << "\n";
    if (!ok) ++failures;
}

}  // namespace

int main(int argc, char** argv) {
    Dune::MPIHelper::instance(argc, argv);
    auto grid = cube_grid();
    std::string why;
    check(conforming_cube(*grid, why), "the cube's 48 tetrahedra are conforming");

    // T0: the first level-0 tetrahedron with no face on the boundary, if any, else the first.
    Element t0 = *elements(grid->leafGridView()).begin();
    for (const auto& e : elements(grid->leafGridView()))
        if (!e.hasBoundaryIntersections()) {
            t0 = e;
            break;
        }
    grid->mark(1, t0);
    grid->preAdapt();
    grid->adapt();
    grid->postAdapt();
    check(conforming_cube(*grid, why), "after refining one tetrahedron: conforming");

    // The pairs (a, R) of the rule.
    const auto view = grid->leafGridView();
    std::vector<std::pair<Element, Element>> pairs;
    for (const auto& a : elements(view)) {
        if (a.isRegular() || a.level() != 1) continue;
        const auto f = a.father();
        for (const auto& r : elements(view)) {
            if (!r.isRegular() || r.level() != 1) continue;
            bool touches = false;
            for (const auto& child : descendantElements(f, 1))
                if (share_edge(child, r)) touches = true;
            if (touches) pairs.emplace_back(a, r);
        }
    }
    std::cout << pairs.size() << " pairs (a irregular child of a green-refined F, R regular level-1 leaf next to F's children)\n";
    check(!pairs.empty(), "the cube has such pairs");
    int broken = 0, alone_ok = 0, grouped_ok = 0;
    for (const auto& [a, r] : pairs) {
        if (plain_adapt_in_child(*grid, {a, r}) == 0) continue;
        ++broken;
        alone_ok += plain_adapt_in_child(*grid, {a}) == 0 && plain_adapt_in_child(*grid, {r}) == 0;
        grouped_ok += adapt_uggrid_in_child(*grid, {a, r});
    }
    std::cout << "one adapt() of {a, R}: " << broken << " of " << pairs.size() << " pairs abort or leave a broken grid\n";
    check(broken > 0, "UG 2.9: one adapt() of some pairs {a, R} goes wrong");
    check(alone_ok == broken, "for each of those, one adapt() of a alone, and of R alone, refines correctly");
    check(grouped_ok == broken, "for each of those, adapt_uggrid (two adapt() calls) refines correctly");

    for (unsigned seed = 0; seed < 3; ++seed) {
        auto g = cube_grid();
        std::mt19937 rng(seed);
        std::bernoulli_distribution coin(0.1);
        bool ok = true;
        int adapts = 0;
        for (int step = 1; step <= 4 && ok; ++step) {
            std::vector<Element> marks;
            for (const auto& e : elements(g->leafGridView()))
                if (coin(rng)) marks.push_back(e);
            adapts += bpm::dune::adapt_uggrid(*g, marks, [] {}).adapts;
            ok = conforming_cube(*g, why);
        }
        check(ok, "random marks, seed " + std::to_string(seed) + ": " + std::to_string(g->leafGridView().size(0)) +
                      " leaves after 4 steps in " + std::to_string(adapts) + " adapt() calls, conforming at every step " + why);
    }
    return failures ? 1 : 0;
}
