#pragma once
// Ear clipping of a convex polygon whose boundary may hold collinear points (the overlay
// cells of smoothing and refinement: a piece of phi cut by a line or by a refined
// triangle). Only strictly convex ears are cut, and only when what is left still has
// positive area, so no triangle is degenerate as long as the polygon is convex; the
// caller decides what a valid ear is (its orientation test, and `emit` may refuse).
//
// The general simple-polygon clipper of the surface readers is io/polygon_triangulation.h;
// the simplifier's star retriangulation is its own (simplify/).

#include <cstddef>
#include <vector>

namespace bpm::detail {

// Cuts ears off the polygon whose corners are `corners` (counter-clockwise, indices the
// caller understands) until three are left. orient(a, b, c) is the sign (+1, 0, -1) of the
// orientation of corners a, b, c; emit(a, b, c) receives each ear in polygon order and
// returns false to stop. Returns true when three corners are left in `corners` (not
// emitted: the caller checks and emits the last triangle), false when no ear could be cut
// or emit refused one.
template <class Orient, class Emit>
bool clip_convex_ears(std::vector<int>& corners, const Orient& orient, const Emit& emit) {
    while (corners.size() > 3) {
        const size_t n = corners.size();
        bool cut = false;
        for (size_t i = 0; i < n && !cut; ++i) {
            const int a = corners[(i + n - 1) % n], b = corners[i], c = corners[(i + 1) % n];
            if (orient(a, b, c) <= 0) continue;
            // Is something left with positive area?
            bool flat = true;
            for (size_t k = 0; k < n && flat; ++k) {
                const int x = corners[k];
                if (x != a && x != b && x != c && orient(a, c, x) != 0) flat = false;
            }
            if (flat) continue;
            if (!emit(a, b, c)) return false;
            corners.erase(corners.begin() + static_cast<std::ptrdiff_t>(i));
            cut = true;
        }
        if (!cut) return false;
    }
    return true;
}

}  // namespace bpm::detail
