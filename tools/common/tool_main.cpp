#include "common/tool_main.h"

#include <unistd.h>

#include <atomic>
#include <cctype>
#include <charconv>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <regex>
#include <utility>
#include <vector>

#include "bpm/bpm_file.h"
#include "bpm/errors.h"
#include "bpm/surface_io.h"
#include "bpm/version.h"

namespace bpm::tools {

namespace {
void print_error(const std::string& tool, const std::string& where, const std::string& message) {
    std::cerr << tool << ": error: ";
    if (!where.empty()) std::cerr << where << ": ";
    std::cerr << message << std::endl;
}
// CLI11's range validators print their bounds with std::to_string, so a negative count
// gave "Value -5 not in range 0.000000 to 1797693134862315708...(309 digits).000000".
// Bounds are shown with %g instead: "Value -5 not in range 0 to 1.79769e+308".
std::string readable_parse_error(const std::string& message) {
    static const std::regex range("not in range (-?[0-9]+\\.?[0-9]*) to (-?[0-9]+\\.?[0-9]*)");
    std::smatch m;
    if (!std::regex_search(message, m, range)) return message;
    const auto shorter = [](const std::string& number) {
        char buffer[32];
        std::snprintf(buffer, sizeof buffer, "%g", std::strtod(number.c_str(), nullptr));
        return std::string(buffer);
    };
    return m.prefix().str() + "not in range " + shorter(m[1].str()) + " to " + shorter(m[2].str()) + m.suffix().str();
}

// The signal that asked the tool to stop (SIGINT, SIGTERM, SIGHUP), 0 if none. The
// handler only records it: the running library call sees it at its next progress poll
// (make_context's callback returns false), unwinds through bpm::Cancelled - which stops
// TetGen and removes its temporary directory - and run() then dies of the same signal.
volatile std::sig_atomic_t g_signal = 0;

extern "C" void die_of_recorded_signal(int) {
    const int sig = g_signal;
    if (sig == 0) return;
    std::signal(sig, SIG_DFL);
    std::raise(sig);  // delivered when this handler returns
}

// When the first stop request came (CLOCK_MONOTONIC; clock_gettime is async-signal-safe).
struct timespec g_first_signal_time {};

extern "C" void record_signal(int sig) {
    struct timespec now {};
    clock_gettime(CLOCK_MONOTONIC, &now);
    if (g_signal != 0) {
        // One request can arrive twice at once: timeout(1) signals the process and then its
        // process group, and a terminal's Ctrl-C reaches the whole foreground group. Only a
        // second request a moment later (a user insisting) stops the tool at once, without
        // the clean-up of the first.
        const double since = double(now.tv_sec - g_first_signal_time.tv_sec) +
                             1e-9 * double(now.tv_nsec - g_first_signal_time.tv_nsec);
        if (since < 1.0) return;
        std::signal(sig, SIG_DFL);
        std::raise(sig);
        return;
    }
    g_first_signal_time = now;
    g_signal = sig;
    // Watchdog: a call that does not poll its progress callback and clean up within 15 s
    // is not waited for (a TetGen holding gigabytes can take seconds to exit under load).
    alarm(15);
}

void install_signal_handlers() {
    for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
        struct sigaction old{};
        sigaction(sig, nullptr, &old);
        if (old.sa_handler == SIG_IGN) continue;  // e.g. nohup, or a background job
        struct sigaction action{};
        action.sa_handler = record_signal;
        sigemptyset(&action.sa_mask);
        sigaction(sig, &action, nullptr);
    }
    struct sigaction alarm_action{};
    alarm_action.sa_handler = die_of_recorded_signal;
    sigemptyset(&alarm_action.sa_mask);
    sigaction(SIGALRM, &alarm_action, nullptr);
}

std::string signal_name(int sig) {
    switch (sig) {
        case SIGINT: return "SIGINT";
        case SIGTERM: return "SIGTERM";
        case SIGHUP: return "SIGHUP";
        default: return "signal " + std::to_string(sig);
    }
}
}  // namespace

bool interrupted() { return g_signal != 0; }

