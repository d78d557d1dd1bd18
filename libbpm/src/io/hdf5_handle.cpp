#include "io/hdf5_handle.h"

#include <atomic>

namespace bpm::detail {

void silence_hdf5() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }

std::string hdf5_error_text() {
    std::string text;
    H5Ewalk2(
        H5E_DEFAULT, H5E_WALK_DOWNWARD,
        [](unsigned n, const H5E_error2_t* err, void* data) -> herr_t {
            auto* out = static_cast<std::string*>(data);
            if (n == 0 && err && err->desc) *out = err->desc;
            return 0;
        },
        &text);
    H5Eclear2(H5E_DEFAULT);
    return text;
}

unsigned next_image_number() {
    static std::atomic<unsigned> counter{0};
    return counter++;
}

}  // namespace bpm::detail
