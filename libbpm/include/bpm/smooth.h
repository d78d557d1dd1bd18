#pragma once
// Parametrization smoothing (Krause & Sander §2.5, "edge relaxation"; Floater 2003 for
// mean value coordinates, a shape-preserving choice of weights in the sense of
// Floater 1997).
//
// phi is rearranged on the quadrangle formed by two coarse triangles that share an edge
// E: the quadrangle is unfolded isometrically into the plane (a reflex corner is moved
// along the continuation of E until the quadrangle is convex), the original vertices
// inside it (and on E) are placed by a convex-combination map whose boundary is the
// fixed outer four edges, and the result is cut along E again. The coarse surface and
// the images of all nodes never move: only where in S the original vertices sit changes.
// Sweeps over all pairs repeat until the largest move is below a tolerance.
//
// Feature lines of S0 (E runs along original edges, no edge crossings on it, and one of
// them a crease of S0: sharper than feature_angle_degrees, or on a long shallow crease
// line, crease_chain_angle_degrees) and patch borders: the
// original vertices on E only slide along E, to where the arc length of S0 along E puts
// them; the rest of both triangles is relaxed with them fixed. Left alone: pairs whose
// edge has not exactly two consistently oriented triangles (boundaries, 3 or more
// sheets), and pairs with nothing to move.
//
// An update is rejected (the pair keeps its phi) if it would make either of its two coarse
// triangles worse when refined check_levels times (a larger max aspect ratio of the
// refined triangles or a larger max |flat - phi|): the relaxation places
// the original vertices by the shape of S0 alone, blind to where the refinement samples
// phi and to how far phi(x) lies from x, and on CAD-like shapes (flat faces, creases
// inside a pair, saddles) its updates made the refined surface worse. Also rejected: an
// update by which a piece would flip or degenerate, or one that would bring a node
// nearer to a corner of its coarse triangle than 1% of the triangle unless one already
// was that near: at coarse vertices where the unfolded pairs
// are wider than the part of S0 they hold (saddles of S), the straight edges of the
// chart otherwise contract the star of S0 around the vertex into the corner, sweep
// after sweep.

#include <cstdint>
#include <map>
#include <string>

#include "bpm/context.h"
#include "bpm/parametrization.h"

namespace bpm {

// How the original vertices inside a pair are placed among their neighbours (smooth.cpp,
// star_weights). Both are shape-preserving in the sense of the paper's Definition 2.5
// (planar stars are reproduced). MeanValue: Floater's mean value coordinates (2003), the
// default: the sweeps converge (largest move ~1e-3 of an edge after 10 sweeps on the
// benchmark meshes). ShapePreserving: Floater's 1997 weights (each at most 1); measured
// on the same meshes they do not settle (moves of 3-14% of an edge after 10 sweeps)
// and give about the same 99th percentile, so they are kept only for comparison.
enum class SmoothWeights { MeanValue, ShapePreserving };

struct SmoothOptions {
    int iterations = 10;          // at most this many sweeps over all pairs
    double tolerance = 1e-3;      // stop when the largest move in a sweep is below this
                                  // fraction of the length of the pair's shared edge
    double feature_angle_degrees = 60.0;  // leave edges of S0 sharper than this alone
    // ... and the long shallow creases of S0 as bpm-simplify finds them (the same rule and
    // defaults as SimplifyOptions::crease_chain_angle_degrees and crease_chain_length), so
    // that the smoother leaves alone the feature lines the simplifier kept.
    double crease_chain_angle_degrees = 20.0;
    double crease_chain_length = 0.10;
    SmoothWeights weights = SmoothWeights::MeanValue;
    bool measure_quality = true;  // compute the refined-triangle quality before and after
    int quality_levels = 3;       // refinement level of the quality measure
    // An update is kept only if it makes neither of its two coarse triangles worse when
    // refined this many times: neither the largest aspect ratio of its refined triangles
    // nor its largest |flat - phi| (over the overlay with phi) may grow. 0 keeps every
    // valid update. A guarantee for this level only: other levels may still get worse.
    int check_levels = 3;
};

// Shape of the K-times refined surface through phi: how much phi distorts.
struct RefinedQuality {
    double max_aspect_ratio = 0.0;     // circumradius / inradius, 2 for equilateral
    double p99_aspect_ratio = 0.0;     // 99th percentile
    double mean_aspect_ratio = 0.0;
};

struct SmoothResult {
    int sweeps = 0;
    int64_t pairs = 0;             // pairs considered per sweep
    int64_t skipped = 0;           // pairs left alone in the last sweep (patch borders, features, ...)
    std::map<std::string, int64_t> skipped_reasons;  // the same, counted by reason
    int64_t updates = 0;           // accepted updates, all sweeps
    int64_t slides = 0;            // of these, updates that slid vertices along a feature line or patch border
    int64_t rejected = 0;          // updates rejected (a piece would flip, ...), all sweeps
    std::map<std::string, int64_t> rejected_reasons;  // the same, counted by reason
    double last_change = 0.0;      // largest move in the last sweep (fraction of edge length)
    RefinedQuality before, after;  // if measure_quality
    double seconds = 0.0;
};

// Refines `param` uniformly `levels` times (bpm/refine.h) and measures the triangles.
RefinedQuality refined_quality(const Parametrization& param, int levels);

// \pre `param` passes check_format and check_bijectivity; it still does afterwards.
// \throw bpm::OptionError for negative iterations or tolerance, bpm::Cancelled.
SmoothResult smooth(Parametrization& param, const SmoothOptions& options, const Context& context = {});

}  // namespace bpm
