#pragma once
// The few exception types libbpm throws. Tools map each to one exit code
// (tools/common/tool_main.h); the library itself never prints.

#include <stdexcept>
#include <string>

namespace bpm {

// Base of every error libbpm reports on purpose.
class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// The input (a surface file, a .bpm file, a stream) is unreadable or malformed.
// `where` names the file (or "-" for standard input); the message names the
// line, byte offset or element and what is wrong with it.
class InputError : public Error {
public:
    InputError(std::string where, const std::string& message)
        : Error(message), where_(std::move(where)) {}
    const std::string& where() const { return where_; }

private:
    std::string where_;
};

// An output could not be written (missing directory, full disk, read-only).
class OutputError : public Error {
public:
    OutputError(std::string where, const std::string& message)
        : Error(message), where_(std::move(where)) {}
    const std::string& where() const { return where_; }

private:
    std::string where_;
};

// Options that contradict each other or are out of range, detected by the library.
class OptionError : public Error {
public:
    using Error::Error;
};

// An algorithm cannot proceed on this (valid) input, e.g. a surface TetGen cannot mesh.
class AlgorithmError : public Error {
public:
    using Error::Error;
};

// A surface that must be closed (to enclose a volume) is open along a seam whose two
// sides are apart by rounding only: merging the input's vertices within
// merge_tolerance of its bounding-box diagonal closes it (SurfaceReadOptions::
// merge_vertices_within). The tool names the option that does.
class OpenSeamError : public AlgorithmError {
public:
    OpenSeamError(const std::string& message, double merge_tolerance)
        : AlgorithmError(message), merge_tolerance_(merge_tolerance) {}
    double merge_tolerance() const { return merge_tolerance_; }

private:
    double merge_tolerance_;
};

// An external program (tetgen) is missing or failed.
class ExternalToolError : public Error {
public:
    using Error::Error;
};

// The user cancelled through the progress callback.
class Cancelled : public Error {
public:
    Cancelled() : Error("cancelled") {}
};

}  // namespace bpm
