#pragma once
// Isolation from HDF5 crashes for the fuzz targets that read .bpm files (fuzz_read_bpm,
// fuzz_read_bpm_outline): HDF5 (not instrumented, not ours) crashes on some corrupt files,
// so every input is parsed first in a child process whose sanitizer report is kept and
// classified (hdf5_child.cpp). Only inputs the child parsed cleanly go on to the
// in-process parse, with coverage and leak checks.

#include <string>

namespace bpm_fuzz {

// What the child runs on each input; any exception it throws is ignored there (the
// in-process parse judges it).
using ParseFunction = void (*)(const std::string& bytes);

// Forks the "zygote" that forks one child per input. Call once, from
// LLVMFuzzerInitialize, before the fuzzer's memory grows.
void start_zygote(ParseFunction parse);

// Parses `bytes` in a child process. True: the child survived (parse in-process next).
// False: HDF5 crashed or hung on this input (skip it; counted on stderr as "HDF5 crash
// skipped" and saved to $BPM_FUZZ_HDF5_CRASH_DIR if set). Aborts (a finding) when the
// child crashed or hung anywhere else.
bool survives_in_child(const std::string& bytes);

// Every HDF5 identifier the library opened must be closed again, whatever the input.
void check_nothing_open();

// A fuzz property is violated: print it and abort (libFuzzer keeps the input).
[[noreturn]] void fail(const char* what, const std::string& detail = "");

}  // namespace bpm_fuzz
