// libFuzzer target: the NRRD label image reader (3D Slicer .nrrd / .seg.nrrd: text header,
// raw / gzip / ascii data, space and segment fields) and the surface nets behind it
// (bpm::read_surface_from_memory with SurfaceFormat::Nrrd). See fuzz_surface.h for the
// property checked; scripts/fuzz.sh runs it. gzip data is inflated only up to what the
// voxels need, so a header cannot make the extraction allocate more than a few times that.
#include "fuzz_surface.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return bpm::fuzz::fuzz_surface_reader(data, size, bpm::SurfaceFormat::Nrrd);
}
