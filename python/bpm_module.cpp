// The Python module bpm (package python/bpm, extension bpm._bpm): read a .bpm file and
// evaluate phi from Python with numpy arrays, through libbpm.so; or make one from a
// surface given as arrays (bpm.simplify) and write it.
//
// Arrays are copies made once when the file is read (numpy owns them; they are read-only
// so that nobody expects a change to reach phi). Batched calls copy their inputs, release
// the GIL and run libbpm's batched evaluation; they can use several threads.
// libbpm's exceptions become bpm.Error subclasses with the tools' messages
// ("FILE: message" for input and output errors, tools/common/tool_main.cpp); bad shapes
// and indices are ValueError (bpm.OptionError is a ValueError too).

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <cctype>
#include <charconv>
#include <cstdint>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "bpm/boundary_repair.h"
#include "bpm/check.h"
#include "bpm/bpm_file.h"
#include "bpm/errors.h"
#include "bpm/phi_evaluation.h"
#include "bpm/phi_inverse.h"
#include "bpm/refine.h"
#include "bpm/self_intersection_repair.h"
#include "bpm/simplify.h"
#include "bpm/smooth.h"
#include "bpm/surface.h"
#include "bpm/tet_refine.h"
#include "bpm/tetmesh.h"
#include "bpm/tetmesh_materials.h"
#include "bpm/version.h"

namespace py = pybind11;

namespace {

// ---- numpy <-> std::vector --------------------------------------------------------

template <class T, size_t N>
py::array rows(const std::vector<std::array<T, N>>& v) {
    py::array_t<T> a({static_cast<py::ssize_t>(v.size()), static_cast<py::ssize_t>(N)});
    if (!v.empty()) std::memcpy(a.mutable_data(), v.data(), v.size() * sizeof(v[0]));
    return std::move(a);
}

template <class T>
py::array column(const std::vector<T>& v) {
    py::array_t<T> a(static_cast<py::ssize_t>(v.size()));
    if (!v.empty()) std::memcpy(a.mutable_data(), v.data(), v.size() * sizeof(T));
    return std::move(a);
}

py::array read_only(py::array a) {
    a.attr("setflags")(py::arg("write") = false);
    return a;
}

std::string shape_of(const py::array& a) { return py::str(py::tuple(a.attr("shape"))).cast<std::string>(); }

// Integer indices (any integer dtype; floats are refused rather than truncated) in
// [lowest, bound), `what` naming them; of shape (k,) (columns = 0) or (k, columns).
std::vector<int32_t> query_indices(const py::object& obj, const char* name, int64_t lowest, int64_t bound,
                                   const char* what, int columns = 0) {
    py::array in = py::array::ensure(obj);  // lists and other sequences too
    if (!in) throw py::value_error(std::string(name) + " must be an array of integers");
    if (columns == 0 && in.ndim() != 1)
        throw py::value_error(std::string(name) + " must be a 1-D array, got " + std::to_string(in.ndim()) + " dimensions");
    if (columns > 0 && (in.ndim() != 2 || in.shape(1) != columns))
        throw py::value_error(std::string(name) + " must have shape (k, " + std::to_string(columns) + "), got " +
                              shape_of(in));
    const char kind = in.dtype().kind();
    if (in.size() > 0 && kind != 'i' && kind != 'u')
        throw py::value_error(std::string(name) + " must be integers, got dtype kind '" + kind + "'");
    auto t = py::array_t<int64_t, py::array::c_style | py::array::forcecast>::ensure(in);
    std::vector<int32_t> out(static_cast<size_t>(t.size()));
    const int64_t* p = t.data();
    for (size_t i = 0; i < out.size(); ++i) {
        if (p[i] < lowest || p[i] >= bound) {
            const std::string at = columns ? std::to_string(i / columns) + ", " + std::to_string(i % columns)
                                           : std::to_string(i);
            throw py::value_error(std::string(name) + "[" + at + "] = " + std::to_string(p[i]) + " is not " + what +
                                  " (" + std::to_string(lowest) + " <= i < " + std::to_string(bound) + ")");
        }
        out[i] = static_cast<int32_t>(p[i]);
    }
    return out;
}

std::vector<int32_t> query_triangles(const py::object& obj, int32_t num_triangles) {
    return query_indices(obj, "triangles", 0, num_triangles, "a coarse triangle");
}

// Points or barycentric coordinates: (k, 3) floats, finite.
std::vector<bpm::Vec3> query_vec3(const py::object& obj, const char* name, size_t k, const char* match) {
    py::array in = py::array::ensure(obj);
    if (!in) throw py::value_error(std::string(name) + " must be an array of shape (k, 3)");
    if (in.ndim() != 2 || in.shape(1) != 3 || (match && static_cast<size_t>(in.shape(0)) != k))
        throw py::value_error(std::string(name) + " must have shape (" + (match ? std::to_string(k) : "k") + ", 3)" +
                              (match ? std::string(" to match ") + match : "") + ", got " + shape_of(in));
    auto b = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(in);
    std::vector<bpm::Vec3> out(static_cast<size_t>(in.shape(0)));
    if (!out.empty()) std::memcpy(out.data(), b.data(), out.size() * sizeof(bpm::Vec3));
    for (size_t i = 0; i < out.size(); ++i)
        for (double x : out[i])
            if (!std::isfinite(x)) throw py::value_error(std::string(name) + "[" + std::to_string(i) + "] is not finite");
    return out;
}

// Barycentric coordinates of points of a triangle: components >= 0 summing to 1, up to
// kBarycentricSlack (what rounding in a caller's arithmetic gives). The C++ evaluators take
// this as a precondition and extrapolate outside it: (0.2, 0.2, 0.2) gave a point off the
// surface, with no error.
constexpr double kBarycentricSlack = 1e-6;

std::vector<bpm::Vec3> query_barycentrics(const py::object& obj, const char* name, size_t k, const char* match) {
    std::vector<bpm::Vec3> out = query_vec3(obj, name, k, match);
    for (size_t i = 0; i < out.size(); ++i) {
        const bpm::Vec3& b = out[i];
        if (b[0] >= -kBarycentricSlack && b[1] >= -kBarycentricSlack && b[2] >= -kBarycentricSlack &&
            std::abs(b[0] + b[1] + b[2] - 1.0) <= kBarycentricSlack)
            continue;
        char text[160];
        std::snprintf(text, sizeof text, "[%zu] = (%.9g, %.9g, %.9g), sum %.9g, is not a point of the triangle", i,
                      b[0], b[1], b[2], b[0] + b[1] + b[2]);
        throw py::value_error(std::string(name) + text +
                              " (barycentric coordinates are >= 0 and sum to 1, up to 1e-6)");
    }
    return out;
}

std::vector<bpm::Vec3> query_barycentrics(const py::object& obj, size_t k) {
    return query_barycentrics(obj, "barycentrics", k, "triangles");
}

int thread_count(int threads) {
    if (threads < 0) throw py::value_error("threads must be >= 0 (0 = all cores), got " + std::to_string(threads));
    return threads;
}

// ---- long calls ------------------------------------------------------------------------

// A long call (bpm.simplify, File.mesh, File.refine_mesh) run without the GIL, that Python
// can stop. libbpm's progress reports (often: every chunk of the first ranking, every 256
// removals; on the calling thread) take the GIL, look for a pending signal, so that Ctrl-C
// raises KeyboardInterrupt from inside a run of minutes instead of after it, and call the
// caller's `progress`: an exception raised there stops the run and is raised, False stops
// it with bpm.Error("cancelled"). libbpm's warnings become Python warnings (UserWarning),
// as the tools print them. Once a stop is asked for, every later report or warning answers
// at once, without Python (the planning pool skips a failed round's remaining tasks, but
// nothing else promises that libbpm reports no more before Cancelled reaches us). The
// exception is kept here, not in the thread's error indicator, and raised by run() when
// libbpm has stopped.
class LongCall {
public:
    explicit LongCall(py::object progress) : progress_(std::move(progress)) {
        context_.progress = [this](double fraction, const std::string& stage) { return go_on(fraction, stage); };
        context_.log = [this](bpm::LogLevel level, const std::string& text) {
            if (level == bpm::LogLevel::Warning) warn(text);
        };
    }
    LongCall(const LongCall&) = delete;
    LongCall& operator=(const LongCall&) = delete;

