#pragma once
// The one place that maps libbpm's exceptions to exit codes and prints errors.
// Every bpm tool's main() is:   return bpm::tools::run("bpm-verb", argc, argv, body);

#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bpm/bpm_file.h"
#include "bpm/context.h"
#include "bpm/errors.h"
#include "bpm/mesh_encoding.h"
#include "bpm/surface_io.h"

namespace bpm::tools {

// Exit codes shared by all tools (README.md lists the same table).
enum ExitCode : int {
    kOk = 0,
    kCheckFailed = 1,    // bpm-check: a requested check failed
    kUsage = 2,          // bad command line
    kBadInput = 3,       // unreadable or malformed input file
    kOutputError = 4,    // output could not be written
    kAlgorithm = 5,      // the algorithm could not proceed on this input
    kExternalTool = 6,   // tetgen missing or failed
    kInternal = 70,      // a bug: an unexpected exception
};

// Runs `body` (which parses with the given app and does the work), catching every
// exception and printing `tool: error: WHERE: message` on stderr. Turns on the HDF5
// crash isolation of .bpm reading (bpm::set_hdf5_isolation) first.
int run(const std::string& tool, int argc, char** argv, CLI::App& app, const std::function<int()>& body);

// True once SIGINT, SIGTERM or SIGHUP arrived: run() installs handlers that record the
// signal; the progress callback of make_context then stops the running library call
// (bpm::Cancelled, which stops TetGen and removes temporary files on the way), and run()
// ends by dying of that signal (exit status 128 + N in a shell). A second signal, or a
// call that has not stopped within 15 s, ends the tool at once.
bool interrupted();

// An error that ended a tool: the file it concerns ("" if none, "-" for standard input),
// the message, and the exit code the tool returns.
struct ErrorReport {
    std::string file;
    std::string message;
    int exit_code = 0;
};

// For tools with --json: when `json` is true (or "--json" is on the command line and
// parsing failed), run() prints render(error) on stdout for every error, besides the
// usual line on stderr. `json` must outlive run().
void set_json_error_report(const bool& json, std::function<std::string(const ErrorReport&)> render);

// The input an algorithm error (exit 5: "cannot proceed on this input") concerns, so that
// it is reported as `tool: error: FILE: message` like the input errors: the library's
// AlgorithmError names no file. Call it once the input is known ("-" for standard input).
void set_error_input(const std::string& name);

// `text` as a JSON string literal, quotes included (control characters escaped; UTF-8
// passed through).
std::string json_string(const std::string& text);

// `value` with `digits` (1..17) significant digits: what printf's "%.<digits>g" writes in
// the "C" locale, whatever locale is set (std::to_chars). The tools' one number formatter
// (libbpm's, core/number_text.h, is internal): 17 digits read back to the same double
// (JSON), 3 are for ratios and tolerances in messages.
std::string significant_text(double value, int digits);
inline std::string round_trip_text(double value) { return significant_text(value, 17); }
inline std::string three_digit_text(double value) { return significant_text(value, 3); }

// {"file": "..." or null, "message": "...", "exit_code": N}
std::string error_json(const ErrorReport& error);

// A Context whose log goes to stderr: "tool: warning: ..." and info lines unless quiet
// (-q prints errors only), debug lines when verbose;
// and whose progress is shown on stderr only when stderr is a terminal.
Context make_context(const std::string& tool, bool verbose, bool quiet);

// Erases a progress line that stopped short of 100 % (a stage that ended early), so that
// what comes next starts a line of its own: the context's log lines and errors call it;
// a tool calls it before it prints its report on standard output (the same terminal).
void end_progress_line();

// "bpm-verb 0.1.0 (bpm format 1.0)"
std::string version_line(const std::string& tool);

// Adds --version to the app (prints version_line and exits 0).
void add_version_flag(CLI::App& app, const std::string& tool);

// The flags every tool that writes a file has: --deterministic, -v/--verbose,
// -q/--quiet and --version.
void add_output_tool_flags(CLI::App& app, const std::string& tool, bool& deterministic, bool& verbose, bool& quiet);

// Puts the options named (any of their names, e.g. "--levels") in the --help group
// `group`; groups are listed in the order of their first option. Unknown names throw.
void group_options(CLI::App& app, const std::string& group, const std::vector<std::string>& names);

// The one name for a file format option in every tool: --input-format (direction
// "input") or --output-format ("output"), as meshio names them. The old --format is kept
// as a deprecated alias with this tool's meaning (a warning names the new option).
CLI::Option* add_format_option(CLI::App& app, std::string& value, const std::string& direction,
                               const std::string& description);

// Records that `old_name` is a deprecated spelling of `new_name`: after parsing, run()
// refuses the two together and the old one together with an option the new one excludes
// (exit 2), and warns on stderr (not with -q: it is a warning) when the old one is used,
// naming the new option and adding `note` (e.g. what the old name means in other tools).
void note_deprecated(const std::string& old_name, const std::string& new_name, const std::string& note = "");

// Keeps `old_name` working for one minor version as a deprecated alias of `replacement`
// (an option already added): it sets the same variable, is listed under "Deprecated" in
// --help, and run() checks and warns as note_deprecated says (no CLI11 `excludes`, which
// would name the old spelling in the replacement's help line). Returns the alias, for
// its validators and its count.
template <typename T>
CLI::Option* add_deprecated_alias(CLI::App& app, const std::string& old_name, T& value, CLI::Option* replacement,
                                  const std::string& note = "") {
    const std::string new_name = replacement->get_name();
    CLI::Option* alias = app.add_option(old_name, value, "Deprecated: the old name of " + new_name)->group("Deprecated");
    note_deprecated(old_name, new_name, note);
    return alias;
}

// Validator for a number in a range, open or closed at each end, whose message says the
// expected range with an example and, for "0,1", that the decimal point is a dot.
CLI::Validator decimal_range(double low, double high, bool low_open, bool high_open, const std::string& example);

// Validator for a limit of the aspect ratio circumradius / inradius (bpm/geometry.h,
// aspect_ratio): at least 2, which an equilateral triangle has and every other triangle
// exceeds, so that a smaller limit fails every triangle (bpm-check --max-aspect 1 did).
CLI::Validator aspect_ratio_limit();

// Throws CLI::ValidationError if `path` is empty or its directory does not exist, and
// OutputError if it is a directory (or ends in '/'); checked before any expensive work
// and before the output format is derived from the name. "-" is always accepted.
void require_output_directory(const std::string& path);

// Throws CLI::ValidationError unless `path` is "-" or ends in .bpm (any case): for the
// tools that write nothing but .bpm files, so that "-o coarse.off" is a usage error
// (exit 2, before any work) instead of an HDF5 file named .off.
void require_bpm_output(const std::string& path, const std::string& tool);

// Throws CLI::ValidationError (exit 2) when `path` is "-" and standard output is a
// terminal: binary data (`kind`, e.g. "binary .bpm (HDF5) data") would only garble it,
// as gzip refuses to. Checked before any work.
void refuse_binary_to_terminal(const std::string& path, const std::string& kind);

// --binary and --compress, the same in every tool that writes .msh or .vtu: how that
// output stores its numbers (bpm/mesh_encoding.h). ASCII is the default.
struct EncodingFlags {
    bool binary = false;    // --binary: MSH 4.1 binary, VTU appended raw data
    bool compress = false;  // --compress: VTU appended data in zlib blocks (implies --binary)
};
void add_encoding_options(CLI::App& app, EncodingFlags& flags);

// The encoding `flags` ask for, for the output format named `format` ("msh", "vtu", "off",
// ...; lower case). Throws CLI::ValidationError (exit 2, before any work) when the format
// has no such encoding, naming the formats that do; formats that are binary anyway (stl,
// ply, bpm) accept --binary. A binary encoding to `path` "-" on a terminal is refused
// (refuse_binary_to_terminal).
MeshEncoding output_encoding(const EncodingFlags& flags, const std::string& format, const std::string& path);

// The command-line flag of a surface repair (bpm-simplify's; bpm-check --surface has the
// same names), e.g. "--merge-duplicate-vertices". run() appends them to an
// InputNeedsRepair error as "Rerun with: --flag --flag".
std::string repair_flag(SurfaceRepair repair);

// --merge-vertices-within TOL (SurfaceReadOptions::merge_vertices_within), the same in
// every tool that reads surfaces.
CLI::Option* add_merge_vertices_within_option(CLI::App& app, SurfaceReadOptions& options);

// "--merge-vertices-within 1e-08": the repair for a seam open by rounding, with the
// tolerance that closes it (SurfaceReadReport::seam_merge_tolerance, OpenSeamError).
std::string merge_vertices_within_flag(double tolerance);

// The warning for the open seam a read found (SurfaceReadReport::open_seam), naming the
// flag that closes it when there is one; empty when the read found none.
std::string open_seam_warning(const SurfaceReadReport& report);

// Throws CLI::ValidationError (exit 2) naming --input-format when one of `inputs` is "-"
// and `format` is empty: standard input has no extension to tell the format from.
void require_input_format_for_stdin(const std::vector<std::string>& inputs, const std::string& format);

// Sets the --help footer to these example command lines (run() appends the exit-code
// table to every tool's help).
void add_examples(CLI::App& app, const std::vector<std::string>& examples);

// read_bpm(path), but when an existing file cannot be read as a .bpm and its name says it
// is a surface or mesh file (femur.off, tets.vtu: what newcomers pass first), the error
// adds "It looks like a surface or mesh file, not a .bpm (HINT)", HINT saying what this
// tool needs and how to make it (default: bpm_from_surface_hint(path)).
BpmFile read_bpm_input(const std::string& path, const std::string& hint = "");

// The same for any reader of a .bpm; call it in the handler that caught `error`: throws
// it again with the hint when `path` names a surface or mesh file, else rethrows it unchanged.
[[noreturn]] void rethrow_with_mesh_file_hint(const InputError& error, const std::string& path,
                                              const std::string& hint = "");

// "make one with bpm-simplify PATH -o STEM.bpm"
std::string bpm_from_surface_hint(const std::string& path);

// Current time as ISO 8601 UTC, for provenance.
std::string utc_timestamp();

// The command line as one string, for provenance.
std::string command_line(int argc, char** argv);

}  // namespace bpm::tools
