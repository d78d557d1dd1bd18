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
// Left alone (documented limitation): pairs whose edge has not exactly two triangles,
// joins two patches, is inconsistently oriented, or lies on a feature line of S0 (no
// edge crossings on E and a dihedral angle of S0 along it above feature_angle_degrees).

#include <cstdint>
#include <map>
#include <string>

#include "bpm/context.h"
#include "bpm/parametrization.h"

namespace bpm {

struct SmoothOptions {
    int iterations = 10;          // at most this many sweeps over all pairs
    double tolerance = 1e-3;      // stop when the largest move in a sweep is below this
                                  // fraction of the length of the pair's shared edge
    double feature_angle_degrees = 60.0;  // leave edges of S0 sharper than this alone
    bool measure_quality = true;  // compute the refined-triangle quality before and after
    int quality_levels = 3;       // refinement level of the quality measure
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
    int64_t rejected = 0;          // updates rejected because a piece would flip, all sweeps
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
