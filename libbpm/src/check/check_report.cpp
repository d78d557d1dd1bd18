// CheckResult bookkeeping, running a selection of checks, and the text and JSON forms
// of a report (spec/check-report.md). The JSON is written by hand: no JSON library is
// a dependency of libbpm.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <future>
#include <locale>
#include <mutex>
#include <sstream>
#include <thread>

#include "bpm/check.h"
#include "check/check_internal.h"
#include "core/number_text.h"

namespace bpm {

namespace {

std::string kind_words(const std::string& kind) {
    std::string s = kind;
    for (char& c : s)
        if (c == '_') c = ' ';
    return s;
}

void json_string(std::string& out, const std::string& s) {
    out += '"';
    for (unsigned char c : s) {
        switch (c) {
            case '"': out += "\\\""; break;
            case '\\': out += "\\\\"; break;
            case '\b': out += "\\b"; break;
            case '\f': out += "\\f"; break;
            case '\n': out += "\\n"; break;
            case '\r': out += "\\r"; break;
            case '\t': out += "\\t"; break;
            default:
                if (c < 0x20 || c == 0x7f) {
                    char buf[8];
                    std::snprintf(buf, sizeof buf, "\\u%04x", c);
                    out += buf;
                } else {
                    out += static_cast<char>(c);  // UTF-8 passes through unchanged
                }
        }
    }
    out += '"';
}

void json_number(std::string& out, double v) {
    if (!std::isfinite(v)) {
        out += "null";  // JSON has no NaN or infinity
        return;
    }
    detail::append_round_trip_text(out, v);  // '.' whatever the C locale: JSON has no decimal comma
}

void json_ids(std::string& out, const std::vector<std::pair<std::string, int64_t>>& ids) {
    out += '{';
    for (size_t i = 0; i < ids.size(); ++i) {
        if (i) out += ", ";
        json_string(out, ids[i].first);
        out += ": " + std::to_string(ids[i].second);
    }
    out += '}';
}

void json_value(std::string& out, const WorstValue& v) {
    out += "{\"name\": ";
    json_string(out, v.name);
    out += ", \"value\": ";
    json_number(out, v.value);
    out += ", \"ids\": ";
    json_ids(out, v.ids);
    out += "}";
}

}  // namespace

namespace detail {

void refuse(CheckResult& result, const std::string& reason) {
    result.passed = false;
    result.problem_count += 1;
    result.problems.push_back({{}, "not checked: " + reason});
    result.summary = "not checked: " + reason;
}

std::string format_number(double value) { return significant_text(value, 6); }

}  // namespace detail

std::string CheckProblem::where() const {
    std::string s;
    for (size_t i = 0; i < ids.size(); ++i) {
        if (i) s += ' ';
        s += kind_words(ids[i].first) + " " + std::to_string(ids[i].second);
    }
    return s;
}

std::string CheckProblem::describe() const {
    const std::string w = where();
    return w.empty() ? message : w + ": " + message;
}

int64_t CheckProblem::id(const std::string& kind) const {
    for (auto& [k, v] : ids)
        if (k == kind) return v;
    return -1;
}

void CheckResult::add_problem(CheckProblem problem, size_t max_problems) {
    passed = false;
    ++problem_count;
    if (problems.size() < max_problems) problems.push_back(std::move(problem));
}

int64_t CheckResult::count(const std::string& n) const {
    for (auto& [k, v] : counts)
        if (k == n) return v;
    return -1;
}

bool CheckReport::passed() const {
    for (auto& c : checks)
        if (!c.passed) return false;
    return true;
}

const CheckResult* CheckReport::find(const std::string& n) const {
    for (auto& c : checks)
        if (c.name == n) return &c;
    return nullptr;
}

CheckReport run_checks(const BpmFile& file, const CheckSelection& sel, const CheckOptions& options,
                       const Context& context) {
    const Parametrization& p = file.param;
    int threads = options.threads > 0 ? options.threads : static_cast<int>(std::thread::hardware_concurrency());
    threads = std::max(1, std::min(threads, 2));
    // Log lines may now come from two threads.
    std::mutex log_mutex;
    Context main_context = context, side_context;
    if (context.log) {
        main_context.log = [&](LogLevel level, const std::string& line) {
            std::lock_guard<std::mutex> lock(log_mutex);
            context.log(level, line);
        };
        side_context.log = main_context.log;
    }
    // The structural checks: quick next to bijectivity on large files (reading the
    // connectivity, sorting), so they share the time on a second thread.
    auto structural = [&](const Context& ctx) {
        std::vector<CheckResult> out;
        if (sel.format) out.push_back(check_format(file, options, ctx));
        if (sel.original_intersections)
            out.push_back(check_intersections(p.original, options, ctx, "original-intersections"));
        if (sel.intersections) out.push_back(check_intersections(p.coarse, options, ctx, "intersections"));
        if (sel.topology) out.push_back(check_topology(p, options, ctx));
        if (sel.junctions) out.push_back(check_junctions(file, options, ctx));
        if (sel.tetmesh && file.tetmesh) out.push_back(check_tetmesh(file, options, ctx));
        return out;
    };
    auto others = [&](const Context& ctx) {
        std::vector<CheckResult> out;
        if (sel.bijectivity) out.push_back(check_bijectivity(p, options, ctx));
        if (sel.distortion) out.push_back(check_distortion(p, options, ctx));
        if (options.max_aspect_ratio || options.min_angle_degrees) out.push_back(check_quality(p.coarse, options, ctx));
        if (options.max_error) out.push_back(check_distance(p, options, ctx));
        if (sel.replay) out.push_back(check_replay(file, options, ctx));
        return out;
    };
    std::vector<CheckResult> first, second;
    const bool side_by_side = threads > 1 && (sel.format || sel.original_intersections || sel.intersections ||
                                              sel.topology || sel.junctions || (sel.tetmesh && file.tetmesh));
    if (side_by_side) {
        auto side = std::async(std::launch::async, [&] { return structural(side_context); });
        try {
            second = others(main_context);
        } catch (...) {
            side.wait();  // it reads `file` and the contexts: let it finish first
            throw;
        }
        first = side.get();
    } else {
        first = structural(context);
        second = others(context);
    }
    CheckReport report;
    for (auto* list : {&first, &second})
        for (CheckResult& r : *list) report.checks.push_back(std::move(r));
    return report;
}

CheckReport run_surface_checks(const Surface& surface, const CheckSelection& sel, const CheckOptions& options,
                               const Context& context) {
    CheckReport report;
    if (sel.intersections || sel.original_intersections)
        report.checks.push_back(check_intersections(surface, options, context, "intersections"));
    if (sel.topology) report.checks.push_back(check_topology(surface, options, context));
    if (options.max_aspect_ratio || options.min_angle_degrees)
        report.checks.push_back(check_quality(surface, options, context));
    return report;
}

std::string check_report_to_json(const CheckReport& report) {
    std::string o;
    o += "{\n  \"bpm_check_report\": 1,\n  \"input\": ";
    json_string(o, report.input);
    o += ",\n  \"passed\": ";
    o += report.passed() ? "true" : "false";
    o += ",\n  \"checks\": [";
    for (size_t i = 0; i < report.checks.size(); ++i) {
        const CheckResult& c = report.checks[i];
        o += i ? ",\n    {" : "\n    {";
        o += "\"name\": ";
        json_string(o, c.name);
        o += ", \"passed\": ";
        o += c.passed ? "true" : "false";
        o += ", \"summary\": ";
        json_string(o, c.summary);
        o += ",\n     \"counts\": ";
        json_ids(o, c.counts);
        o += ",\n     \"problem_count\": " + std::to_string(c.problem_count) + ",\n     \"problems\": [";
        for (size_t j = 0; j < c.problems.size(); ++j) {
            const CheckProblem& p = c.problems[j];
            o += j ? ",\n       {" : "\n       {";
            o += "\"where\": ";
            json_string(o, p.where());
            o += ", \"ids\": ";
            json_ids(o, p.ids);
            o += ", \"message\": ";
            json_string(o, p.message);
            o += "}";
        }
        o += c.problems.empty() ? "]" : "\n     ]";
        o += ",\n     \"worst\": ";
        if (c.worst) {
            json_value(o, *c.worst);
        } else {
            o += "null";
        }
        if (!c.measures.empty()) {  // added in the distance check; absent elsewhere
            o += ",\n     \"measures\": [";
            for (size_t j = 0; j < c.measures.size(); ++j) {
                o += j ? ",\n       " : "\n       ";
                json_value(o, c.measures[j]);
            }
            o += "\n     ]";
        }
        o += "}";
    }
    o += report.checks.empty() ? "]\n}\n" : "\n  ]\n}\n";
    return o;
}

std::string check_report_to_text(const CheckReport& report) {
    std::ostringstream o;
    o.imbue(std::locale::classic());  // not a host's global locale: no "12.345", no "0,5"
    for (const CheckResult& c : report.checks) {
        o << (c.passed ? "PASS " : "FAIL ") << c.name << "  ";
        if (c.passed) {
            o << c.summary;
        } else {
            o << c.problem_count << (c.problem_count == 1 ? " problem" : " problems");
            if (!c.problems.empty()) o << "; first: " << c.problems.front().describe();
        }
        o << '\n';
    }
    return o.str();
}

}  // namespace bpm
