// bpm-bench-refine: measurements of refinement through phi for bench/refine.py
// (bench/README.md). Three subcommands, each printing one JSON object:
//
//   shape FILE.bpm [--levels K]
//       aspect ratio R/r (max, 99th percentile, mean) of the coarse surface, of the
//       K-times uniformly refined surface through phi and of the same refinement without
//       phi ("plain": midpoints on the flat coarse triangles, whose refined triangles are
//       similar to their coarse parents, so its percentiles equal the coarse ones), and
//       the distortion factor aspect(refined) / aspect(coarse parent) per refined triangle.
//   convergence FILE.bpm [--levels 0,1,2,3,4] [--samples N] [--min-per-triangle K]
//       two-sided sampled Hausdorff distance / diagonal between the original surface and
//       the K-times refined surface, with phi and plain, for every K.
//   throughput FILE.bpm [--points N] [--threads 1,2] [--repeat R] [--seed S]
//       phi evaluations per second for N random points (uniform random coarse triangle,
//       uniform random barycentric coordinates), batched (PhiEvaluator::evaluate with
//       full PhiSample output and evaluate_positions, on the whole batch), wall and CPU
//       time (process CPU time: all threads); plus single-query loops in random and in
//       grouped order for reference. Input generation and output allocation are not timed.
//   inverse FILE.bpm [--points N] [--threads 1,2] [--repeat R] [--seed S] [--offset F]
//       inverse phi (PhiInverse) next to phi, batched, per thread count: N random parameter
//       points x (as for throughput) give y = phi(x) untimed; then, alternating within each
//       repetition, phi (PhiSample and positions only), from_original(T, beta of y),
//       from_position(y + F * diagonal * normal) with SurfacePoint and with full
//       PhiInverseSample output. Median wall and CPU seconds over R repetitions, points
//       per second and per CPU second, and the largest round-trip error |phi(phi^-1(y)) - y|
//       / diagonal of each inverse form.

#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "bpm/bpm_file.h"
#include "bpm/errors.h"
#include "bpm/phi_evaluation.h"
#include "bpm/phi_inverse.h"
#include "bpm/refine.h"
#include "common/tool_main.h"
#include "metrics.h"