    const bpm::Context& context() const { return context_; }

    // Runs `call` without the GIL; raises the Python exception that stopped it, if any.
    template <class Call>
    void run(Call&& call) {
        try {
            py::gil_scoped_release release;
            call();
        } catch (const bpm::Cancelled&) {
            if (error_) throw *error_;
            throw;
        }
        if (error_) throw *error_;  // a warning turned into an error after the last report
    }

    // A warning about the result, raised as a Python warning (the GIL held).
    void warn_now(const std::string& text) {
        if (PyErr_WarnEx(PyExc_UserWarning, text.c_str(), 1) != 0) throw py::error_already_set();
    }

private:
    bool go_on(double fraction, const std::string& stage) {
        if (stopped_.load()) return false;
        py::gil_scoped_acquire gil;
        if (PyErr_CheckSignals() != 0) return stop();
        if (progress_.is_none()) return true;
        try {
            const py::object answer = progress_(fraction, stage);
            if (answer.is_none()) return true;
            const int truth = PyObject_IsTrue(answer.ptr());
            if (truth < 0) return stop();  // its __bool__ raised
            if (truth == 0) stopped_.store(true);
            return truth != 0;
        } catch (py::error_already_set& e) {  // raised by the callback
            error_.emplace(std::move(e));
            stopped_.store(true);
            return false;
        }
    }
    // With the GIL and a Python error pending: keep it for run(), stop.
    bool stop() {
        error_.emplace(py::error_already_set());
        stopped_.store(true);
        return false;
    }
    void warn(const std::string& text) {
        if (stopped_.load()) return;
        py::gil_scoped_acquire gil;
        if (PyErr_WarnEx(PyExc_UserWarning, text.c_str(), 1) != 0) stop();  // warnings as errors
    }

    py::object progress_;
    bpm::Context context_;
    std::atomic<bool> stopped_{false};
    std::optional<py::error_already_set> error_;
};

// ---- the file object -----------------------------------------------------------------

class File {
public:
    explicit File(const std::string& path) : File(bpm::read_bpm(path), path) {}
    // A file made in memory (bpm.simplify): `path` is what __repr__ and File.path show.
    File(bpm::BpmFile file, std::string path) : file_(std::make_unique<bpm::BpmFile>(std::move(file))), path_(std::move(path)) {
        const bpm::Parametrization& p = file_->param;
        arrays_["coarse_vertices"] = read_only(rows(p.coarse.vertices));
        arrays_["coarse_triangles"] = read_only(rows(p.coarse.triangles));
        arrays_["coarse_patches"] = read_only(column(p.coarse.patches));
        arrays_["original_vertices"] = read_only(rows(p.original.vertices));
        arrays_["original_triangles"] = read_only(rows(p.original.triangles));
        arrays_["original_patches"] = read_only(column(p.original.patches));
        arrays_["coarse_vertex_origin"] = read_only(column(p.coarse_vertex_origin));
        if (file_->tetmesh) {
            const bpm::TetMesh& m = *file_->tetmesh;
            arrays_["tet_vertices"] = read_only(rows(m.vertices));
            arrays_["tet_tetrahedra"] = read_only(rows(m.tetrahedra));
            arrays_["tet_regions"] = read_only(column(m.regions));
            arrays_["tet_faces"] = read_only(rows(m.faces));
            arrays_["tet_face_coarse_triangle"] = read_only(column(m.face_coarse_triangle));
            // The file's two datasets, one column each, from the SurfacePoint per vertex.
            std::vector<int32_t> triangles(m.vertex_parameter_points.size());
            std::vector<bpm::Vec3> barycentrics(m.vertex_parameter_points.size());
            for (size_t v = 0; v < m.vertex_parameter_points.size(); ++v) {
                triangles[v] = m.vertex_parameter_points[v].triangle;
                barycentrics[v] = m.vertex_parameter_points[v].barycentric;
            }
            arrays_["tet_vertex_parameter_triangle"] = read_only(column(triangles));
            arrays_["tet_vertex_parameter_barycentric"] = read_only(rows(barycentrics));
            if (!m.region_material.empty()) arrays_["tet_region_material"] = read_only(column(m.region_material));
        }
    }

    py::object array(const char* name) const {
        auto it = arrays_.find(name);
        return it == arrays_.end() ? py::none() : py::object(it->second);
    }
    bool has_tetmesh() const { return file_->tetmesh.has_value(); }
    const std::string& path() const { return path_; }
    const std::string& units() const { return file_->units; }
    int32_t num_coarse_triangles() const { return file_->param.coarse.num_triangles(); }

    py::array phi(const py::object& triangles, const py::object& barycentrics, int threads) {
        std::vector<int32_t> t = query_triangles(triangles, num_coarse_triangles());
        std::vector<bpm::Vec3> b = query_barycentrics(barycentrics, t.size());
        threads = thread_count(threads);
        const bpm::PhiEvaluator& ev = evaluator();
        std::vector<bpm::Vec3> positions;
        {
            py::gil_scoped_release release;
            ev.evaluate_positions(t, b, positions, threads);
        }
        return rows(positions);
    }

    py::dict phi_samples(const py::object& triangles, const py::object& barycentrics, int threads) {
        std::vector<int32_t> t = query_triangles(triangles, num_coarse_triangles());
        std::vector<bpm::Vec3> b = query_barycentrics(barycentrics, t.size());
        threads = thread_count(threads);
        const bpm::PhiEvaluator& ev = evaluator();
        std::vector<bpm::PhiSample> samples;
        std::vector<bpm::Vec3> pos, normal, obary;
        std::vector<int32_t> otri;
        {
            py::gil_scoped_release release;
            ev.evaluate(t, b, samples, threads);
            pos.resize(samples.size()), normal.resize(samples.size()), obary.resize(samples.size()),
                otri.resize(samples.size());
            for (size_t i = 0; i < samples.size(); ++i) {
                pos[i] = samples[i].position;
                normal[i] = samples[i].normal;
                otri[i] = samples[i].original_triangle;
                obary[i] = samples[i].original_barycentric;
            }
        }
        py::dict d;
        d["positions"] = rows(pos);
        d["normals"] = rows(normal);
        d["original_triangles"] = column(otri);
        d["original_barycentrics"] = rows(obary);
        return d;
    }

