#pragma once
// The bpm file format v2.1 (spec/bpm-format.md is normative): one HDF5 file holding a
// parametrized surface, its provenance, and room for later groups.

#include <optional>
#include <string>
#include <vector>

#include "bpm/parametrization.h"
#include "bpm/patch_info.h"
#include "bpm/simplification_steps.h"
#include "bpm/tetmesh.h"

namespace bpm {

// One step of provenance: which tool ran with which options.
struct ProvenanceStep {
    std::string tool;        // e.g. "bpm-simplify"
    std::string version;     // tool version
    std::string arguments;   // the command line as run
    std::string timestamp;   // ISO 8601 UTC; empty in deterministic mode
};

struct BpmFormatVersion {
    int major = 0;
    int minor = 0;
};

struct BpmFile {
    Parametrization param;
    std::vector<ProvenanceStep> provenance;  // oldest first
    std::string units;                        // free text, e.g. "mm"; empty if unknown
    // The anatomical frame of all coordinates, "LPS" or "RAS" (a surface from a label image,
    // bpm/label_image.h), in the optional root attribute coordinate_frame (format 2.1,
    // spec/bpm-format.md §2); empty if unknown (then not written).
    std::string coordinate_frame;
    // A tetrahedral mesh of the volume bounded by the coarse surface (bpm-mesh), stored
    // in the optional /tetmesh group (spec/tetmesh.md). Files without one are unchanged.
    std::optional<TetMesh> tetmesh;
    // The point removals that made `param.coarse` from `param.original` (bpm-simplify
    // --record-steps), in the optional /simplification_steps group (format 1.1,
    // spec/bpm-format.md §10.1); bpm-check --replay re-applies them. Files without one
    // are unchanged.
    std::optional<SimplificationSteps> simplification_steps;
    // What the input said about the patches of /original and /coarse (names, the materials
    // on their two sides), in the optional /patch_info group (format 1.3, spec/bpm-format.md
    // §5.2), sorted by patch id; empty in older files and when nothing was known.
    std::vector<PatchInfo> patch_info;
    // The format version the file was written in, as read_bpm found it ({0, 0} for a
    // BpmFile made in memory); write_bpm ignores it and writes bpm_format_version().
    BpmFormatVersion format_version;
    // Files of format 1.x only: /phi/node_image as the file stored it, one row per node.
    // param.node_image is always the images recomputed from the node kinds (format 2.0
    // no longer stores them); bpm-check's format check compares the two. Empty for 2.x
    // files and files made in memory; write_bpm ignores it.
    std::vector<Vec3> stored_node_image;
};

BpmFormatVersion bpm_format_version();  // what this build writes

// The functions below use the HDF5 library, which (as packaged by Debian) is not
// thread-safe: do not call them from several threads at the same time.

// Writes the file atomically (temporary name in the same directory, renamed when
// complete); "-" writes the whole file to standard output. Throws bpm::OutputError,
// also when `file` breaks a rule of the spec that the reader would reject (index out of
// range, broken CSR offsets, ...), so that bpm never writes a file it cannot read.
// Deterministic: the same BpmFile gives byte-identical output (no HDF5 timestamps;
// the only time in the file is ProvenanceStep::timestamp, chosen by the caller).
void write_bpm(const std::string& path, const BpmFile& file);
// The exact bytes write_bpm would produce.
std::string write_bpm_to_memory(const BpmFile& file);

// Reads and checks structure (datasets, types, shapes, index ranges, CSR offsets,
// finite values, version). Throws bpm::InputError with the dataset and element at fault.
// "-" reads standard input. gzip-compressed input (a .bpm.gz, or gzip data on standard
// input or in memory, told by its magic bytes) is decompressed first; a truncated or
// corrupt one is an InputError. Accepts any minor version of major versions 1 and 2 and
// ignores groups and attributes it does not know (spec §2, §10); the /VTKHDF group is not
// read. The node images are recomputed from the node kinds (node_images_from_kinds), also
// for 1.x files, whose stored ones go to BpmFile::stored_node_image.
// Does not check the geometry of phi (tiling, orientation, bijectivity): bpm-check does.
// Memory use is bounded by a small multiple of the input size (dataset extents are
// checked against the file size before anything is allocated).
BpmFile read_bpm(const std::string& path);
BpmFile read_bpm_from_memory(const std::string& bytes, const std::string& name);

// Isolation from HDF5 crashes (off by default; every bpm tool turns it on). HDF5 1.10
// reads out of bounds, and sometimes crashes, on some corrupt files. With isolation on,
// read_bpm and read_bpm_from_memory parse the bytes first in a forked child process
// (POSIX fork; the child writes nothing and dies with its parent): if the child crashes
// they throw InputError "the HDF5 library crashed reading it (signal ...): the file is
// corrupt", otherwise they parse the same bytes again in-process. Costs a second parse
// and a fork per read; a library should not fork behind its caller's back, hence opt-in.
void set_hdf5_isolation(bool enabled);

}  // namespace bpm