namespace {
// Deprecated spellings registered by note_deprecated.
struct DeprecatedName {
    std::string old_name, new_name, note;
};
std::vector<DeprecatedName> g_deprecated;

// The old spelling stands for the new one: it may not come with it, nor with what the
// new one excludes. Throws CLI::ExcludesError (exit 2).
void check_deprecated(const CLI::App& app) {
    for (const DeprecatedName& d : g_deprecated) {
        const CLI::Option* old_option = app.get_option_no_throw(d.old_name);
        const CLI::Option* new_option = app.get_option_no_throw(d.new_name);
        if (!old_option || old_option->count() == 0 || !new_option) continue;
        if (new_option->count() > 0)
            throw CLI::ValidationError(d.old_name, "is the old name of " + d.new_name +
                                                       ": give only " + d.new_name);
        for (const CLI::Option* excluded : new_option->get_excludes())
            if (excluded->count() > 0)
                throw CLI::ExcludesError(d.old_name, excluded->get_name());
    }
}

void warn_deprecated(const std::string& tool, const CLI::App& app) {
    const CLI::Option* quiet = app.get_option_no_throw("--quiet");
    if (quiet && quiet->count() > 0) return;
    for (const DeprecatedName& d : g_deprecated) {
        const CLI::Option* o = app.get_option_no_throw(d.old_name);
        if (o && o->count() > 0)
            std::cerr << tool << ": warning: " << d.old_name << " is deprecated and will be removed in the next minor "
                      << "version: use " << d.new_name << " (same meaning)" << (d.note.empty() ? "" : "; ") << d.note
                      << std::endl;
    }
}
}  // namespace

void note_deprecated(const std::string& old_name, const std::string& new_name, const std::string& note) {
    g_deprecated.push_back({old_name, new_name, note});
}

CLI::Option* add_format_option(CLI::App& app, std::string& value, const std::string& direction,
                               const std::string& description) {
    CLI::Option* option = app.add_option("--" + direction + "-format", value, description);
    add_deprecated_alias(app, "--format", value, option);
    return option;
}

CLI::Validator decimal_range(double low, double high, bool low_open, bool high_open, const std::string& example) {
    const auto bound = [](double v) {
        char buffer[32];
        std::snprintf(buffer, sizeof buffer, "%g", v);
        return std::string(buffer);
    };
    const std::string range = std::string(low_open ? "(" : "[") + bound(low) + ", " + bound(high) + (high_open ? ")" : "]");
    CLI::Validator v(
        [=](std::string& text) -> std::string {
            char* end = nullptr;
            const double x = std::strtod(text.c_str(), &end);
            const bool number = !text.empty() && end && *end == '\0';
            const bool inside = number && (low_open ? x > low : x >= low) && (high_open ? x < high : x <= high);
            if (inside) return std::string();
            std::string message = "expects a number in " + range + " (e.g. " + example + "), got '" + text + "'";
            if (text.find(',') != std::string::npos) message += ": write the decimal point as a dot";
            return message;
        },
        "NUMBER in " + range);
    return v;
}

CLI::Validator aspect_ratio_limit() {
    return CLI::Validator(
        [](std::string& text) -> std::string {
            char* end = nullptr;
            const double x = std::strtod(text.c_str(), &end);
            if (!text.empty() && end && *end == '\0' && x >= 2) return std::string();
            std::string message = "expects a circumradius/inradius ratio of at least 2 (an equilateral triangle has "
                                  "2, every other triangle more, so a smaller limit fails every triangle; e.g. 30), "
                                  "got '" + text + "'";
            if (text.find(',') != std::string::npos) message += ": write the decimal point as a dot";
            return message;
        },
        "NUMBER >= 2");
}

namespace {
const bool* g_json = nullptr;
std::function<std::string(const ErrorReport&)> g_render_error;
std::string g_error_input;
}  // namespace

void set_error_input(const std::string& name) { g_error_input = name == "-" ? "<stdin>" : name; }  // as the readers say

void set_json_error_report(const bool& json, std::function<std::string(const ErrorReport&)> render) {
    g_json = &json;
    g_render_error = std::move(render);
}