    // Inverse phi of points of S0 given exactly (original triangle, barycentric).
    py::tuple phi_inverse(const py::object& original_triangles, const py::object& original_barycentrics,
                          int threads) {
        std::vector<int32_t> t = query_indices(original_triangles, "original_triangles", 0,
                                               file_->param.original.num_triangles(), "an original triangle");
        std::vector<bpm::Vec3> b = query_barycentrics(original_barycentrics, "original_barycentrics", t.size(),
                                                      "original_triangles");
        threads = thread_count(threads);
        const bpm::PhiInverse& inv = inverse();
        std::vector<bpm::OriginalPoint> in(t.size());
        for (size_t i = 0; i < t.size(); ++i) in[i] = {t[i], b[i]};
        std::vector<bpm::SurfacePoint> out;
        {
            py::gil_scoped_release release;
            inv.from_original(in, out, threads);
        }
        return surface_points(out);
    }

    // Inverse phi of positions on or near S0: the closest point of S0 first.
    py::dict phi_inverse_positions(const py::object& positions, int threads) {
        std::vector<bpm::Vec3> x = query_vec3(positions, "positions", 0, nullptr);
        threads = thread_count(threads);
        const bpm::PhiInverse& inv = inverse();
        std::vector<bpm::PhiInverseSample> out;
        std::vector<bpm::SurfacePoint> points;
        std::vector<int32_t> otri;
        std::vector<bpm::Vec3> obary, feet;
        std::vector<double> distances;
        {
            py::gil_scoped_release release;
            inv.from_position(x, out, threads);
            for (const bpm::PhiInverseSample& s : out) {
                points.push_back(s.point);
                otri.push_back(s.original.triangle);
                obary.push_back(s.original.barycentric);
                feet.push_back(s.foot);
                distances.push_back(s.distance);
            }
        }
        py::tuple tb = surface_points(points);
        py::dict d;
        d["triangles"] = tb[0];
        d["barycentrics"] = tb[1];
        d["feet"] = rows(feet);
        d["original_triangles"] = column(otri);
        d["original_barycentrics"] = rows(obary);
        d["distances"] = column(distances);
        return d;
    }

    // repair_boundary_sliding (bpm/boundary_repair.h) on a copy of `vertices`; with plain
    // positions (not None) its retreat (step 5) too. The slide (step 6, options.slide) changes
    // parameter points: the new ones are returned in the dict, for the caller to keep (the next
    // level's points are made from them, and the next call moves each vertex towards phi of
    // its point).
    py::tuple repair(const py::object& vertices, const py::object& tetrahedra, const py::object& parameter_triangles,
                     const py::object& parameter_barycentrics, const py::object& plain_positions,
                     const bpm::BoundaryRepairOptions& options) {
        std::vector<bpm::Vec3> x = query_vec3(vertices, "vertices", 0, nullptr);
        const int64_t n = static_cast<int64_t>(x.size());
        std::vector<int32_t> flat = query_indices(tetrahedra, "tetrahedra", 0, n, "a vertex", 4);
        std::vector<bpm::Tet> tets(flat.size() / 4);
        if (!tets.empty()) std::memcpy(tets.data(), flat.data(), flat.size() * sizeof(int32_t));
        std::vector<int32_t> pt = query_indices(parameter_triangles, "parameter_triangles", -1, num_coarse_triangles(),
                                                "a coarse triangle or -1");
        if (static_cast<int64_t>(pt.size()) != n)
            throw py::value_error("parameter_triangles must have one entry per vertex (" + std::to_string(n) +
                                  "), got " + std::to_string(pt.size()));
        std::vector<bpm::Vec3> pb = query_vec3(parameter_barycentrics, "parameter_barycentrics", pt.size(),
                                               "parameter_triangles");
        std::vector<bpm::SurfacePoint> points(pt.size());
        for (size_t i = 0; i < pt.size(); ++i) points[i] = {pt[i], pb[i]};
        std::vector<bpm::Vec3> plain;
        if (!plain_positions.is_none()) plain = query_vec3(plain_positions, "plain_positions", x.size(), "vertices");
        const bpm::PhiEvaluator& ev = evaluator();
        bpm::BoundaryRepairResult r;
        {
            py::gil_scoped_release release;
            r = bpm::repair_boundary_sliding(ev, x, tets, points, plain, options, bpm::Context{});
        }
        std::vector<int32_t> new_triangles(points.size());
        std::vector<bpm::Vec3> new_barycentrics(points.size());
        for (size_t i = 0; i < points.size(); ++i) {
            new_triangles[i] = points[i].triangle;
            new_barycentrics[i] = points[i].barycentric;
        }
        py::dict d;
        d["boundary_vertices"] = r.boundary_vertices;
        d["at_phi_before"] = r.at_phi_before;
        d["at_phi"] = r.at_phi;
        d["held_back"] = r.held_back;
        d["not_moved"] = r.not_moved;
        d["widened"] = r.widened;
        d["retreated"] = r.retreated;
        d["slid"] = r.slid;
        d["parameter_triangles"] = column(new_triangles);
        d["parameter_barycentrics"] = rows(new_barycentrics);
        d["max_distance"] = r.max_distance;
        d["max_distance_relative"] = r.max_distance_relative;
        d["min_phi_fraction"] = r.min_phi_fraction;
        d["smoothed_vertices"] = r.smoothed_vertices;
        d["min_dihedral_degrees"] = r.min_dihedral_degrees;
        d["inverted_before"] = r.inverted_before;
        d["inverted_after"] = r.inverted_after;
        d["seconds"] = r.seconds;
        return py::make_tuple(rows(x), d);
    }

    py::tuple refine(int levels, double tolerance, std::optional<int> max_level) {
        bpm::RefineOptions options;
        // bpm-refine's --levels excludes --max-level as it does --max-error (the library
        // refuses levels with a tolerance itself): a uniform refinement has no level limit.
        if (levels >= 0 && max_level)
            throw bpm::OptionError("refine: max_level limits the adaptive refinement (tolerance) only; give levels "
                                   "or max_level, not both; got levels " + std::to_string(levels) +
                                   " and max_level " + std::to_string(*max_level));
        options.levels = levels;
        options.tolerance = tolerance;
        if (max_level) options.max_level = *max_level;
        bpm::RefinedSurface out;
        {
            py::gil_scoped_release release;
            bpm::refine(file_->param, options, bpm::Context{}, out);
        }
        return py::make_tuple(rows(out.surface.vertices), rows(out.surface.triangles));
    }

    // bpm-mesh: a tet mesh of the coarse surface (bpm/tetmesh.h, TetGen), its regions given
    // the materials the patches name (bpm/tetmesh_materials.h); a new file in memory.
    File mesh(const bpm::TetMeshOptions& options, const py::object& progress) const {
        bpm::BpmFile meshed = *file_;
        bpm::TetMesh tets;
        LongCall call(progress);
        bpm::MaterialResult materials;
        call.run([&] {
            bpm::generate_tetmesh(meshed.param, options, call.context(), tets);
            materials = bpm::assign_materials(tets, meshed.patch_info);
            bpm::name_patches_after_regions(tets, meshed.patch_info);  // as bpm-mesh does
        });
        // What bpm-mesh warns about the materials.
        if (materials.orientation_ignored)
            call.warn_now("the patches' front/back materials contradict each other (reversed normals?): read "
                          "them as unordered pairs");
        for (const std::string& problem : materials.problems) call.warn_now(problem);
        meshed.tetmesh = std::move(tets);
        const auto given = [](const std::optional<double>& x) {
            if (!x) return std::string("None");
            char text[32];
            std::snprintf(text, sizeof text, "%.17g", *x);
            return std::string(text);
        };
        char arguments[240];
        std::snprintf(arguments, sizeof arguments, "File.mesh(quality=%.17g, min_dihedral=%s, max_volume=%s, smooth=%s, flip=%s)",
                      options.quality, given(options.min_dihedral_degrees).c_str(), given(options.max_volume).c_str(),
                      options.smooth ? "True" : "False", options.flip ? "True" : "False");
        meshed.provenance.push_back({"bpm (Python)", std::string("bpm ") + BPM_VERSION_STRING, arguments, ""});
        return File(std::move(meshed), "<memory>");
    }

