// libFuzzer target: the MetaImage label image reader (.mha: "Key = Value" header, voxels
// after ElementDataFile = LOCAL, raw or zlib-compressed) and the surface nets behind it
// (bpm::read_surface_from_memory with SurfaceFormat::MetaImage; from memory a header that
// names a separate data file is refused). See fuzz_surface.h for the property checked;
// scripts/fuzz.sh runs it. Compressed data is inflated only up to what the voxels need.
#include "fuzz_surface.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return bpm::fuzz::fuzz_surface_reader(data, size, bpm::SurfaceFormat::MetaImage);
}