std::string significant_text(double value, int digits) {
    char buffer[64];
    const std::to_chars_result r =
        std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::general, digits);
    return std::string(buffer, r.ptr);
}

std::string json_string(const std::string& text) {
    std::string out = "\"";
    for (const char c : text) {
        switch (c) {
            case '"': out += "\\\""; break;
            case '\\': out += "\\\\"; break;
            case '\n': out += "\\n"; break;
            case '\t': out += "\\t"; break;
            case '\r': out += "\\r"; break;
            default:
                if (static_cast<unsigned char>(c) < 0x20) {
                    char buffer[8];
                    std::snprintf(buffer, sizeof buffer, "\\u%04x", static_cast<unsigned>(c));
                    out += buffer;
                } else {
                    out += c;
                }
        }
    }
    return out + "\"";
}

std::string error_json(const ErrorReport& error) {
    return "{\"file\": " + (error.file.empty() ? std::string("null") : json_string(error.file)) +
           ", \"message\": " + json_string(error.message) + ", \"exit_code\": " + std::to_string(error.exit_code) +
           "}";
}

void add_examples(CLI::App& app, const std::vector<std::string>& examples) {
    std::string text = "\nExamples:\n";
    for (const std::string& e : examples) text += "  " + e + "\n";
    app.footer(text);
}

namespace {
// The table README.md has; every tool's --help ends with it.
const char* const kExitCodeTable =
    "\nExit codes:\n"
    "  0   success (bpm-check: every requested check passed)\n"
    "  1   bpm-check: a check failed\n"
    "  2   bad command line (unknown option, value out of range, refused setting)\n"
    "  3   unreadable or malformed input file\n"
    "  4   output could not be written\n"
    "  5   the algorithm could not proceed on this input\n"
    "  6   an external program (tetgen) is missing, failed or ran out of time\n"
    "  70  internal error (a bug: please report it)\n"
    "  128+N  stopped by signal N (SIGINT 130, SIGTERM 143)\n";
}  // namespace

int run(const std::string& tool, int argc, char** argv, CLI::App& app, const std::function<int()>& body) {
    app.footer(app.get_footer() + kExitCodeTable);
    // Every error: `tool: error: WHERE: message` on stderr, and with --json also the
    // tool's JSON report of it on stdout (a CI job parsing stdout always gets a report).
    // --json counts when it is on the command line even if parsing failed.
    const auto fail = [&](const std::string& where, const std::string& message, int code) {
        end_progress_line();
        print_error(tool, where, message);
        bool json = g_json && *g_json;
        for (int i = 1; i < argc && !json && g_render_error; ++i) json = std::string(argv[i]) == "--json";
        if (json && g_render_error) std::cout << g_render_error(ErrorReport{where, message, code}) << std::endl;
        return code;
    };
    try {
        app.parse(argc, argv);
        check_deprecated(app);
    } catch (const CLI::CallForHelp&) {
        std::cout << app.help();
        return kOk;
    } catch (const CLI::CallForAllHelp&) {
        std::cout << app.help("", CLI::AppFormatMode::All);
        return kOk;
    } catch (const CLI::CallForVersion&) {
        std::cout << version_line(tool) << std::endl;
        return kOk;
    } catch (const CLI::ParseError& e) {
        const int code = fail("", readable_parse_error(e.what()), kUsage);
        std::cerr << "Run '" << tool << " --help' for the options." << std::endl;
        return code;
    }
    warn_deprecated(tool, app);
    // .bpm input is parsed in a child process first, so that a corrupt file that crashes
    // HDF5 ends as exit 3 with a message instead of a segfault (bpm/bpm_file.h).
    set_hdf5_isolation(true);
    install_signal_handlers();
    try {
        const int code = body();
        end_progress_line();  // no prompt after a stage left below 100 %
        return code;
    } catch (const InputNeedsRepair& e) {
        // The library names the repairs; the command line to copy is the tool's to give.
        std::string flags;
        for (const SurfaceRepair r : e.repairs()) flags += " " + repair_flag(r);
        return fail(e.where(), std::string(e.what()) + ". Rerun with:" + flags, kBadInput);
    } catch (const InputError& e) {
        return fail(e.where(), e.what(), kBadInput);
    } catch (const OutputError& e) {
        return fail(e.where(), e.what(), kOutputError);
    } catch (const OptionError& e) {
        return fail("", e.what(), kUsage);
    } catch (const CLI::ParseError& e) {
        return fail("", readable_parse_error(e.what()), kUsage);
    } catch (const OpenSeamError& e) {
        // Found by a tool that reads a .bpm (bpm-mesh): the repair is bpm-simplify's.
        return fail(g_error_input, std::string(e.what()) + ". Rerun bpm-simplify on the input with " +
                                       merge_vertices_within_flag(e.merge_tolerance()),
                    kAlgorithm);
    } catch (const AlgorithmError& e) {
        return fail(g_error_input, e.what(), kAlgorithm);
    } catch (const ExternalToolError& e) {
        return fail("", e.what(), kExternalTool);
    } catch (const Cancelled&) {
        const int sig = g_signal;
        if (sig == 0) return fail("", "cancelled", kAlgorithm);
        fail("", "interrupted by " + signal_name(sig) + ": stopped", 128 + sig);
        std::cout.flush();
        alarm(0);
        std::signal(sig, SIG_DFL);
        std::raise(sig);
        return 128 + sig;
    } catch (const std::bad_alloc&) {
        return fail("", "out of memory", kAlgorithm);
    } catch (const std::exception& e) {
        return fail("", std::string("internal error (please report): ") + e.what(), kInternal);
    }
}