    // bpm-check (bpm/check.h): its default checks (format, intersections, topology, junctions,
    // bijectivity, distortion, and the tet mesh's when there is one), replay on request,
    // distance and quality by their limits; the report as bpm-check --json writes it
    // (spec/check-report.md), parsed.
    py::object check(const bpm::CheckSelection& selection, const bpm::CheckOptions& options,
                     const py::object& progress) const {
        LongCall call(progress);
        bpm::CheckReport report;
        call.run([&] { report = bpm::run_checks(*file_, selection, options, call.context()); });
        return py::module_::import("json").attr("loads")(bpm::check_report_to_json(report));
    }

    // bpm-smooth: phi smoothed (bpm/smooth.h), the same coarse surface; a new file in memory
    // with the file's other groups kept, as bpm-smooth keeps them.
    File smooth(const bpm::SmoothOptions& options, const py::object& progress) const {
        bpm::BpmFile smoothed = *file_;
        LongCall call(progress);
        call.run([&] { bpm::smooth(smoothed.param, options, call.context()); });
        char arguments[160];
        std::snprintf(arguments, sizeof arguments, "File.smooth(iterations=%d, tolerance=%.17g, feature_angle=%.17g)",
                      options.iterations, options.tolerance, options.feature_angle_degrees);
        smoothed.provenance.push_back({"bpm (Python)", std::string("bpm ") + BPM_VERSION_STRING, arguments, ""});
        return File(std::move(smoothed), "<memory>");
    }

    // bpm-mesh --existing --refine K: the file's tet mesh refined K times (red refinement),
    // new boundary vertices through phi (bpm/tet_refine.h); a new file in memory.
    File refine_mesh(const bpm::TetRefineOptions& options, const py::object& progress) const {
        if (!file_->tetmesh) throw py::value_error("refine_mesh: the file has no tet mesh (File.mesh makes one)");
        bpm::BpmFile refined = *file_;
        bpm::TetMesh fine;
        LongCall call(progress);
        call.run([&] { bpm::refine_tetmesh(refined.param, *file_->tetmesh, options, call.context(), fine); });
        refined.tetmesh = std::move(fine);
        char arguments[120];
        std::snprintf(arguments, sizeof arguments, "File.refine_mesh(levels=%d, flat=%s, smooth=%s, flip=%s)",
                      options.levels, options.move_to_surface ? "False" : "True", options.repair.smooth ? "True" : "False",
                      options.flip ? "True" : "False");
        refined.provenance.push_back({"bpm (Python)", std::string("bpm ") + BPM_VERSION_STRING, arguments, ""});
        return File(std::move(refined), "<memory>");
    }

    py::list material_names() const {
        py::list names;
        if (file_->tetmesh)
            for (const std::string& n : file_->tetmesh->material_names) names.append(n);
        return names;
    }

    // Writes the file (bpm/bpm_file.h: atomically, the same bytes as the tools would);
    // File.path is then `path`.
    // The GIL stays held: HDF5 is not to run in two Python threads at once, nor beside the
    // fork of an isolated read (set_hdf5_isolation), whose child would inherit HDF5's lock.
    void write(const std::string& path) {
        // An HDF5 file named like a mesh format is a trap for whoever opens it next (the
        // tools refuse any name but .bpm; other names, e.g. .h5, are left to the caller).
        std::string ext = std::filesystem::path(path).extension().string();
        for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        for (const char* mesh : {".off", ".obj", ".stl", ".ply", ".msh", ".vtk", ".vtp", ".vtu", ".mesh", ".surf"})
            if (ext == mesh)
                throw bpm::OptionError("File.write writes .bpm (HDF5) files, and '" + path + "' is named like a " +
                                       ext.substr(1) + " file: name it .bpm (the coarse surface is coarse_vertices "
                                       "and coarse_triangles, e.g. for meshio)");
        bpm::write_bpm(path, *file_);
        path_ = path;
    }

    // What bpm.simplify achieved (None for a file read from disk).
    py::object simplify_report() const { return simplify_report_ ? py::object(*simplify_report_) : py::none(); }
    void set_simplify_report(py::dict report) { simplify_report_ = std::move(report); }

private:
    // Built on first use (O(#pieces), O(#pieces + #S0.T)); the GIL is held here, so only
    // one thread builds them.
    const bpm::PhiEvaluator& evaluator() {
        if (!phi_) phi_ = std::make_unique<bpm::PhiEvaluator>(file_->param);
        return *phi_;
    }
    const bpm::PhiInverse& inverse() {
        if (!inverse_) inverse_ = std::make_unique<bpm::PhiInverse>(file_->param);
        return *inverse_;
    }
    static py::tuple surface_points(const std::vector<bpm::SurfacePoint>& points) {
        std::vector<int32_t> t(points.size());
        std::vector<bpm::Vec3> b(points.size());
        for (size_t i = 0; i < points.size(); ++i) t[i] = points[i].triangle, b[i] = points[i].barycentric;
        return py::make_tuple(column(t), rows(b));
    }

