// check_quality: the triangle-shape gates of bpm-check (--max-aspect, --min-angle) on
// the coarse surface. Aspect ratio is R/r as in the paper (§2.2.2), 2 for equilateral.
#include <algorithm>
#include <cmath>

#include "bpm/check.h"
#include "check/check_internal.h"

namespace bpm {

namespace {
// Smallest interior angle in degrees, computed with atan2 for accuracy at tiny angles.
double min_angle_degrees(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 p[3] = {a, b, c};
    double smallest = 180.0;
    for (int i = 0; i < 3; ++i) {
        const Vec3 u = p[(i + 1) % 3] - p[i], v = p[(i + 2) % 3] - p[i];
        const double angle = std::atan2(norm(cross(u, v)), dot(u, v)) * 180.0 / M_PI;
        smallest = std::min(smallest, angle);
    }
    return smallest;
}
}  // namespace

CheckResult check_quality(const Surface& surface, const CheckOptions& options, const Context& context) {
    CheckResult r;
    r.name = "quality";
    r.add_count("triangles", surface.num_triangles());
    if (auto why = detail::surface_unsafe(surface)) {
        detail::refuse(r, *why);
        return r;
    }
    (void)context;
    double worst_aspect = 0.0, worst_angle = 180.0;
    int32_t worst_aspect_t = -1, worst_angle_t = -1;
    int64_t aspect_violations = 0, angle_violations = 0;
    for (int32_t t = 0; t < surface.num_triangles(); ++t) {
        const Tri& tri = surface.triangles[t];
        const Vec3 &a = surface.vertices[tri[0]], &b = surface.vertices[tri[1]], &c = surface.vertices[tri[2]];
        const double aspect = aspect_ratio(a, b, c);
        const double angle = min_angle_degrees(a, b, c);
        if (worst_aspect_t < 0 || !(aspect <= worst_aspect)) {
            worst_aspect = aspect;
            worst_aspect_t = t;
        }
        if (worst_angle_t < 0 || angle < worst_angle) {
            worst_angle = angle;
            worst_angle_t = t;
        }
        if (options.max_aspect_ratio && !(aspect <= *options.max_aspect_ratio)) {
            ++aspect_violations;
            r.add_problem({{{"triangle", t}}, "aspect ratio " + detail::format_number(aspect) + " exceeds " +
                                                  detail::format_number(*options.max_aspect_ratio)},
                          options.max_problems);
        }
        if (options.min_angle_degrees && !(angle >= *options.min_angle_degrees)) {
            ++angle_violations;
            r.add_problem({{{"triangle", t}}, "smallest angle " + detail::format_number(angle) + " degrees is below " +
                                                  detail::format_number(*options.min_angle_degrees)},
                          options.max_problems);
        }
    }
    r.add_count("aspect_violations", aspect_violations);
    r.add_count("angle_violations", angle_violations);
    if (surface.num_triangles() == 0) {
        r.summary = "no triangles";
        return r;
    }
    if (options.min_angle_degrees && !options.max_aspect_ratio)
        r.worst = WorstValue{"min_angle_degrees", worst_angle, {{"triangle", worst_angle_t}}};
    else
        r.worst = WorstValue{"aspect_ratio", worst_aspect, {{"triangle", worst_aspect_t}}};
    r.summary = std::to_string(surface.num_triangles()) + " triangles, worst aspect ratio " +
                detail::format_number(worst_aspect) + ", smallest angle " + detail::format_number(worst_angle) + " degrees";
    return r;
}

}  // namespace bpm