namespace {
// Whether the last thing on stderr is a progress line ("\rstage  42%") without its end:
// the next line printed, on stderr or on stdout (the same terminal), would continue it.
// Atomic: the library may log from its worker threads while the main thread reports progress.
std::atomic<bool> g_progress_line_open{false};
}  // namespace

void end_progress_line() {
    if (!g_progress_line_open.exchange(false)) return;
    std::fprintf(stderr, "\r%65s\r", "");  // as wide as "%-60.60s %3d%%"
    std::fflush(stderr);
}

Context make_context(const std::string& tool, bool verbose, bool quiet) {
    Context context;
    context.log = [tool, verbose, quiet](LogLevel level, const std::string& message) {
        const bool shown = (level == LogLevel::Warning || level == LogLevel::Info) ? !quiet : verbose;
        if (shown) end_progress_line();
        if (level == LogLevel::Warning && !quiet) {
            std::cerr << tool << ": warning: " << message << std::endl;
        } else if (level == LogLevel::Info && !quiet) {
            std::cerr << tool << ": " << message << std::endl;
        } else if (level == LogLevel::Debug && verbose) {
            std::cerr << tool << ": " << message << std::endl;
        }
    };
    // Always set: it is how a signal (install_signal_handlers) stops a running call.
    const bool show = !quiet && isatty(STDERR_FILENO);
    auto last_percent = std::make_shared<int>(-1);
    auto last_stage = std::make_shared<std::string>();
    context.progress = [show, last_percent, last_stage](double fraction, const std::string& stage) {
        if (g_signal != 0) return false;
        if (!show) return true;
        const int percent = static_cast<int>(fraction * 100.0);
        if (percent != *last_percent || stage != *last_stage) {
            *last_percent = percent;
            *last_stage = stage;
            std::fprintf(stderr, "\r%-60.60s %3d%%", stage.c_str(), percent);
            if (percent >= 100) std::fprintf(stderr, "\n");
            g_progress_line_open = percent < 100;
            std::fflush(stderr);
        }
        return true;
    };
    return context;
}

std::string version_line(const std::string& tool) {
    return tool + " " + BPM_VERSION_STRING + " (bpm format " + std::to_string(BPM_FORMAT_VERSION_MAJOR) + "." +
           std::to_string(BPM_FORMAT_VERSION_MINOR) + ")";
}

void add_version_flag(CLI::App& app, const std::string& tool) {
    app.add_flag_callback("--version", [] { throw CLI::CallForVersion(); },
                          "Print the tool version and the bpm format version, then exit");
    (void)tool;
}

