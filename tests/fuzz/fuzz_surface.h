#pragma once
// The body shared by the surface-reader fuzz targets (fuzz_read_<format>.cpp).
//
// Property checked for every input: read_surface_from_memory() either returns a surface
// that satisfies its contract (bpm/surface_io.h: patches.size() == triangles.size(),
// indices in range, finite coordinates, at least one triangle) or throws bpm::InputError
// naming the input with a non-empty message. Anything else (another exception, a crash,
// ASan/UBSan report, a leak, a hang, a huge allocation) is a finding. The input is read
// twice: with the default options and with all three repairs (what the tools' --merge-
// duplicate-vertices --drop-unreferenced-vertices --triangulate-polygons do). A surface that reads is also run
// through the checks bpm-check --surface runs (topology, intersections) when small.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "bpm/check.h"
#include "bpm/errors.h"
#include "bpm/surface_io.h"

namespace bpm::fuzz {

[[noreturn]] inline void fail(const char* what, const std::string& detail = "") {
    std::fprintf(stderr, "fuzz property violated: %s %s\n", what, detail.c_str());
    std::abort();
}

inline void check_surface_contract(const Surface& s) {
    if (s.triangles.empty()) fail("a surface without triangles was accepted");
    if (s.patches.size() != s.triangles.size()) fail("patches.size() != triangles.size()");
    for (const Tri& t : s.triangles)
        for (int32_t v : t)
            if (v < 0 || v >= s.num_vertices()) fail("triangle index out of range", std::to_string(v));
    for (const Vec3& p : s.vertices)
        for (double x : p)
            if (!std::isfinite(x)) fail("non-finite coordinate accepted");
}

inline int fuzz_surface_reader(const uint8_t* data, size_t size, SurfaceFormat format) {
    static const char* kName = "fuzz-input";
    const std::string bytes(reinterpret_cast<const char*>(data), size);
    for (int repair = 0; repair < 2; ++repair) {
        SurfaceReadOptions options;
        options.merge_duplicate_vertices = options.drop_unreferenced_vertices = repair == 1;
        options.triangulate_polygons = repair == 1;
        try {
            SurfaceReadReport report;
            const Surface s = read_surface_from_memory(bytes, format, kName, options, &report);
            check_surface_contract(s);
            if (report.merged_vertices < 0 || report.dropped_vertices < 0 || report.skipped_elements < 0)
                fail("negative counts in the read report");
            if (repair == 0 && s.num_triangles() <= 2000) {
                CheckSelection selection;
                CheckOptions check_options;
                check_options.max_aspect_ratio = 10;
                check_options.min_angle_degrees = 5;
                const CheckReport r = run_surface_checks(s, selection, check_options);
                (void)check_report_to_json(r);
                (void)check_report_to_text(r);
            }
        } catch (const InputError& e) {
            if (e.where() != kName) fail("InputError does not name the input", e.where());
            if (std::string(e.what()).empty()) fail("InputError without a message");
        }
    }
    return 0;
}

}  // namespace bpm::fuzz
