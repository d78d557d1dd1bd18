#pragma once
// Whether a triangle runs along an edge from a to b: one of its three corner-to-next-corner
// steps (corners in stored order, counter-clockwise seen from the front) is a -> b. Two
// triangles that share an edge are consistently oriented when they run along it in
// opposite directions.

#include <cstdint>

#include "bpm/geometry.h"

namespace bpm::detail {

inline bool runs_from(const Tri& t, int32_t a, int32_t b) {
    for (int k = 0; k < 3; ++k)
        if (t[k] == a && t[(k + 1) % 3] == b) return true;
    return false;
}

}  // namespace bpm::detail