void add_output_tool_flags(CLI::App& app, const std::string& tool, bool& deterministic, bool& verbose, bool& quiet) {
    app.add_flag("--deterministic", deterministic,
                 "Leave the timestamp out of the provenance (byte-identical output for identical input)")
        ->group("Output");
    app.add_flag("-v,--verbose", verbose, "More detail on standard error")->group("Output");
    app.add_flag("-q,--quiet", quiet, "Only errors on standard error")->group("Output");
    add_version_flag(app, tool);
}

void group_options(CLI::App& app, const std::string& group, const std::vector<std::string>& names) {
    for (const std::string& name : names) app.get_option(name)->group(group);
}

void require_output_directory(const std::string& path) {
    if (path == "-") return;
    if (path.empty()) throw CLI::ValidationError("--output", "the file name is empty");
    // A directory, or a name ending in '/' (exit 4, as when the writer finds it): the
    // format checks that follow would talk about an empty file name ("'' does not end in
    // .bpm", "unknown output format ''").
    std::error_code ec;
    if (path.back() == '/' || std::filesystem::is_directory(path, ec)) {
        std::string dir = path;
        while (dir.size() > 1 && dir.back() == '/') dir.pop_back();
        throw OutputError(path, "is a directory: -o names the output file (e.g. " + dir + "/NAME.EXT)");
    }
    std::filesystem::path parent = std::filesystem::path(path).parent_path();
    if (parent.empty()) return;
    if (!std::filesystem::is_directory(parent, ec))
        throw CLI::ValidationError("--output", "directory does not exist: " + parent.string());
}