namespace {

using namespace bpm;

std::string num(double v) {
    if (!std::isfinite(v)) return "null";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

struct Stats {
    double max = 0, p99 = 0, p50 = 0, mean = 0;
    int64_t count = 0, degenerate = 0;
};

// Percentiles as index floor(f * n) of the sorted values (the convention of
// bpm::refined_quality); degenerate (infinite) values count as the largest.
Stats stats(std::vector<double> v) {
    Stats s;
    s.count = int64_t(v.size());
    if (v.empty()) return s;
    std::sort(v.begin(), v.end());
    s.max = v.back();
    s.p99 = v[std::min(v.size() - 1, size_t(0.99 * double(v.size())))];
    s.p50 = v[std::min(v.size() - 1, size_t(0.5 * double(v.size())))];
    double sum = 0;
    int64_t finite = 0;
    for (double x : v) {
        if (std::isfinite(x)) sum += x, ++finite;
        else ++s.degenerate;
    }
    s.mean = finite ? sum / double(finite) : 0;
    return s;
}

std::string stats_json(const Stats& s) {
    std::ostringstream o;
    o << "{\"count\": " << s.count << ", \"max\": " << num(s.max) << ", \"p99\": " << num(s.p99)
      << ", \"p50\": " << num(s.p50) << ", \"mean\": " << num(s.mean) << ", \"degenerate\": " << s.degenerate << "}";
    return o.str();
}

std::vector<double> aspects(const Surface& s) {
    std::vector<double> a;
    a.reserve(s.triangles.size());
    for (const Tri& t : s.triangles)
        a.push_back(aspect_ratio(s.vertices[size_t(t[0])], s.vertices[size_t(t[1])], s.vertices[size_t(t[2])]));
    return a;
}

// The refined connectivity with every vertex on the flat coarse triangle (no phi).
Surface plain_surface(const Parametrization& p, const RefinedSurface& r) {
    Surface s = r.surface;
    for (size_t v = 0; v < s.vertices.size(); ++v) {
        const Tri& t = p.coarse.triangles[size_t(r.vertex_coarse_triangle[v])];
        s.vertices[v] = barycentric_point(p.coarse.vertices[size_t(t[0])], p.coarse.vertices[size_t(t[1])],
                                          p.coarse.vertices[size_t(t[2])], r.vertex_barycentric[v]);
    }
    return s;
}

RefinedSurface refine_uniform(const Parametrization& p, int levels) {
    RefinedSurface r;
    RefineOptions o;
    o.levels = levels;
    refine(p, o, Context{}, r);
    return r;
}

std::vector<int> parse_list(const std::string& text) {
    std::vector<int> out;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        if (item.empty()) continue;
        out.push_back(std::stoi(item));
    }
    return out;
}

double cpu_seconds() {
    timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

double wall_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::string shape(const Parametrization& p, int levels) {
    const std::vector<double> coarse = aspects(p.coarse);
    const RefinedSurface r = refine_uniform(p, levels);
    const std::vector<double> refined = aspects(r.surface);
    const std::vector<double> plain = aspects(plain_surface(p, r));
    std::vector<double> factor(refined.size());
    for (size_t i = 0; i < refined.size(); ++i) factor[i] = refined[i] / coarse[size_t(r.triangle_coarse[i])];
    std::ostringstream o;
    o << "{\"levels\": " << levels << ", \"coarse\": " << stats_json(stats(coarse))
      << ", \"refined\": " << stats_json(stats(refined)) << ", \"plain\": " << stats_json(stats(plain))
      << ", \"distortion\": " << stats_json(stats(factor)) << "}";
    return o.str();
}

// How phi behaves on one coarse triangle, for locating where the Hausdorff distance
// comes from: the largest angle between the coarse triangle's normal and the normal of
// a piece's image (> 90 degrees: the original surface folds back over the triangle),
// the original area phi maps into it over its own area, and the largest local area
// stretch of a piece (image area / parameter area) over that mean.
struct CoarseTriangleStats {
    double normal_deviation_degrees = 0, area_ratio = 0, max_stretch = 0;
    int64_t pieces = 0;
};

CoarseTriangleStats coarse_triangle_stats(const Parametrization& p, int32_t t) {
    CoarseTriangleStats st;
    const Tri& c = p.coarse.triangles[size_t(t)];
    const Vec3 &c0 = p.coarse.vertices[size_t(c[0])], &c1 = p.coarse.vertices[size_t(c[1])],
               &c2 = p.coarse.vertices[size_t(c[2])];
    const Vec3 n = cross(c1 - c0, c2 - c0);
    const double coarse_area = 0.5 * norm(n);
    double image_area = 0;
    std::vector<std::pair<double, double>> areas;  // (image, parameter) per piece
    const int64_t base = p.node_offsets[size_t(t)];
    for (int64_t i = p.piece_offsets[size_t(t)]; i < p.piece_offsets[size_t(t) + 1]; ++i) {
        const Tri& q = p.pieces[size_t(i)];
        const Vec3 &a = p.node_image[size_t(base + q[0])], &b = p.node_image[size_t(base + q[1])],
                   &d = p.node_image[size_t(base + q[2])];
        const Vec3 m = cross(b - a, d - a);
        const double len = norm(m) * norm(n);
        if (len > 0) {
            const double cosine = std::max(-1.0, std::min(1.0, dot(m, n) / len));
            st.normal_deviation_degrees = std::max(st.normal_deviation_degrees, std::acos(cosine) * 180.0 / M_PI);
        }
        auto param = [&](int32_t k) {
            return barycentric_point(c0, c1, c2, p.node_barycentric[size_t(base + k)]);
        };
        const double pa = triangle_area(param(q[0]), param(q[1]), param(q[2]));
        areas.push_back({0.5 * norm(m), pa});
        image_area += 0.5 * norm(m);
        ++st.pieces;
    }
    st.area_ratio = coarse_area > 0 ? image_area / coarse_area : 0;
    const double mean = coarse_area > 0 ? image_area / coarse_area : 0;
    for (const auto& [img, par] : areas)
        if (par > 0 && mean > 0) st.max_stretch = std::max(st.max_stretch, img / par / mean);
    return st;
}

std::string stats_of(const Parametrization& p, int32_t t) {
    const CoarseTriangleStats st = coarse_triangle_stats(p, t);
    std::ostringstream o;
    o << "{\"coarse_triangle\": " << t << ", \"normal_deviation_degrees\": " << num(st.normal_deviation_degrees)
      << ", \"area_ratio\": " << num(st.area_ratio) << ", \"max_stretch\": " << num(st.max_stretch)
      << ", \"pieces\": " << st.pieces << "}";
    return o.str();
}

// The coarse triangles phi maps (partly) onto original triangle T.
std::vector<int32_t> coarse_triangles_of(const Parametrization& p, int32_t original_triangle) {
    std::vector<int32_t> out;
    for (int32_t t = 0; t < p.coarse.num_triangles(); ++t)
        for (int64_t i = p.piece_offsets[size_t(t)]; i < p.piece_offsets[size_t(t) + 1]; ++i)
            if (p.piece_original_triangle[size_t(i)] == original_triangle) {
                out.push_back(t);
                break;
            }
    return out;
}

// Where the larger one-sided maximum was found: the point, and the coarse triangle(s)
// it belongs to with their CoarseTriangleStats.
std::string worst_spot(const Parametrization& p, const RefinedSurface& r, const bench::DistanceReport& d,
                       double diagonal) {
    const bool from_original = d.original_to_coarse.max >= d.coarse_to_original.max;
    const bench::OneSidedDistance& side = from_original ? d.original_to_coarse : d.coarse_to_original;
    std::vector<int32_t> coarse;
    if (side.max_triangle >= 0) {
        if (from_original) coarse = coarse_triangles_of(p, side.max_triangle);
        else coarse.push_back(r.triangle_coarse[size_t(side.max_triangle)]);
    }
    std::ostringstream o;
    o << "{\"side\": \"" << (from_original ? "original_to_refined" : "refined_to_original")
      << "\", \"distance_relative\": " << num(side.max / diagonal) << ", \"at\": [" << num(side.max_at[0]) << ", "
      << num(side.max_at[1]) << ", " << num(side.max_at[2]) << "], \"triangle\": " << side.max_triangle
      << ", \"coarse\": [";
    for (size_t i = 0; i < coarse.size(); ++i) o << (i ? ", " : "") << stats_of(p, coarse[i]);
    o << "]}";
    return o.str();
}

std::string convergence(const Parametrization& p, const std::vector<int>& levels, const bench::SamplingOptions& sampling,
                        bool diagnose) {
    const double diagonal = bounding_box_diagonal(p.original);
    std::ostringstream o;
    o << "{\"bbox_diagonal\": " << num(diagonal) << ", \"sampling\": {\"area_samples\": " << sampling.area_samples
      << ", \"min_per_triangle\": " << sampling.min_per_triangle << ", \"seed\": " << sampling.seed
      << "}, \"levels\": [";
    bool first = true;
    for (int k : levels) {
        const auto t0 = std::chrono::steady_clock::now();
        const RefinedSurface r = refine_uniform(p, k);
        const bench::DistanceReport phi = bench::compute_distances(p.original, r.surface, sampling);
        const bench::DistanceReport plain = bench::compute_distances(p.original, plain_surface(p, r), sampling);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        auto side = [&](const bench::DistanceReport& d) {
            std::ostringstream s;
            s << "{\"hausdorff_relative\": " << num(d.hausdorff / diagonal)
              << ", \"original_to_refined_max_relative\": " << num(d.original_to_coarse.max / diagonal)
              << ", \"refined_to_original_max_relative\": " << num(d.coarse_to_original.max / diagonal)
              << ", \"mean_two_sided_relative\": "
              << num(0.5 * (d.original_to_coarse.mean + d.coarse_to_original.mean) / diagonal)
              << ", \"p99_two_sided_relative\": "
              << num(std::max(d.original_to_coarse.p99, d.coarse_to_original.p99) / diagonal)
              << ", \"p999_two_sided_relative\": "
              << num(std::max(d.original_to_coarse.p999, d.coarse_to_original.p999) / diagonal)
              << ", \"samples\": " << d.original_to_coarse.samples + d.coarse_to_original.samples << "}";
            return s.str();
        };
        o << (first ? "" : ", ") << "\n  {\"K\": " << k << ", \"triangles\": " << r.surface.num_triangles()
          << ", \"phi\": " << side(phi) << ", \"plain\": " << side(plain) << ", \"seconds\": " << num(seconds);
        if (diagnose) o << ", \"worst_with_phi\": " << worst_spot(p, r, phi, diagonal);
        o << "}";
        first = false;
    }
    o << "]";
    if (diagnose) {
        // Distribution over the coarse triangles, to compare with the worst spots.
        int64_t over90 = 0, over60 = 0;
        double worst_dev = 0, worst_stretch = 0;
        for (int32_t t = 0; t < p.coarse.num_triangles(); ++t) {
            const CoarseTriangleStats st = coarse_triangle_stats(p, t);
            over90 += st.normal_deviation_degrees > 90;
            over60 += st.normal_deviation_degrees > 60;
            worst_dev = std::max(worst_dev, st.normal_deviation_degrees);
            worst_stretch = std::max(worst_stretch, st.max_stretch);
        }
        o << ", \"coarse_triangles_normal_deviation_over_60\": " << over60 << ", \"over_90\": " << over90
          << ", \"max_normal_deviation_degrees\": " << num(worst_dev) << ", \"max_stretch\": " << num(worst_stretch);
    }
    o << "}";
    return o.str();
}

std::string throughput(const Parametrization& p, int64_t points, const std::vector<int>& threads, int repeat,
                       uint64_t seed) {
    double t0 = wall_seconds();
    const PhiEvaluator phi(p);
    const double build = wall_seconds() - t0;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    const int32_t nt = p.coarse.num_triangles();
    std::vector<int32_t> tris(static_cast<size_t>(points));
    std::vector<Vec3> bary(static_cast<size_t>(points));
    for (int64_t i = 0; i < points; ++i) {
        tris[size_t(i)] = int32_t(rng() % uint64_t(nt));
        double a = u(rng), b = u(rng);
        if (a + b > 1) a = 1 - a, b = 1 - b;
        bary[size_t(i)] = {1 - a - b, a, b};
    }
    std::vector<PhiSample> out;
    std::vector<Vec3> positions;
    std::ostringstream o;
    o << "{\"coarse_triangles\": " << nt << ", \"pieces\": " << p.num_pieces() << ", \"points\": " << points
      << ", \"build_seconds\": " << num(build) << ", \"batched\": [";
    double checksum = 0;
    bool first = true;
    for (const bool full : {true, false})
        for (int th : threads) {
            // One untimed call first: it allocates the output (page faults are not phi).
            if (full) phi.evaluate(tris, bary, out, th);
            else phi.evaluate_positions(tris, bary, positions, th);
            std::vector<double> wall, cpu;
            for (int rep = 0; rep < repeat; ++rep) {
                const double w0 = wall_seconds(), c0 = cpu_seconds();
                if (full) phi.evaluate(tris, bary, out, th);
                else phi.evaluate_positions(tris, bary, positions, th);
                wall.push_back(wall_seconds() - w0);
                cpu.push_back(cpu_seconds() - c0);
                checksum += full ? out[size_t(rep)].position[0] : positions[size_t(rep)][0];
            }
            std::sort(wall.begin(), wall.end());
            std::sort(cpu.begin(), cpu.end());
            const double best = wall.front(), median = wall[wall.size() / 2], cpu_median = cpu[cpu.size() / 2];
            o << (first ? "" : ", ") << "\n  {\"output\": \"" << (full ? "PhiSample" : "position")
              << "\", \"threads\": " << th << ", \"best_wall_seconds\": " << num(best)
              << ", \"median_wall_seconds\": " << num(median) << ", \"median_cpu_seconds\": " << num(cpu_median)
              << ", \"per_second_best\": " << num(double(points) / best)
              << ", \"per_second_median\": " << num(double(points) / median)
              << ", \"per_cpu_second\": " << num(double(points) / cpu_median) << "}";
            first = false;
        }
    o << "]";
    // Reference: one query at a time, in the random order and grouped by triangle.
    const size_t n = std::min<size_t>(size_t(points), 2000000);
    {
        const double w0 = wall_seconds();
        for (size_t i = 0; i < n; ++i) checksum += phi.evaluate(tris[i], bary[i]).position[1];
        const double w = wall_seconds() - w0;
        o << ",\n \"single_random_order_per_second\": " << num(double(n) / w);
    }
    {
        std::vector<size_t> order(n);
        for (size_t i = 0; i < n; ++i) order[i] = i;
        std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return tris[a] < tris[b]; });
        std::vector<int32_t> gt(n);
        std::vector<Vec3> gb(n);
        for (size_t i = 0; i < n; ++i) gt[i] = tris[order[i]], gb[i] = bary[order[i]];
        const double w0 = wall_seconds();
        for (size_t i = 0; i < n; ++i) checksum += phi.evaluate(gt[i], gb[i]).position[2];
        const double w = wall_seconds() - w0;
        o << ",\n \"single_grouped_order_per_second\": " << num(double(n) / w);
    }
    o << ",\n \"checksum\": " << num(checksum) << "}";
    return o.str();
}