    std::unique_ptr<bpm::BpmFile> file_;  // stable address: phi_ keeps a reference into it
    std::unique_ptr<bpm::PhiEvaluator> phi_;
    std::unique_ptr<bpm::PhiInverse> inverse_;
    std::map<std::string, py::array> arrays_;
    std::string path_;
    std::optional<py::dict> simplify_report_;
};

// ---- bpm.simplify ----------------------------------------------------------------------

// What a caller passes to bpm.simplify, as bpm-simplify's command line would say it: the
// provenance of the file (spec/bpm-format.md, /provenance/arguments).
std::string simplify_arguments(int64_t vertices, int64_t triangles, const bpm::SimplifyOptions& o) {
    char text[320];
    std::snprintf(text, sizeof text,
                  "bpm.simplify(<%lld vertices>, <%lld triangles>, target_vertices=%lld, ratio=%.17g, "
                  "max_error=%.17g, max_aspect=%.17g, feature_angle=%.17g, keep_corners=%s)",
                  (long long)vertices, (long long)triangles, (long long)o.target_vertices, o.target_ratio, o.max_error,
                  o.max_aspect_ratio, o.feature_angle_degrees, o.keep_corners ? "True" : "False");
    return text;
}

// A number for a message: 6 significant digits, '.' whatever the locale (a Python
// program may have called locale.setlocale).
std::string number_text(double value) {
    char text[32];
    const auto end = std::to_chars(text, text + sizeof text, value, std::chars_format::general, 6).ptr;
    return std::string(text, end);
}

void require_feature_angle(double feature_angle) {
    if (!(feature_angle >= 0 && feature_angle <= 180))
        throw bpm::OptionError("feature_angle must be between 0 and 180 degrees (default 60), got " +
                               number_text(feature_angle));
}

// A surface from the arrays of bpm.simplify / bpm.repair_self_intersections: shapes, types
// and index ranges checked (ValueError), not yet validated as a surface.
bpm::Surface surface_from_arrays(const py::object& vertices, const py::object& triangles, const py::object& patches) {
    bpm::Surface surface;
    {
        py::array in = py::array::ensure(vertices);
        if (!in || in.ndim() != 2 || in.shape(1) != 3)
            throw py::value_error("vertices must have shape (n, 3), got " + (in ? shape_of(in) : std::string("no array")));
        if (in.size() > 0 && in.dtype().kind() != 'f' && in.dtype().kind() != 'i' && in.dtype().kind() != 'u')
            throw py::value_error("vertices must be numbers, got dtype kind '" + std::string(1, in.dtype().kind()) + "'");
        if (in.shape(0) > std::numeric_limits<int32_t>::max())
            throw py::value_error("vertices: more than 2^31 - 1 rows");
        auto b = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(in);
        surface.vertices.resize(static_cast<size_t>(in.shape(0)));
        if (!surface.vertices.empty())
            std::memcpy(surface.vertices.data(), b.data(), surface.vertices.size() * sizeof(bpm::Vec3));
    }
    const std::vector<int32_t> flat =
        query_indices(triangles, "triangles", 0, int64_t(surface.vertices.size()), "a vertex", 3);
    surface.triangles.resize(flat.size() / 3);
    if (!flat.empty()) std::memcpy(surface.triangles.data(), flat.data(), flat.size() * sizeof(int32_t));
    if (patches.is_none()) {
        surface.patches.assign(surface.triangles.size(), 0);
    } else {
        surface.patches = query_indices(patches, "patches", std::numeric_limits<int32_t>::min(),
                                        int64_t(std::numeric_limits<int32_t>::max()) + 1, "a patch id (an int32)");
        if (surface.patches.size() != surface.triangles.size())
            throw py::value_error("patches must have one entry per triangle (" +
                                  std::to_string(surface.triangles.size()) + "), got " +
                                  std::to_string(surface.patches.size()));
    }
    if (surface.triangles.empty()) throw py::value_error("triangles: the surface has no triangles");
    return surface;
}

File simplify_arrays(const py::object& vertices, const py::object& triangles, const py::object& patches,
                     int64_t target_vertices, double ratio, double max_error, double max_aspect, double feature_angle,
                     bool keep_corners, int threads, const std::string& units, const py::object& progress) {
    bpm::Surface surface = surface_from_arrays(vertices, triangles, patches);
    // The checks bpm-simplify makes of a file it read (bpm/surface.h); the repairs are the
    // caller's (the tools' --merge-duplicate-vertices and the like).
    const std::vector<bpm::SurfaceProblem> problems = bpm::validate_surface(surface);
    if (!problems.empty()) {
        std::string message = "the surface cannot be simplified: " + bpm::describe_problem(problems[0], surface);
        for (size_t i = 1; i < problems.size() && i < 3; ++i) message += "; " + bpm::describe_problem(problems[i], surface);
        if (problems.size() > 3) message += "; and " + std::to_string(problems.size() - 3) + " more problem" + (problems.size() == 4 ? "" : "s");
        throw py::value_error(message);
    }
    // Each keyword by its Python name (libbpm's messages name the C++ fields, e.g.
    // max_aspect_ratio, which are no keywords of this function).
    if (target_vertices < 0) throw py::value_error("target_vertices must be >= 0, got " + std::to_string(target_vertices));
    if (!(ratio >= 0 && ratio <= 1))
        throw py::value_error("ratio must be in [0, 1] (a fraction of the input vertices, e.g. 0.1), got " +
                              number_text(ratio));
    if (!(max_error >= 0))
        throw py::value_error("max_error must be >= 0 (a fraction of the bounding-box diagonal, e.g. 0.005), got " +
                              number_text(max_error));
    if (!(max_aspect >= 2))
        throw bpm::OptionError("max_aspect must be at least 2 (2 = equilateral; default 30), got " +
                               number_text(max_aspect));
    require_feature_angle(feature_angle);
    if (target_vertices == 0 && ratio == 0 && !std::isfinite(max_error))
        throw py::value_error("give a target: target_vertices, ratio or max_error");
    bpm::SimplifyOptions options;
    options.target_vertices = target_vertices;
    options.target_ratio = ratio;
    options.max_error = max_error;
    options.max_aspect_ratio = max_aspect;
    options.feature_angle_degrees = feature_angle;
    options.keep_corners = keep_corners;
    if (threads < 0)
        throw py::value_error("threads must be >= 0 (0 = as bpm-simplify chooses: 1 for small inputs or a busy "
                              "machine, else 2), got " + std::to_string(threads));
    options.threads = threads;
    bpm::BpmFile file;
    file.units = units;
    file.provenance.push_back({"bpm (Python)", std::string("bpm ") + BPM_VERSION_STRING,
                               simplify_arguments(int64_t(surface.vertices.size()), int64_t(surface.triangles.size()), options),
                               ""});
    LongCall call(progress);
    bpm::SimplifyResult result;
    call.run([&] { result = bpm::simplify(std::move(surface), options, call.context(), file.param); });
    py::dict report;
    report["input_vertices"] = result.input_vertices;
    report["output_vertices"] = result.output_vertices;
    report["output_triangles"] = result.output_triangles;
    report["max_error"] = result.max_error;
    report["worst_aspect_ratio"] = result.worst_aspect_ratio;
    report["target_reached"] = result.target_reached;
    report["stop_reason"] = result.stop_reason;
    report["threads"] = result.threads;
    File made(std::move(file), "<memory>");
    made.set_simplify_report(std::move(report));
    return made;
}

// Python exception classes: bpm.Error and one subclass per libbpm exception type; the
// file errors are OSErrors too, option errors ValueErrors.
PyObject* new_exception(py::module_& m, const char* name, PyObject* base, PyObject* second_base, const char* doc) {
    PyObject* bases = second_base ? PyTuple_Pack(2, base, second_base) : PyTuple_Pack(1, base);
    std::string qualified = std::string("bpm.") + name;
    PyObject* type = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases, nullptr);
    Py_DECREF(bases);
    if (!type) throw py::error_already_set();
    m.add_object(name, py::handle(type));  // the module keeps a reference
    return type;
}

std::string with_where(const std::string& where, const char* what) {
    return where.empty() ? std::string(what) : where + ": " + what;
}

}  // namespace

