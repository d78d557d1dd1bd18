// libFuzzer target: the NIfTI-1 label image reader and the surface nets behind it
// (bpm::read_surface_from_memory with SurfaceFormat::Nifti). See fuzz_surface.h for the
// property checked; scripts/fuzz.sh runs it. The voxel data must fit the input, so a
// header cannot make the extraction allocate more than a few times the input's size.
#include "fuzz_surface.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return bpm::fuzz::fuzz_surface_reader(data, size, bpm::SurfaceFormat::Nifti);
}
