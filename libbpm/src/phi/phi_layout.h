#pragma once
// The structural rules of phi's layout (parametrization.h, spec/bpm-format.md), visited
// once for every caller: the .bpm reader and writer (their shared rules,
// io/bpm_file_rules.cpp) and bpm-check's format check (check_format.cpp). A layout that passes can be indexed without bounds
// checks: array sizes agree, CSR offsets are well formed, every index is in range,
// every node kind is valid and the numbers the others are computed from are finite.
//
// Value rules that go beyond index safety (barycentric coordinates non-negative and
// summing to 1, corner identities, edge parameters in range) are not here: the reader
// and bpm-check apply them with different strictness, each in its own file.
//
// Each violation is handed to a sink as a LayoutProblem naming the rule, the array at
// fault and the element; the callers turn it into their own message (a dataset path
// for the file format, element ids for bpm-check), so the wording stays theirs.

#include <cstdint>
#include <functional>

#include "bpm/parametrization.h"

namespace bpm::detail {

// The arrays of a parametrization, named as the datasets of spec/bpm-format.md.
enum class PhiArray : uint8_t {
    Vertices,   // of the surface named by LayoutProblem::surface
    Triangles,  // of that surface
    Patches,    // of that surface
    VertexOrigin,  // coarse_vertex_origin (/coarse/vertex_origin)
    NodeOffsets,
    NodeBarycentric,
    NodeImage,
    NodeKind,
    NodeOriginalVertex,
    NodeOriginalEdge,
    NodeEdgeParameter,
    PieceOffsets,
    Pieces,
    PieceOriginalTriangle,
};

// The dataset name of `array` without its group ("node_offsets", "vertices", ...).
const char* phi_array_name(PhiArray array);

enum class SurfaceRole : uint8_t { Original, Coarse, Alone };

enum class LayoutRule : uint8_t {
    NotFinite,          // array[element] (entry `component` when >= 0) is NaN or infinite
    CountMismatch,      // array has `value` rows where `limit` are expected
    OutOfRange,         // array[element] (entry `component` when >= 0) = value is not in [0, limit)
    OffsetsCount,       // offsets array has `value` entries, `limit` = #coarse triangles + 1 expected
    OffsetsStart,       // offsets[0] = value, not 0
    OffsetsDecreasing,  // offsets[element] = value is smaller than offsets[element - 1] = limit
    OffsetsEnd,         // offsets ends at `value`, but its target array has `limit` rows
    InvalidNodeKind,    // node_kind[element] = value is not 0, 1 or 2
    NotAnEdge,          // node_original_edge[element] of an edge crossing is not (u, w), 0 <= u < w < limit
};

struct LayoutProblem {
    LayoutRule rule;
    PhiArray array;
    SurfaceRole surface = SurfaceRole::Alone;  // which surface, for Vertices/Triangles/Patches
    int64_t element = -1;          // row of `array`; -1 when the rule is about the whole array
    int component = -1;            // column (coordinate or corner) of the entry at fault; -1 for the row
    int32_t coarse_triangle = -1;  // the coarse triangle whose CSR range holds `element` (pieces only)
    int64_t value = 0;             // the offending integer: an index, a count, an offset or a kind
    int64_t limit = 0;             // the expected count, the end of the valid range [0, limit), or (for
                                   // OffsetsDecreasing) the previous offset
};

// Receives each violation; returns false to stop the visit.
using LayoutSink = std::function<bool(const LayoutProblem&)>;

// Visits the layout rules of one surface in this order: finite vertex coordinates (one
// problem per vertex, naming its first non-finite coordinate), triangle corners in range,
// and, when `need_patches`, one patch id per triangle. Returns true when nothing was found.
bool visit_surface_layout(const Surface& s, SurfaceRole role, const LayoutSink& sink, bool need_patches = true);

// Visits every layout rule of `p`: both surfaces; then the counts of coarse_vertex_origin,
// of the node arrays against node_kind and of piece_original_triangle against pieces;
// then both CSR offset arrays; then, only when all of that held (so that indexing is
// safe), coarse_vertex_origin ranges, each node (kind, finite barycentric coordinates and
// image, original vertex or original edge and finite edge parameter) and each piece
// (local corners within its triangle's node range, original triangle in range).
// Returns true when nothing was found, i.e. when `p` can be indexed safely.
bool visit_phi_layout(const Parametrization& p, const LayoutSink& sink);

// Throws AlgorithmError (coordinate_range_problem's text, bpm/surface.h) when the original
// or the coarse surface of `p` lies outside the range bpm computes in: what refine, smooth
// and generate_tetmesh do first, since a .bpm written elsewhere may hold anything and
// their measures overflow there (NaN distortions, TetGen aborting) instead of failing.
void require_coordinates_in_range(const Parametrization& p);

}  // namespace bpm::detail
