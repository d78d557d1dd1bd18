// libFuzzer target: bpm-info's reader, bpm::read_bpm_info without --distortion, which reads
// a .bpm file through read_bpm_outline (libbpm/src/io/bpm_outline.h: only what bpm-info
// reports, dataset sizes from their extents) and summarizes it, features included.
//
// Properties checked for every input:
//   * read_bpm_info returns or throws bpm::InputError naming the file with a non-empty
//     message (anything else - another exception, a crash, an ASan/UBSan report, a leak,
//     a hang, a huge allocation - is a finding);
//   * every HDF5 identifier it opened is closed again;
//   * the outline agrees with the whole file: where read_bpm (which reads and checks
//     everything) accepts the bytes, read_bpm_info accepts them too and reports what
//     summarize_bpm reports from the file in memory, field by field. (The outline may
//     accept more: what it does not read it does not check.)
//
// read_bpm_info reads a path (bpm-info opens a plain file in place), so every input is
// written to a scratch file first, one per process ($TMPDIR, else /tmp). HDF5 crashes:
// every input is parsed first in a child process (hdf5_child.h).
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <string>

#include "bpm/bpm_file.h"
#include "bpm/bpm_info.h"
#include "bpm/errors.h"
#include "hdf5_child.h"

using bpm_fuzz::fail;

namespace {

// The scratch file of this process (the zygote's children each have their own).
std::string write_scratch(const std::string& bytes) {
    const char* dir = std::getenv("TMPDIR");
    const std::string path =
        std::string(dir && *dir ? dir : "/tmp") + "/bpm-fuzz-outline-" + std::to_string(::getpid()) + ".bpm";
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) fail("cannot write the scratch file", path);
    return path;
}

// Both readers, as in-process below, for the child that runs first.
void parse_in_child(const std::string& bytes) {
    const std::string path = write_scratch(bytes);
    try {
        (void)bpm::read_bpm_info(path);
    } catch (...) {
    }
    try {
        (void)bpm::read_bpm_from_memory(bytes, "fuzz-input");
    } catch (...) {
    }
    ::unlink(path.c_str());
}

// The first field in which two summaries differ, or empty (file and file_bytes aside).
std::string first_difference(const bpm::BpmInfo& a, const bpm::BpmInfo& b) {
    if (a.format_version.major != b.format_version.major || a.format_version.minor != b.format_version.minor)
        return "format_version";
    if (a.units != b.units) return "units";
    if (a.original_vertices != b.original_vertices) return "original_vertices";
    if (a.original_triangles != b.original_triangles) return "original_triangles";
    if (a.coarse_vertices != b.coarse_vertices) return "coarse_vertices";
    if (a.coarse_triangles != b.coarse_triangles) return "coarse_triangles";
    if (a.phi_nodes != b.phi_nodes) return "phi_nodes";
    if (a.phi_pieces != b.phi_pieces) return "phi_pieces";
    if (a.original_point_data != b.original_point_data) return "original_point_data";
    if (a.patches.size() != b.patches.size()) return "patches";
    for (size_t i = 0; i < a.patches.size(); ++i) {
        const bpm::BpmPatchSummary &p = a.patches[i], &q = b.patches[i];
        if (p.id != q.id || p.original_triangles != q.original_triangles || p.coarse_triangles != q.coarse_triangles ||
            p.info.has_value() != q.info.has_value() || (p.info && !(*p.info == *q.info)))
            return "patches[" + std::to_string(i) + "]";
    }
    const bpm::BpmFeatureSummary &f = a.features, &g = b.features;
    if (f.boundary_edges != g.boundary_edges || f.non_manifold_edges != g.non_manifold_edges ||
        f.interface_edges != g.interface_edges || f.crease_edges != g.crease_edges ||
        f.feature_edges != g.feature_edges || f.feature_vertices != g.feature_vertices ||
        f.feature_lines != g.feature_lines || f.feature_loops != g.feature_loops)
        return "features";
    if (a.materials != b.materials) return "materials";
    if (a.tetmesh.has_value() != b.tetmesh.has_value()) return "tetmesh";
    if (a.tetmesh) {
        const bpm::BpmTetMeshSummary &s = *a.tetmesh, &t = *b.tetmesh;
        if (s.vertices != t.vertices || s.tetrahedra != t.tetrahedra || s.boundary_faces != t.boundary_faces ||
            s.level != t.level || s.materials != t.materials || s.regions.size() != t.regions.size())
            return "tetmesh";
        for (size_t i = 0; i < s.regions.size(); ++i)
            if (s.regions[i].id != t.regions[i].id || s.regions[i].tetrahedra != t.regions[i].tetrahedra ||
                s.regions[i].material != t.regions[i].material)
                return "tetmesh.regions[" + std::to_string(i) + "]";
    }
    if (a.simplification_steps != b.simplification_steps) return "simplification_steps";
    if (a.provenance.size() != b.provenance.size()) return "provenance";
    for (size_t i = 0; i < a.provenance.size(); ++i) {
        const bpm::ProvenanceStep &p = a.provenance[i], &q = b.provenance[i];
        if (p.tool != q.tool || p.version != q.version || p.arguments != q.arguments || p.timestamp != q.timestamp)
            return "provenance[" + std::to_string(i) + "]";
    }
    return {};
}

void fuzz_one(const std::string& bytes) {
    if (!bpm_fuzz::survives_in_child(bytes)) return;
    const std::string path = write_scratch(bytes);
    std::optional<bpm::BpmInfo> outline;
    try {
        outline = bpm::read_bpm_info(path);
    } catch (const bpm::InputError& e) {
        if (e.where() != path) fail("InputError does not name the file", e.where());
        if (std::string(e.what()).empty()) fail("InputError without a message");
    }
    bpm_fuzz::check_nothing_open();

    std::optional<bpm::BpmFile> file;
    try {
        file = bpm::read_bpm_from_memory(bytes, "fuzz-input");
    } catch (const bpm::InputError&) {
        // fuzz_read_bpm judges read_bpm's errors
    }
    if (file) {
        if (!outline) fail("read_bpm_info refused a file read_bpm accepted");
        bpm::BpmInfo whole;
        try {
            whole = bpm::summarize_bpm(*file);
        } catch (const std::exception& e) {
            fail("summarize_bpm threw on a file read_bpm accepted:", e.what());
        }
        const std::string field = first_difference(*outline, whole);
        if (!field.empty()) fail("the outline and the whole file disagree in", field);
    }
    ::unlink(path.c_str());
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    bpm_fuzz::start_zygote(parse_in_child);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    fuzz_one(std::string(reinterpret_cast<const char*>(data), size));
    bpm_fuzz::check_nothing_open();
    return 0;
}