// bpm-simplify --repair-self-intersections on arrays: (vertices, triangles, patches, report).
py::tuple repair_self_intersections_arrays(const py::object& vertices, const py::object& triangles,
                                           const py::object& patches, double max_change, const py::object& progress) {
    bpm::Surface surface = surface_from_arrays(vertices, triangles, patches);
    if (!(max_change > 0))
        throw py::value_error("max_change must be > 0 (a fraction of the bounding-box diagonal, e.g. 0.01), got " +
                              number_text(max_change));
    for (const bpm::SurfaceProblem& p : bpm::validate_surface(surface))
        if (p.kind == bpm::SurfaceProblem::Kind::NonFiniteCoordinate)
            throw py::value_error("the surface cannot be repaired: " + bpm::describe_problem(p, surface));
    bpm::SelfIntersectionRepairOptions options;
    options.max_change = max_change;
    LongCall call(progress);
    bpm::SelfIntersectionRepair r;
    call.run([&] { r = bpm::repair_self_intersections(surface, options, call.context()); });
    py::dict report;
    report["intersecting_pairs"] = r.intersecting_pairs;
    report["remaining_pairs"] = r.remaining_pairs;
    report["removed_triangles"] = r.removed_triangles;
    report["added_triangles"] = r.added_triangles;
    report["removed_vertices"] = r.removed_vertices;
    report["added_vertices"] = r.added_vertices;
    report["largest_change"] = r.largest_change;
    report["topology_change"] = r.topology_change;
    report["refused"] = r.refused;
    return py::make_tuple(rows(surface.vertices), rows(surface.triangles), column(surface.patches), report);
}

