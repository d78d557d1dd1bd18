#pragma once
// Benchmark metrics for bpm-bench-metrics (bench/README.md): sampled two-sided surface
// distances and a tiny reader for the ASCII .vtu grids that psurface-simplify writes.
// Not part of libbpm; CGAL stays inside metrics_distance.cpp.

#include <cstdint>
#include <string>

#include "bpm/surface.h"

namespace bpm::bench {

struct SamplingOptions {
    // Random points on a sampled surface: every triangle gets
    // max(min_per_triangle, round(area_samples * area / total area)) points, uniformly
    // distributed in the triangle. All vertices and all edge midpoints are sampled too.
    int64_t area_samples = 500000;
    int32_t min_per_triangle = 3;
    uint64_t seed = 1;  // std::mt19937_64 seed; the same seed gives the same samples
};

// Distances from sample points of a surface `from` to the surface `to` (closest point
// on any triangle of `to`, exact in double precision via a CGAL AABB tree).
struct OneSidedDistance {
    int64_t samples = 0;        // vertices + edge midpoints + random points
    double max = 0.0;           // absolute, in model units
    double mean = 0.0;
    double rms = 0.0;
    // 99th and 99.9th percentile of the sample distances: the bulk of the surface, without
    // the few farthest points that decide `max` (a sharp kink or a fold of S0 can hold the
    // maximum while everything else converges).
    double p99 = 0.0;
    double p999 = 0.0;
    // The sample point where the maximum was found.
    Vec3 max_at{0.0, 0.0, 0.0};
    // A triangle of `from` that contains that sample point (for diagnostics).
    int32_t max_triangle = -1;
};

struct DistanceReport {
    OneSidedDistance original_to_coarse;  // samples on the original, distance to the coarse surface
    OneSidedDistance coarse_to_original;  // samples on the coarse surface, distance to the original
    double hausdorff = 0.0;               // max of both maxima
};

DistanceReport compute_distances(const Surface& original, const Surface& coarse, const SamplingOptions& options);

// Reads the ASCII UnstructuredGrid .vtu written by psurface-simplify (Points + Cells with
// connectivity/offsets/types). Triangles only (VTK type 5); other cells are an error.
// Vertices no triangle uses are dropped (with a count in `dropped_vertices`). Patches are
// set to 0, like an OFF file's. Throws bpm::InputError.
Surface read_vtu(const std::string& path, int64_t* dropped_vertices = nullptr);

}  // namespace bpm::bench
