#pragma once
// The bpm file format v1 (spec/bpm-format.md is normative): one HDF5 file holding a
// parametrized surface, its provenance, and room for later groups.

#include <string>
#include <vector>

#include "bpm/parametrization.h"

namespace bpm {

// One step of provenance: which tool ran with which options.
struct ProvenanceStep {
    std::string tool;        // e.g. "bpm-simplify"
    std::string version;     // tool version
    std::string arguments;   // the command line as run
    std::string timestamp;   // ISO 8601 UTC; empty in deterministic mode
};

struct BpmFile {
    Parametrization param;
    std::vector<ProvenanceStep> provenance;  // oldest first
    std::string units;                        // free text, e.g. "mm"; empty if unknown
};

struct BpmFormatVersion {
    int major = 0;
    int minor = 0;
};
BpmFormatVersion bpm_format_version();  // what this build writes

// Writes the file atomically (temporary name in the same directory, renamed when
// complete); "-" writes the whole file to standard output. Throws bpm::OutputError.
void write_bpm(const std::string& path, const BpmFile& file);
// The exact bytes write_bpm would produce.
std::string write_bpm_to_memory(const BpmFile& file);

// Reads and checks structure (datasets, types, shapes, index ranges, CSR offsets,
// finite values, version). Throws bpm::InputError with the dataset and element at fault.
// "-" reads standard input.
BpmFile read_bpm(const std::string& path);
BpmFile read_bpm_from_memory(const std::string& bytes, const std::string& name);

}  // namespace bpm