PYBIND11_MODULE(_bpm, m) {
    m.doc() = "bpm: read boundary-parametrized surfaces (.bpm) and evaluate phi (see README, "
              "'Using bpm from a solver')";
    m.attr("__version__") = BPM_VERSION_STRING;
    m.attr("format_version") = py::make_tuple(BPM_FORMAT_VERSION_MAJOR, BPM_FORMAT_VERSION_MINOR);

    static PyObject* error = new_exception(m, "Error", PyExc_Exception, nullptr, "Base of every error bpm reports.");
    static PyObject* input_error = new_exception(m, "InputError", error, PyExc_OSError,
                                                 "A .bpm file is missing, unreadable or malformed.");
    static PyObject* output_error =
        new_exception(m, "OutputError", error, PyExc_OSError, "An output could not be written.");
    static PyObject* option_error =
        new_exception(m, "OptionError", error, PyExc_ValueError, "Options out of range or contradicting each other.");
    static PyObject* algorithm_error =
        new_exception(m, "AlgorithmError", error, nullptr, "An algorithm cannot proceed on this (valid) input.");
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const bpm::InputError& e) {
            PyErr_SetString(input_error, with_where(e.where(), e.what()).c_str());
        } catch (const bpm::OutputError& e) {
            PyErr_SetString(output_error, with_where(e.where(), e.what()).c_str());
        } catch (const bpm::OptionError& e) {
            PyErr_SetString(option_error, e.what());
        } catch (const bpm::AlgorithmError& e) {
            PyErr_SetString(algorithm_error, e.what());
        } catch (const bpm::Error& e) {
            PyErr_SetString(error, e.what());
        } catch (const std::out_of_range& e) {  // libbpm's index checks
            PyErr_SetString(PyExc_ValueError, e.what());
        } catch (const std::invalid_argument& e) {
            PyErr_SetString(PyExc_ValueError, e.what());
        }
    });

    py::class_<File>(m, "File", "A .bpm file read into memory (bpm.read). Arrays are read-only numpy copies.")
        .def_property_readonly("path", &File::path)
        .def_property_readonly("units", &File::units, "free text, e.g. 'mm'; '' if unknown")
        .def_property_readonly("coarse_vertices", [](const File& f) { return f.array("coarse_vertices"); },
                               "(n, 3) float64 vertices of the coarse surface S")
        .def_property_readonly("coarse_triangles", [](const File& f) { return f.array("coarse_triangles"); },
                               "(m, 3) int32 triangles of S (counter-clockwise seen from the front)")
        .def_property_readonly("coarse_patches", [](const File& f) { return f.array("coarse_patches"); },
                               "(m,) int32 patch id of every coarse triangle")
        .def_property_readonly("patches", [](const File& f) { return f.array("coarse_patches"); },
                               "the same as coarse_patches")
        .def_property_readonly("coarse_vertex_origin", [](const File& f) { return f.array("coarse_vertex_origin"); },
                               "(n,) int32 the original vertex each coarse vertex is")
        .def_property_readonly("original_vertices", [](const File& f) { return f.array("original_vertices"); },
                               "(n0, 3) float64 vertices of the original surface S0")
        .def_property_readonly("original_triangles", [](const File& f) { return f.array("original_triangles"); },
                               "(m0, 3) int32 triangles of S0")
        .def_property_readonly("original_patches", [](const File& f) { return f.array("original_patches"); },
                               "(m0,) int32 patch id of every original triangle")
        .def_property_readonly("has_tetmesh", &File::has_tetmesh, "whether the file has a /tetmesh group")
        .def_property_readonly("tet_vertices", [](const File& f) { return f.array("tet_vertices"); },
                               "(v, 3) float64 tet-mesh vertices, or None without /tetmesh")
        .def_property_readonly("tet_tetrahedra", [](const File& f) { return f.array("tet_tetrahedra"); },
                               "(t, 4) int32 positively oriented tetrahedra, or None")
        .def_property_readonly("tet_regions", [](const File& f) { return f.array("tet_regions"); },
                               "(t,) int32 region id >= 1 of every tetrahedron, or None")
        .def_property_readonly("tet_faces", [](const File& f) { return f.array("tet_faces"); },
                               "(f, 3) int32 faces on S, oriented like their coarse triangle, or None")
        .def_property_readonly("tet_face_coarse_triangle",
                               [](const File& f) { return f.array("tet_face_coarse_triangle"); },
                               "(f,) int32 the coarse triangle each face lies on, or None")
        .def_property_readonly("tet_vertex_parameter_triangle",
                               [](const File& f) { return f.array("tet_vertex_parameter_triangle"); },
                               "(v,) int32 coarse triangle containing each vertex, -1 inside; or None")
        .def_property_readonly("tet_vertex_parameter_barycentric",
                               [](const File& f) { return f.array("tet_vertex_parameter_barycentric"); },
                               "(v, 3) float64 barycentric coordinates there (0 inside); or None")
        .def("phi", &File::phi, py::arg("triangles"), py::arg("barycentrics"), py::arg("threads") = 1,
             "phi at points of S given by coarse triangle (k,) and barycentric coordinates (k, 3),\n"
             ">= 0 and summing to 1 (ValueError otherwise): positions (k, 3) on S0. threads=0 uses all cores; the result does not depend on it.")
        .def("phi_samples", &File::phi_samples, py::arg("triangles"), py::arg("barycentrics"),
             py::arg("threads") = 1,
             "Like phi, and also the unit normal of S0 and the original triangle and barycentric\n"
             "coordinates there: dict of positions (k, 3), normals (k, 3), original_triangles (k,)\n"
             "int32, original_barycentrics (k, 3).")
        .def("phi_inverse", &File::phi_inverse, py::arg("original_triangles"), py::arg("original_barycentrics"),
             py::arg("threads") = 1,
             "Inverse phi (bpm/phi_inverse.h) of points of S0 given as original triangle (k,) and\n"
             "barycentric coordinates there (k, 3): the parameter points (triangles (k,) int32,\n"
             "barycentrics (k, 3)) with phi(parameter point) == that point up to rounding.")
        .def("phi_inverse_positions", &File::phi_inverse_positions, py::arg("positions"), py::arg("threads") = 1,
             "Inverse phi of positions (k, 3) on or near S0: the closest point of S0 (foot), then its\n"
             "parameter point. dict of triangles (k,) int32, barycentrics (k, 3), feet (k, 3),\n"
             "original_triangles (k,), original_barycentrics (k, 3), distances (k,) |position - foot|.")
        .def("repair",
             [](File& f, const py::object& vertices, const py::object& tetrahedra, const py::object& parameter_triangles,
                const py::object& parameter_barycentrics, const py::object& plain_positions, int bisection_steps,
                double min_volume_fraction, double min_dihedral_degrees, int boundary_steps, int retry_passes,
                bool smooth, bool widen, bool retreat, bool slide) {
                 bpm::BoundaryRepairOptions o;
                 o.bisection_steps = bisection_steps;
                 o.min_volume_fraction = min_volume_fraction;
                 o.min_dihedral_degrees = min_dihedral_degrees;
                 o.boundary_steps = boundary_steps;
                 o.retry_passes = retry_passes;
                 o.smooth = smooth;
                 o.widen = widen;
                 o.retreat = retreat;
                 o.slide = slide;
                 return f.repair(vertices, tetrahedra, parameter_triangles, parameter_barycentrics, plain_positions, o);
             },
             py::arg("vertices"), py::arg("tetrahedra"), py::arg("parameter_triangles"),
             py::arg("parameter_barycentrics"), py::arg("plain_positions") = py::none(), py::kw_only(),
             py::arg("bisection_steps") = bpm::BoundaryRepairOptions{}.bisection_steps,
             py::arg("min_volume_fraction") = bpm::BoundaryRepairOptions{}.min_volume_fraction,
             py::arg("min_dihedral_degrees") = bpm::BoundaryRepairOptions{}.min_dihedral_degrees,
             py::arg("boundary_steps") = bpm::BoundaryRepairOptions{}.boundary_steps,
             py::arg("retry_passes") = bpm::BoundaryRepairOptions{}.retry_passes,
             py::arg("smooth") = bpm::BoundaryRepairOptions{}.smooth,
             py::arg("widen") = bpm::BoundaryRepairOptions{}.widen,
             py::arg("retreat") = bpm::BoundaryRepairOptions{}.retreat,
             py::arg("slide") = bpm::BoundaryRepairOptions{}.slide,
             "Repair after a solver refines (bpm/boundary_repair.h): moves the boundary vertices of a\n"
             "tet mesh (vertices (n, 3), positively oriented tetrahedra (m, 4)) towards phi of their\n"
             "parameter points (parameter_triangles (n,), -1 for interior vertices;\n"
             "parameter_barycentrics (n, 3)), holding a vertex back where phi would invert or flatten\n"
             "a tetrahedron, and smooths the interior (widen: a last pass lets a held-back vertex widen\n"
             "the thinnest tetrahedron around it). plain_positions (n, 3), where the solver's plain\n"
             "refinement puts each vertex (a new one: the midpoint of the edge it split, of the edge\n"
             "ends' current positions; only those of boundary vertices are used, but every row must be\n"
             "finite), adds the retreat\n"
             "(retreat=True): a boundary vertex next to a tetrahedron below min_dihedral_degrees moves\n"
             "back towards its plain position where that widens the worst tetrahedron around it.\n"
             "slide=True: a boundary vertex next to such a tetrahedron moves along S0 (a new parameter\n"
             "point in the same coarse triangle, on the same coarse edge) where that widens it.\n"
             "Returns (new vertices (n, 3), dict of counts: boundary_vertices, at_phi, held_back,\n"
             "retreated, slid, max_distance, inverted_before/after, ..., and the parameter points after\n"
             "the slide, parameter_triangles (n,) and parameter_barycentrics (n, 3): keep them for the\n"
             "next level and the next call).")
        .def("refine", &File::refine, py::arg("levels") = -1, py::arg("tolerance") = 0.0,
             py::arg("max_level") = py::none(),
             "The coarse surface refined through phi (bpm/refine.h): levels=K splits each coarse\n"
             "triangle into 4**K (0 <= K <= 10); or adaptive with tolerance > 0 (fraction of the\n"
             "bounding-box diagonal of S0), at most max_level levels (default 10). levels with\n"
             "tolerance or max_level raises bpm.OptionError, as bpm-refine refuses --levels with\n"
             "--max-error or --max-level. Returns (vertices (n, 3) float64, triangles (m, 3) int32).")
        .def_property_readonly("tet_region_material", [](const File& f) { return f.array("tet_region_material"); },
                               "(R,) int32 material id (1-based, into material_names) of each region 1..R, or None")
        .def_property_readonly("material_names", &File::material_names,
                               "names of the tet mesh's materials (tet_region_material's ids - 1); [] without")
        .def("mesh",
             [](const File& f, double quality, std::optional<double> min_dihedral, std::optional<double> max_volume,
                bool smooth, bool flip, const py::object& progress) {
                 bpm::TetMeshOptions o;
                 o.quality = quality;
                 o.min_dihedral_degrees = min_dihedral;
                 o.max_volume = max_volume;
                 o.smooth = smooth;
                 o.flip = flip;
                 return f.mesh(o, progress);
             },
             py::kw_only(), py::arg("quality") = bpm::TetMeshOptions{}.quality, py::arg("min_dihedral") = py::none(),
             py::arg("max_volume") = py::none(), py::arg("smooth") = bpm::TetMeshOptions{}.smooth,
             py::arg("flip") = bpm::TetMeshOptions{}.flip, py::arg("progress") = py::none(),
             "bpm-mesh (bpm/tetmesh.h): a tetrahedral mesh of the coarse surface with TetGen (Debian\n"
             "package tetgen), every region given the material its patches name; a new bpm.File in\n"
             "memory with the tet_* arrays, tet_region_material and material_names. quality: TetGen's\n"
             "radius-edge bound (> 1), min_dihedral (degrees) and max_volume as bpm-mesh's options.\n"
             "progress and Ctrl-C as in bpm.simplify. Raises bpm.AlgorithmError for a surface TetGen\n"
             "cannot mesh (open, touching itself), bpm.Error if TetGen is missing or fails.")
        .def("check",
             [](const File& f, bool replay, std::optional<double> max_distance, std::optional<double> max_aspect,
                std::optional<double> min_angle, int threads, const py::object& progress) {
                 // The ranges bpm-check's options have (a value outside was no error but a
                 // check that failed on every triangle).
                 if (max_distance && !(*max_distance >= 0 && std::isfinite(*max_distance)))
                     throw bpm::OptionError("max_distance must be a number >= 0 (a fraction of the bounding-box "
                                            "diagonal, e.g. 0.005), got " + number_text(*max_distance));
                 if (max_aspect && !(*max_aspect >= 2))
                     throw bpm::OptionError("max_aspect must be at least 2 (2 = equilateral), got " +
                                            number_text(*max_aspect));
                 if (min_angle && !(*min_angle >= 0 && *min_angle <= 60))
                     throw bpm::OptionError("min_angle must be between 0 and 60 degrees (60 = equilateral), got " +
                                            number_text(*min_angle));
                 bpm::CheckSelection selection;
                 selection.distortion = true;  // bpm-check's default, 'all'
                 selection.replay = replay;
                 bpm::CheckOptions options;
                 options.max_error = max_distance;
                 options.max_aspect_ratio = max_aspect;
                 options.min_angle_degrees = min_angle;
                 options.threads = thread_count(threads);
                 return f.check(selection, options, progress);
             },
             py::kw_only(), py::arg("replay") = false, py::arg("max_distance") = py::none(),
             py::arg("max_aspect") = py::none(), py::arg("min_angle") = py::none(), py::arg("threads") = 0,
             py::arg("progress") = py::none(),
             "bpm-check (bpm/check.h): format, intersections, topology, junctions, bijectivity, distortion and, with a\n"
             "tet mesh, tetmesh; replay=True replays the recorded removals; max_distance (fraction of the\n"
             "diagonal), max_aspect and min_angle (degrees) add the distance and quality gates. Returns the\n"
             "report bpm-check --json writes (spec/check-report.md) as a dict: 'passed', and 'checks', one\n"
             "dict per check with 'name', 'passed', 'summary', 'problems'. progress and Ctrl-C as in\n"
             "bpm.simplify.")
        .def("smooth",
             [](const File& f, int iterations, double tolerance, double feature_angle, const py::object& progress) {
                 require_feature_angle(feature_angle);
                 bpm::SmoothOptions o;
                 o.iterations = iterations;
                 o.tolerance = tolerance;
                 o.feature_angle_degrees = feature_angle;
                 o.measure_quality = false;  // a report only (bpm-smooth -q leaves it out too)
                 return f.smooth(o, progress);
             },
             py::kw_only(), py::arg("iterations") = bpm::SmoothOptions{}.iterations,
             py::arg("tolerance") = bpm::SmoothOptions{}.tolerance,
             py::arg("feature_angle") = bpm::SmoothOptions{}.feature_angle_degrees, py::arg("progress") = py::none(),
             "bpm-smooth (bpm/smooth.h, paper 2.5): phi smoothed for better shaped refinements, the same\n"
             "coarse surface; a new bpm.File in memory. progress and Ctrl-C as in bpm.simplify.")
        .def("refine_mesh",
             [](const File& f, int levels, bool flat, bool smooth, bool flip, const py::object& progress) {
                 if (levels < 0 || levels > 8) throw py::value_error("levels must be in 0..8 (as bpm-mesh --refine), got " + std::to_string(levels));
                 bpm::TetRefineOptions o;
                 o.levels = levels;
                 o.move_to_surface = !flat;
                 o.repair.smooth = smooth;
                 o.flip = smooth && flip;
                 return f.refine_mesh(o, progress);
             },
             py::arg("levels") = 1, py::kw_only(), py::arg("flat") = false, py::arg("smooth") = true,
             py::arg("flip") = true, py::arg("progress") = py::none(),
             "bpm-mesh --existing --refine LEVELS (bpm/tet_refine.h): the tet mesh refined (each level\n"
             "8 children per tetrahedron), new boundary vertices moved onto S0 through phi as far as no\n"
             "tetrahedron inverts, interior smoothed (smooth) and flipped (flip); flat=True keeps them\n"
             "at the midpoints. A new bpm.File in memory; progress and Ctrl-C as in bpm.simplify.")
        .def("write", [](File& f, const py::object& path) {
                 f.write(py::module_::import("os").attr("fsdecode")(path).cast<std::string>());
             },
             py::arg("path"),
             "Writes the file as a .bpm (bpm/bpm_file.h; atomically: complete or not at all). Raises\n"
             "bpm.OutputError (an OSError) with the file name and what went wrong; bpm.OptionError for a\n"
             "name of a mesh format (.off .obj .stl .ply .msh .vtk .vtp .vtu .mesh .surf).")
        .def_property_readonly("simplify_report", &File::simplify_report,
                               "For a file made by bpm.simplify: dict of input_vertices, output_vertices,\n"
                               "output_triangles, max_error (of the diagonal), worst_aspect_ratio,\n"
                               "target_reached, stop_reason, threads; None for a file read from disk.")
        .def("__repr__", [](const File& f) {
            return "<bpm.File '" + f.path() + "': " + std::to_string(f.num_coarse_triangles()) + " coarse triangles" +
                   (f.has_tetmesh() ? ", tet mesh>" : ">");
        });

    m.def("read", [](const py::object& path) {
              // str or any os.PathLike (pathlib.Path); bytes paths are decoded by os.fsdecode.
              return File(py::module_::import("os").attr("fsdecode")(path).cast<std::string>());
          },
          py::arg("path"),
          "Reads a .bpm file (bpm/bpm_file.h). Raises bpm.InputError (an OSError) with the\n"
          "file name and what is wrong.");
    m.def("simplify", &simplify_arrays, py::arg("vertices"), py::arg("triangles"), py::arg("patches") = py::none(),
          py::kw_only(), py::arg("target_vertices") = 0, py::arg("ratio") = 0.0,
          py::arg("max_error") = std::numeric_limits<double>::infinity(),
          py::arg("max_aspect") = bpm::SimplifyOptions{}.max_aspect_ratio,
          py::arg("feature_angle") = bpm::SimplifyOptions{}.feature_angle_degrees,
          py::arg("keep_corners") = bpm::SimplifyOptions{}.keep_corners, py::arg("threads") = 0, py::arg("units") = "",
          py::arg("progress") = py::none(),
          "bpm-simplify on a surface given as arrays (bpm/simplify.h): vertices (n, 3) floats,\n"
          "triangles (m, 3) integer indices (counter-clockwise seen from the front), patches\n"
          "(m,) integer ids or None. Targets as the tool's: target_vertices, ratio (of the input\n"
          "vertices) or max_error (fraction of the bounding-box diagonal); the first reached\n"
          "stops. Returns a bpm.File in memory (File.write(path) writes it; File.simplify_report\n"
          "says what was achieved). The same coarse surface and phi as bpm-simplify with the same\n"
          "options; threads=0 picks as the tool does, and the result does not depend on it.\n"
          "Raises ValueError for bad arrays and for a surface bpm-simplify would refuse (NaN,\n"
          "degenerate or duplicate triangles, unused or duplicate vertices: repair them first),\n"
          "bpm.AlgorithmError for a surface that intersects itself (bpm.repair_self_intersections may\n"
          "repair it). progress(fraction, stage) is\n"
          "called often (every 256 vertices ranked or removed; fractions rise to 1): returning False\n"
          "stops the run with bpm.Error('cancelled'), an exception it raises stops it and is raised;\n"
          "so does Ctrl-C. The tool's warnings are UserWarnings.");
    m.def("repair_self_intersections", &repair_self_intersections_arrays, py::arg("vertices"), py::arg("triangles"),
          py::arg("patches") = py::none(), py::kw_only(),
          py::arg("max_change") = bpm::SelfIntersectionRepairOptions{}.max_change, py::arg("progress") = py::none(),
          "bpm-simplify --repair-self-intersections on arrays (bpm/self_intersection_repair.h):\n"
          "replaces the triangles around each place the surface crosses itself by a local patch.\n"
          "Returns (vertices, triangles, patches, report): the repaired arrays (kept vertices and\n"
          "triangles first, in order; new ones after), or the input's if nothing was repaired, and a\n"
          "dict with intersecting_pairs, remaining_pairs, removed/added triangles and vertices,\n"
          "largest_change (fraction of the diagonal), topology_change and refused (why nothing\n"
          "changed). All or nothing: no new crossing, and no move beyond max_change. Pass the\n"
          "result to bpm.simplify; phi then maps onto the repaired surface.");
    m.def("set_hdf5_isolation", &bpm::set_hdf5_isolation, py::arg("enabled"),
          "Parse .bpm files in a forked child first, so that a corrupt file that crashes HDF5\n"
          "raises bpm.InputError instead of killing Python (off by default; bpm/bpm_file.h).");
}