void require_bpm_output(const std::string& path, const std::string& tool) {
    if (path == "-") return;
    const std::string name = std::filesystem::path(path).filename().string();
    std::string extension = std::filesystem::path(name).extension().string();
    for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    std::string lower_name = name;
    for (char& c : lower_name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (lower_name == ".bpm")  // a hidden file without extension, for std::filesystem
        throw CLI::ValidationError("--output", "'" + name + "' has no name before the extension (e.g. -o coarse.bpm)");
    if (extension != ".bpm")
        throw CLI::ValidationError("--output", tool + " writes .bpm files only, and '" + name +
                                                   "' does not end in .bpm (bpm-refine writes surfaces, bpm-mesh "
                                                   "volume meshes)");
}

CLI::Option* add_merge_vertices_within_option(CLI::App& app, SurfaceReadOptions& options) {
    return app
        .add_option("--merge-vertices-within", options.merge_vertices_within,
                    "Merge input vertices closer than TOL (fraction of the bounding-box diagonal, e.g. 1e-8) to "
                    "close seams an export left open by rounding; exact duplicates too")
        ->type_name("TOL")
        ->check(decimal_range(0.0, 1.0, false, true, "1e-8"));
}

std::string merge_vertices_within_flag(double tolerance) {
    return "--merge-vertices-within " + three_digit_text(tolerance);
}

std::string open_seam_warning(const SurfaceReadReport& report) {
    if (!report.open_seam) return {};
    const OpenSeam& seam = *report.open_seam;
    const std::string gap = three_digit_text(seam.gap);
    std::string edges = seam.paired_edges == seam.boundary_edges
                            ? "its " + std::to_string(seam.boundary_edges) + " boundary edges"
                            : std::to_string(seam.paired_edges) + " of its " + std::to_string(seam.boundary_edges) +
                                  " boundary edges";
    std::string w = "the surface is open, and " + edges + " pair up with other boundary edges within " + gap +
                    " of the bounding-box diagonal (first: the edge of vertices " + std::to_string(seam.first_edge[0]) +
                    " and " + std::to_string(seam.first_edge[1]) +
                    "): an open seam, whose two sides have vertices at slightly different positions. Open surfaces "
                    "are accepted, but they enclose no volume (bpm-mesh refuses them)";
    if (report.seam_merge_tolerance > 0)
        w += "; " + merge_vertices_within_flag(report.seam_merge_tolerance) + " closes it";
    return w;
}

std::string repair_flag(SurfaceRepair repair) {
    switch (repair) {
        case SurfaceRepair::TriangulatePolygons: return "--triangulate-polygons";
        case SurfaceRepair::MergeDuplicateVertices: return "--merge-duplicate-vertices";
        case SurfaceRepair::DropUnreferencedVertices: return "--drop-unreferenced-vertices";
        case SurfaceRepair::MergeDuplicateTriangles: return "--merge-duplicate-triangles";
    }
    return "?";
}

void require_input_format_for_stdin(const std::vector<std::string>& inputs, const std::string& format) {
    if (!format.empty()) return;
    for (const std::string& input : inputs)
        if (input == "-")
            throw CLI::ValidationError("--input-format", "standard input ('-') has no file name to tell the format "
                                                         "from: add --input-format FORMAT (off, obj, stl, ply, msh, "
                                                         "vtk, vtp, vtu, surf)");
}

void refuse_binary_to_terminal(const std::string& path, const std::string& kind) {
    if (path != "-" || !isatty(STDOUT_FILENO)) return;
    // No example name: "out.bpm" for a .msh or .vtu output sent users to the wrong format.
    throw CLI::ValidationError("--output", "'-' would write " + kind +
                                               " to the terminal: give a file name (-o FILE) or send standard "
                                               "output into a pipe or file (-o - | ... , -o - > FILE)");
}

void add_encoding_options(CLI::App& app, EncodingFlags& flags) {
    app.add_flag("--binary", flags.binary,
                 "Write .msh (MSH 4.1) and .vtu as binary: VTU 40 % and MSH 75 % of the ASCII size, written faster "
                 "(default: ASCII)");
    app.add_flag("--compress", flags.compress,
                 "Write .vtu as binary, zlib-compressed as by VTK (24 % of the ASCII size; implies --binary)");
}

MeshEncoding output_encoding(const EncodingFlags& flags, const std::string& format, const std::string& path) {
    if (flags.compress) {
        if (format != "vtu")
            throw CLI::ValidationError("--compress", "only .vtu output is compressed, not " + format +
                                                         " (use --binary alone for .msh)");
        refuse_binary_to_terminal(path, "compressed VTU data");
        return MeshEncoding::BinaryZlib;
    }
    if (!flags.binary) return MeshEncoding::Ascii;
    if (format == "msh" || format == "vtu") {
        refuse_binary_to_terminal(path, "binary " + format + " data");
        return MeshEncoding::Binary;
    }
    if (format == "stl" || format == "ply" || format == "bpm") return MeshEncoding::Binary;  // binary anyway
    throw CLI::ValidationError("--binary", format + " has no binary form: --binary writes msh (MSH 4.1) and vtu " +
                                               "(stl, ply and bpm are always binary)");
}

std::string utc_timestamp() {
    std::time_t now = std::time(nullptr);
    std::tm utc{};
    gmtime_r(&now, &utc);
    char buffer[32];
    std::strftime(buffer, sizeof buffer, "%Y-%m-%dT%H:%M:%SZ", &utc);
    return buffer;
}

std::string command_line(int argc, char** argv) {
    std::string line;
    for (int i = 0; i < argc; ++i) {
        if (i) line += ' ';
        line += argv[i];
    }
    return line;
}

std::string bpm_from_surface_hint(const std::string& path) {
    const std::filesystem::path p(path);
    return "make one with bpm-simplify " + path + " -o " + p.stem().string() + ".bpm";
}

void rethrow_with_mesh_file_hint(const InputError& error, const std::string& path, const std::string& hint) {
    std::error_code ec;
    if (path == "-" || !surface_format_from_path(path) || !std::filesystem::is_regular_file(path, ec))
        throw;  // the caught exception, as it was
    throw InputError(error.where(), std::string(error.what()) + ". It looks like a surface or mesh file, not a .bpm (" +
                                        (hint.empty() ? bpm_from_surface_hint(path) : hint) + ")");
}

BpmFile read_bpm_input(const std::string& path, const std::string& hint) {
    try {
        return read_bpm(path);
    } catch (const InputError& e) {
        rethrow_with_mesh_file_hint(e, path, hint);
    }
}

}  // namespace bpm::tools
