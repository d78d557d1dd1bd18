#pragma once
// Label image readers (NIfTI-1, ...): each parses its format into a bpm::LabelImage;
// label_image_reader_output() then extracts the multi-material surface (bpm/label_image.h)
// for read_surface. Internal, like surface_readers.h.

#include <algorithm>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "bpm/context.h"
#include "bpm/label_image.h"
#include "io/surface_readers.h"

namespace bpm::detail {

// The voxel types label image files store.
enum class VoxelType { U8, I8, I16, U16, I32, U32, F32, F64 };
int voxel_type_size(VoxelType type);
const char* voxel_type_name(VoxelType type);  // "uint8", ...

// Fills the compact labels of `image` (LabelImage::label_values and label_index8/16;
// image.size set) from its voxels of `type` at `data` (byte-swapped when `swap`), each value scaled by slope * x + inter when those are not 1 and 0. A value
// that is not an integer, or beyond int32, is an InputError naming the voxel (i, j, k).
// `scaled_by` names the scaling for that message ("scl_slope/scl_inter"), empty if none.
// More than 65536 distinct labels is an InputError too.
void decode_labels(const unsigned char* data, VoxelType type, bool swap, double slope, double inter,
                   const std::string& scaled_by, LabelImage& image, const std::string& name);

// NIfTI-1 single file (magic "n+1"), already decompressed. Details in read_nifti.cpp.
// `notes`, if given, receives a line describing the image. \throw InputError naming the
// file and the header field or voxel that is wrong.
LabelImage read_nifti_image(std::string_view bytes, const std::string& name, std::vector<std::string>* notes = nullptr);

// NRRD (3D Slicer .nrrd / .seg.nrrd), attached data, encodings raw, gzip and ascii.
// Details in read_nrrd.cpp. Segment names of a .seg.nrrd become LabelImage::names.
LabelImage read_nrrd_image(std::string_view bytes, const std::string& name, std::vector<std::string>* notes = nullptr);

// Reads the data file a MetaImage header names (ElementDataFile), given as written in the
// header; throws InputError when it cannot.
using DataFileLoader = std::function<std::string(const std::string& file_name)>;

// MetaImage (.mha, or .mhd with its data file read through `load`; null: only LOCAL data).
// Details in read_metaimage.cpp. World coordinates are LPS (as ITK's).
LabelImage read_metaimage_image(std::string_view bytes, const std::string& name, const DataFileLoader& load,
                                std::vector<std::string>* notes = nullptr);

// The surface of `image` (label_image_surface with `options`) as a reader's output:
// patches, patch_info (one oriented row per label pair), the frame of its coordinates, and
// notes with the counts and the frame. An image of background only is an InputError
// (there is no surface), as is a label_image_problem.
ReaderOutput label_image_reader_output(LabelImage image, const std::string& name, const LabelSurfaceOptions& options,
                                       const Context& context, std::vector<std::string> notes);

// Text of the key/value headers of NRRD and MetaImage: `s` without leading and trailing
// white space; ASCII lower case; the fields between runs of white space.
inline std::string header_trim(std::string_view s) {
    size_t a = 0, b = s.size();
    while (a < b && is_space(s[a])) ++a;
    while (b > a && is_space(s[b - 1])) --b;
    return std::string(s.substr(a, b - a));
}
inline std::string header_lower(std::string s) {
    for (char& c : s)
        if (c >= 'A' && c <= 'Z') c = char(c - 'A' + 'a');
    return s;
}
// The lines of a text header one at a time (ended by \n or \r\n, the last one perhaps by
// the end of the bytes), numbered from 1 for messages; offset() is where the next line,
// or after the header's last line the data, starts.
class HeaderLines {
public:
    explicit HeaderLines(std::string_view bytes) : bytes_(bytes) {}
    bool next(std::string_view& line) {
        if (offset_ >= bytes_.size()) return false;
        size_t end = bytes_.find('\n', offset_);
        if (end == std::string_view::npos) end = bytes_.size();
        line = bytes_.substr(offset_, end - offset_);
        offset_ = std::min(end + 1, bytes_.size());
        ++number_;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        return true;
    }
    int64_t number() const { return number_; }  // of the line next() returned last
    size_t offset() const { return offset_; }

private:
    std::string_view bytes_;
    size_t offset_ = 0;
    int64_t number_ = 0;
};
inline std::vector<std::string> header_words(const std::string& s) {
    std::vector<std::string> out;
    size_t i = 0;
    while (i < s.size()) {
        while (i < s.size() && is_space(s[i])) ++i;
        size_t j = i;
        while (j < s.size() && !is_space(s[j])) ++j;
        if (j > i) out.push_back(s.substr(i, j - i));
        i = j;
    }
    return out;
}

}  // namespace bpm::detail
