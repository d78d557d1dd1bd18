// libFuzzer target: the Amira HyperSurface reader (bpm::read_surface_from_memory with
// SurfaceFormat::Surf). See fuzz_surface.h for the property checked; scripts/fuzz.sh runs it.
#include "fuzz_surface.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return bpm::fuzz::fuzz_surface_reader(data, size, bpm::SurfaceFormat::Surf);
}
