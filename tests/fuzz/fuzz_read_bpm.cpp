// libFuzzer target: bpm::read_bpm_from_memory, then everything bpm-check runs on what it
// read, then a write/read round trip.
//
// Properties checked for every input:
//   * read_bpm_from_memory returns or throws bpm::InputError naming the input with a
//     non-empty message (anything else - another exception, a crash, an ASan/UBSan
//     report, a leak, a hang, a huge allocation - is a finding);
//   * every HDF5 identifier it opened is closed again;
//   * on a file that reads, every check (format, original-intersections, intersections,
//     topology, bijectivity, quality, distance, replay) and both report renderers run
//     without throwing: checks report bad data, they never throw on it (bpm/check.h);
//   * a file that reads can be written (write_bpm refuses exactly what read_bpm
//     refuses), the written bytes read back, and writing that again gives the same
//     bytes (determinism).
//
// HDF5 crashes: every input is parsed first in a child process (hdf5_child.h); a crash
// there in HDF5 skips the input, a crash anywhere else is a finding.
#include <cstdint>
#include <string>

#include "bpm/bpm_file.h"
#include "bpm/check.h"
#include "bpm/errors.h"
#include "bpm/tetmesh.h"
#include "hdf5_child.h"

using bpm_fuzz::fail;

namespace {

void fuzz_one(const std::string& bytes) {
    static const char* kName = "fuzz-input";
    if (!bpm_fuzz::survives_in_child(bytes)) return;
    bpm::BpmFile file;
    try {
        file = bpm::read_bpm_from_memory(bytes, kName);
    } catch (const bpm::InputError& e) {
        if (e.where() != kName) fail("InputError does not name the input", e.where());
        if (std::string(e.what()).empty()) fail("InputError without a message");
        return;
    }

    bpm::CheckSelection selection;
    selection.original_intersections = true;
    selection.replay = true;  // "not checked" without a /simplification_steps record
    bpm::CheckOptions options;
    options.max_aspect_ratio = 10;
    options.min_angle_degrees = 5;
    options.error_sample_spacing = 0.05;  // coarse sampling: a tiny file may hold huge triangles
    try {
        // Unconditionally: a node image of 8e252 once made check_distance hand an
        // overflowed NaN to GMP (SIGFPE; found by this target); it now refuses such files.
        options.max_error = 0.01;
        bpm::CheckReport report = bpm::run_checks(file, selection, options);
        report.input = kName;
        (void)bpm::check_report_to_json(report);
        (void)bpm::check_report_to_text(report);
        if (file.tetmesh) (void)bpm::tetmesh_stats(*file.tetmesh);
    } catch (const std::exception& e) {
        fail("a check threw on a file read_bpm accepted:", e.what());
    }

    std::string written;
    try {
        written = bpm::write_bpm_to_memory(file);
    } catch (const std::exception& e) {
        fail("write_bpm refused a file read_bpm accepted:", e.what());
    }
    try {
        const bpm::BpmFile again = bpm::read_bpm_from_memory(written, "round-trip");
        if (bpm::write_bpm_to_memory(again) != written) fail("writing is not deterministic across a round trip");
    } catch (const bpm::Error& e) {
        fail("the written file does not read back:", e.what());
    }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    bpm_fuzz::start_zygote([](const std::string& bytes) { (void)bpm::read_bpm_from_memory(bytes, "fuzz-input"); });
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    fuzz_one(std::string(reinterpret_cast<const char*>(data), size));
    bpm_fuzz::check_nothing_open();
    return 0;
}
