#include "common/tool_main.h"

#include <unistd.h>

#include <cstdio>
#include <ctime>
#include <filesystem>
#include <iostream>

#include "bpm/errors.h"
#include "bpm/version.h"

namespace bpm::tools {

namespace {
void print_error(const std::string& tool, const std::string& where, const std::string& message) {
    std::cerr << tool << ": error: ";
    if (!where.empty()) std::cerr << where << ": ";
    std::cerr << message << std::endl;
}
}  // namespace

int run(const std::string& tool, int argc, char** argv, CLI::App& app, const std::function<int()>& body) {
    try {
        app.parse(argc, argv);
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
        print_error(tool, "", e.what());
        std::cerr << "Run '" << tool << " --help' for the options." << std::endl;
        return kUsage;
    }
    try {
        return body();
    } catch (const InputError& e) {
        print_error(tool, e.where(), e.what());
        return kBadInput;
    } catch (const OutputError& e) {
        print_error(tool, e.where(), e.what());
        return kOutputError;
    } catch (const OptionError& e) {
        print_error(tool, "", e.what());
        return kUsage;
    } catch (const CLI::ParseError& e) {
        print_error(tool, "", e.what());
        return kUsage;
    } catch (const AlgorithmError& e) {
        print_error(tool, "", e.what());
        return kAlgorithm;
    } catch (const ExternalToolError& e) {
        print_error(tool, "", e.what());
        return kExternalTool;
    } catch (const Cancelled&) {
        print_error(tool, "", "cancelled");
        return kAlgorithm;
    } catch (const std::bad_alloc&) {
        print_error(tool, "", "out of memory");
        return kAlgorithm;
    } catch (const std::exception& e) {
        print_error(tool, "", std::string("internal error (please report): ") + e.what());
        return kInternal;
    }
}

Context make_context(const std::string& tool, bool verbose, bool quiet) {
    Context context;
    context.log = [tool, verbose, quiet](LogLevel level, const std::string& message) {
        if (level == LogLevel::Warning) {
            std::cerr << tool << ": warning: " << message << std::endl;
        } else if (level == LogLevel::Info && !quiet) {
            std::cerr << tool << ": " << message << std::endl;
        } else if (level == LogLevel::Debug && verbose) {
            std::cerr << tool << ": " << message << std::endl;
        }
    };
    if (!quiet && isatty(STDERR_FILENO)) {
        auto last = std::make_shared<int>(-1);
        context.progress = [last](double fraction, const std::string& stage) {
            int percent = static_cast<int>(fraction * 100.0);
            if (percent != *last) {
                *last = percent;
                std::fprintf(stderr, "\r%-60.60s %3d%%", stage.c_str(), percent);
                if (percent >= 100) std::fprintf(stderr, "\n");
                std::fflush(stderr);
            }
            return true;
        };
    }
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
                 "Leave the timestamp out of the provenance (byte-identical output for identical input)");
    app.add_flag("-v,--verbose", verbose, "More detail on standard error");
    app.add_flag("-q,--quiet", quiet, "Only errors on standard error");
    add_version_flag(app, tool);
}

void require_output_directory(const std::string& path) {
    if (path.empty() || path == "-") return;
    std::filesystem::path parent = std::filesystem::path(path).parent_path();
    if (parent.empty()) return;
    std::error_code ec;
    if (!std::filesystem::is_directory(parent, ec))
        throw CLI::ValidationError("--output", "directory does not exist: " + parent.string());
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

}  // namespace bpm::tools