std::string inverse_throughput(const Parametrization& p, int64_t points, const std::vector<int>& threads, int repeat,
                               uint64_t seed, double offset) {
    const double diagonal = bounding_box_diagonal(p.original);
    double t0 = wall_seconds();
    const PhiEvaluator phi(p);
    const double build_phi = wall_seconds() - t0;
    t0 = wall_seconds();
    const PhiInverse inverse(p);
    const double build_inverse = wall_seconds() - t0;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    const int32_t nt = p.coarse.num_triangles();
    const size_t n = static_cast<size_t>(points);
    std::vector<SurfacePoint> xs(n);
    for (size_t i = 0; i < n; ++i) {
        double a = u(rng), b = u(rng);
        if (a + b > 1) a = 1 - a, b = 1 - b;
        xs[i] = {int32_t(rng() % uint64_t(nt)), {1 - a - b, a, b}};
    }
    std::vector<PhiSample> ys;
    phi.evaluate(xs, ys, 2);
    std::vector<OriginalPoint> originals(n);
    std::vector<Vec3> positions(n);
    for (size_t i = 0; i < n; ++i) {
        originals[i] = {ys[i].original_triangle, ys[i].original_barycentric};
        positions[i] = ys[i].position + (offset * diagonal) * ys[i].normal;
    }
    // Outputs, allocated by one untimed call each.
    std::vector<PhiSample> samples;
    std::vector<Vec3> images;
    std::vector<SurfacePoint> from_original, from_position;
    std::vector<PhiInverseSample> inverse_samples;
    const char* names[5] = {"phi PhiSample", "phi position", "inverse from_original", "inverse from_position",
                            "inverse from_position PhiInverseSample"};
    const auto run = [&](int form, int th) {
        switch (form) {
        case 0: phi.evaluate(xs, samples, th); break;
        case 1: phi.evaluate_positions(xs, images, th); break;
        case 2: inverse.from_original(originals, from_original, th); break;
        case 3: inverse.from_position(positions, from_position, th); break;
        default: inverse.from_position(positions, inverse_samples, th); break;
        }
    };
    for (int form = 0; form < 5; ++form) run(form, 1);
    // Round trips (untimed): phi of the inverse against y.
    double err_original = 0, err_position = 0;
    {
        std::vector<Vec3> back;
        phi.evaluate_positions(from_original, back, 2);
        for (size_t i = 0; i < n; ++i) err_original = std::max(err_original, distance(back[i], ys[i].position));
        phi.evaluate_positions(from_position, back, 2);
        for (size_t i = 0; i < n; ++i) err_position = std::max(err_position, distance(back[i], ys[i].position));
    }
    std::vector<std::vector<double>> wall(5 * threads.size()), cpu(5 * threads.size());
    for (int rep = 0; rep < repeat; ++rep)
        for (size_t k = 0; k < threads.size(); ++k)
            for (int form = 0; form < 5; ++form) {
                const double w0 = wall_seconds(), c0 = cpu_seconds();
                run(form, threads[k]);
                wall[5 * k + size_t(form)].push_back(wall_seconds() - w0);
                cpu[5 * k + size_t(form)].push_back(cpu_seconds() - c0);
            }
    std::ostringstream o;
    o << "{\"coarse_triangles\": " << nt << ", \"original_triangles\": " << p.original.num_triangles()
      << ", \"pieces\": " << p.num_pieces() << ", \"points\": " << points << ", \"offset_relative\": " << num(offset)
      << ", \"build_seconds_phi\": " << num(build_phi) << ", \"build_seconds_inverse\": " << num(build_inverse)
      << ", \"max_round_trip_error_relative\": {\"from_original\": " << num(err_original / diagonal)
      << ", \"from_position\": " << num(err_position / diagonal) << "}, \"batched\": [";
    bool first = true;
    for (size_t k = 0; k < threads.size(); ++k)
        for (int form = 0; form < 5; ++form) {
            std::vector<double> w = wall[5 * k + size_t(form)], c = cpu[5 * k + size_t(form)];
            std::sort(w.begin(), w.end());
            std::sort(c.begin(), c.end());
            const double median = w[w.size() / 2], cpu_median = c[c.size() / 2];
            o << (first ? "" : ", ") << "\n  {\"call\": \"" << names[form] << "\", \"threads\": " << threads[k]
              << ", \"median_wall_seconds\": " << num(median) << ", \"median_cpu_seconds\": " << num(cpu_median)
              << ", \"per_second_median\": " << num(double(points) / median)
              << ", \"per_cpu_second\": " << num(double(points) / cpu_median) << "}";
            first = false;
        }
    o << "]}";
    return o.str();
}

}  // namespace

int main(int argc, char** argv) {
    const std::string tool = "bpm-bench-refine";
    CLI::App app{"Refinement measurements for bench/refine.py: shape, convergence, throughput (JSON on stdout).", tool};
    app.require_subcommand(1);
    std::string file, levels_text = "0,1,2,3,4", threads_text = "1,2", output = "-";
    int levels = 3, repeat = 3;
    int64_t points = 10000000;
    uint64_t seed = 1;
    bench::SamplingOptions sampling;
    sampling.area_samples = 200000;
    sampling.min_per_triangle = 1;
    auto* sh = app.add_subcommand("shape", "Aspect ratios of the coarse and the K-times refined surface");
    sh->add_option("FILE", file, "Input .bpm")->required();
    sh->add_option("--levels", levels, "K")->capture_default_str();
    auto* cv = app.add_subcommand("convergence", "Hausdorff distance of the refined surfaces, with phi and plain");
    cv->add_option("FILE", file, "Input .bpm")->required();
    cv->add_option("--levels", levels_text, "Comma-separated K")->capture_default_str();
    cv->add_option("--samples", sampling.area_samples, "Area-proportional random samples per surface")
        ->capture_default_str();
    cv->add_option("--min-per-triangle", sampling.min_per_triangle, "Random samples at least per triangle")
        ->capture_default_str();
    bool diagnose = false;
    cv->add_flag("--diagnose", diagnose,
                 "Also report, per K, where the largest distance with phi was found (the coarse triangle, the largest "
                 "angle between its normal and the normals of the original pieces on it, and how much phi stretches "
                 "them), and how many coarse triangles carry pieces turned by more than 60 / 90 degrees");
    auto* tp = app.add_subcommand("throughput", "phi evaluations per second for random points");
    tp->add_option("FILE", file, "Input .bpm")->required();
    tp->add_option("--points", points, "Number of random points")->capture_default_str();
    tp->add_option("--threads", threads_text, "Comma-separated thread counts for the batched call")
        ->capture_default_str();
    tp->add_option("--repeat", repeat, "Repetitions per thread count (best and median reported)")
        ->capture_default_str();
    tp->add_option("--seed", seed, "Seed of the random points")->capture_default_str();
    double offset = 0;
    auto* iv = app.add_subcommand("inverse", "inverse phi evaluations per second next to phi's, for random points");
    iv->add_option("FILE", file, "Input .bpm")->required();
    iv->add_option("--points", points, "Number of random points")->capture_default_str();
    iv->add_option("--threads", threads_text, "Comma-separated thread counts for the batched calls")
        ->capture_default_str();
    iv->add_option("--repeat", repeat, "Repetitions (median reported)")->capture_default_str();
    iv->add_option("--seed", seed, "Seed of the random points")->capture_default_str();
    iv->add_option("--offset", offset,
                   "Move the position queries this far (relative to the bounding-box diagonal) along the normal")
        ->capture_default_str();
    app.add_option("-o,--output", output, "Write the JSON here instead of standard output");
    tools::add_version_flag(app, tool);
    return tools::run(tool, argc, argv, app, [&]() {
        const BpmFile f = read_bpm(file);
        std::string json;
        if (*sh) json = shape(f.param, levels);
        else if (*cv) json = convergence(f.param, parse_list(levels_text), sampling, diagnose);
        else if (*iv) json = inverse_throughput(f.param, points, parse_list(threads_text), std::max(1, repeat), seed, offset);
        else json = throughput(f.param, points, parse_list(threads_text), std::max(1, repeat), seed);
        json += "\n";
        if (output == "-") {
            std::cout << json;
        } else {
            FILE* fp = std::fopen(output.c_str(), "wb");
            if (!fp) throw OutputError(output, "cannot open for writing");
            const bool ok = std::fwrite(json.data(), 1, json.size(), fp) == json.size();
            if (std::fclose(fp) != 0 || !ok) throw OutputError(output, "write failed");
        }
        return int(tools::kOk);
    });
}
