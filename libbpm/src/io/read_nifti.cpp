// NIfTI-1 label images (.nii, .nii.gz; gzip is undone before this reader sees the bytes):
// the 348-byte header, then the voxels from vox_offset ("n+1" single files only; a
// ".hdr"/".img" pair, magic "ni1", is refused with that said).
//
// Header fields used (byte offset: type name): 0 int32 sizeof_hdr (348; its byte order
// tells the file's), 40 int16 dim[8], 70 int16 datatype, 72 int16 bitpix, 76 float32
// pixdim[8], 108 float32 vox_offset, 112/116 float32 scl_slope/scl_inter, 123 xyzt_units,
// 252/254 int16 qform_code/sform_code, 256-276 float32 quatern_b/c/d, qoffset_x/y/z,
// 280-327 float32 srow_x/y/z[4], 344 char magic[4].
//
// Voxel to model space, as the NIfTI-1 standard orders the methods: sform_code > 0 -> the
// srow affine; else qform_code > 0 -> the quaternion, pixdim and qfac (pixdim[0]); else
// pixdim scaling alone. The model space is the file's: RAS+ (LabelImage::frame Ras), in
// its units, usually mm; label_image_surface turns it to LPS unless asked for RAS.
//
// Data types: uint8 (2), int8 (256), int16 (4), uint16 (512), int32 (8), uint32 (768,
// values up to 2^31 - 1), and float32 (16) / float64 (64) when every value is an integer
// (writers that store labels as floats); scl_slope/scl_inter, when not 0/1 and 0, are
// applied and the result must be an integer. Refused with the field named: other types
// (complex, RGB, ...), a bitpix that does not match, more than 3 dimensions with more than
// one element (a 4-D time series), sizes < 1, voxel data beyond the end of the file, a
// vox_offset inside the header, NIfTI-2 (sizeof_hdr 540).
#include <cmath>
#include <cstring>
#include <limits>

#include "bpm/errors.h"
#include "bpm/label_image.h"
#include "io/label_image_readers.h"
#include "io/surface_readers.h"

namespace bpm::detail {

namespace {

struct HeaderReader {
    std::string_view bytes;
    bool swap;
    template <class T>
    T get(size_t offset) const {
        unsigned char raw[sizeof(T)];
        std::memcpy(raw, bytes.data() + offset, sizeof(T));
        if (swap)
            for (size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(raw[i], raw[sizeof(T) - 1 - i]);
        T value;
        std::memcpy(&value, raw, sizeof(T));
        return value;
    }
};

const char* nifti_type_name(int type) {
    switch (type) {
        case 2: return "uint8";
        case 4: return "int16";
        case 8: return "int32";
        case 16: return "float32";
        case 32: return "complex64";
        case 64: return "float64";
        case 128: return "RGB24";
        case 256: return "int8";
        case 512: return "uint16";
        case 768: return "uint32";
        case 1024: return "int64";
        case 1280: return "uint64";
        case 1536: return "float128";
        case 1792: return "complex128";
        case 2048: return "complex256";
        case 2304: return "RGBA32";
    }
    return nullptr;
}

std::string fmt(double x) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%g", x);
    return buffer;
}

}  // namespace

LabelImage read_nifti_image(std::string_view bytes, const std::string& name, std::vector<std::string>* notes) {
    const auto fail = [&](const std::string& message) -> void { throw InputError(name, message); };
    if (bytes.size() < 348)
        fail("the file ends inside the NIfTI-1 header (" + std::to_string(bytes.size()) + " of 348 bytes)");
    int32_t sizeof_hdr = 0;
    std::memcpy(&sizeof_hdr, bytes.data(), 4);
    HeaderReader h{bytes, false};
    if (sizeof_hdr != 348) {
        h.swap = true;
        if (h.get<int32_t>(0) != 348) {
            h.swap = false;
            if (sizeof_hdr == 540 || HeaderReader{bytes, true}.get<int32_t>(0) == 540)
                fail("a NIfTI-2 file (sizeof_hdr 540); bpm reads NIfTI-1 (convert with e.g. nibabel: "
                     "nib.Nifti1Image(img.dataobj, img.affine))");
            fail("field sizeof_hdr is " + std::to_string(sizeof_hdr) + ", not 348: not a NIfTI-1 file");
        }
    }
    const std::string_view magic = bytes.substr(344, 4);
    if (magic == std::string_view("ni1\0", 4))
        fail("field magic is 'ni1': a header (.hdr) whose voxels are in a separate .img file; bpm reads single "
             "NIfTI-1 files (magic 'n+1', .nii or .nii.gz)");
    if (magic != std::string_view("n+1\0", 4)) fail("field magic is " + quote_token(magic) + ", not 'n+1'");

    int16_t dim[8];
    for (int i = 0; i < 8; ++i) dim[i] = h.get<int16_t>(40 + 2 * size_t(i));
    if (dim[0] < 1 || dim[0] > 7) fail("field dim[0] (the number of dimensions) is " + std::to_string(dim[0]) + ", not 1 to 7");
    LabelImage image;
    for (int d = 1; d <= dim[0]; ++d) {
        if (dim[d] < 1) fail("field dim[" + std::to_string(d) + "] is " + std::to_string(dim[d]) + " (a size must be >= 1)");
        if (d > 3 && dim[d] != 1)
            fail("a " + std::to_string(dim[0]) + "-D image (dim[" + std::to_string(d) + "] = " + std::to_string(dim[d]) +
                 "); a label image has 3 dimensions (a 4-D file with one volume is accepted)");
    }
    for (int d = 0; d < 3; ++d) image.size[size_t(d)] = d + 1 <= dim[0] ? dim[d + 1] : 1;

    const int16_t datatype = h.get<int16_t>(70), bitpix = h.get<int16_t>(72);
    int bytes_per_voxel = 0;
    switch (datatype) {
        case 2: case 256: bytes_per_voxel = 1; break;
        case 4: case 512: bytes_per_voxel = 2; break;
        case 8: case 768: case 16: bytes_per_voxel = 4; break;
        case 64: bytes_per_voxel = 8; break;
        default: {
            const char* type = nifti_type_name(datatype);
            fail("field datatype is " + std::to_string(datatype) + (type ? std::string(" (") + type + ")" : std::string(" (unknown)")) +
                 "; a label image needs integer labels: uint8, int8, int16, uint16, int32, uint32 (or float32/float64 "
                 "holding integers)");
        }
    }
    if (bitpix != 8 * bytes_per_voxel)
        fail("field bitpix is " + std::to_string(bitpix) + ", but datatype " + nifti_type_name(datatype) + " has " +
             std::to_string(8 * bytes_per_voxel) + " bits");
    const float vox_offset = h.get<float>(108);
    if (!(vox_offset >= 348) || vox_offset != std::floor(vox_offset) || vox_offset > float(bytes.size()))
        fail("field vox_offset is " + fmt(vox_offset) + "; the voxels must start at a whole byte offset >= 348 (normally 352) within "
             "the file (" + std::to_string(bytes.size()) + " bytes)");
    const size_t start = size_t(vox_offset);
    const int64_t voxels = image.num_voxels();
    const double needed = double(voxels) * bytes_per_voxel;
    if (needed > double(bytes.size() - start))
        fail("truncated: " + std::to_string(image.size[0]) + " x " + std::to_string(image.size[1]) + " x " +
             std::to_string(image.size[2]) + " voxels of " + nifti_type_name(datatype) + " need " + fmt(needed) +
             " bytes from offset " + std::to_string(start) + ", but only " + std::to_string(bytes.size() - start) +
             " are there");

    // Geometry.
    float pixdim[8];
    for (int i = 0; i < 8; ++i) pixdim[i] = h.get<float>(76 + 4 * size_t(i));
    const int16_t qform_code = h.get<int16_t>(252), sform_code = h.get<int16_t>(254);
    double affine[3][4] = {};
    std::string method;
    if (sform_code > 0) {
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 4; ++c) affine[r][c] = h.get<float>(280 + 16 * size_t(r) + 4 * size_t(c));
        method = "sform";
    } else if (qform_code > 0) {
        const double b = h.get<float>(256), c = h.get<float>(260), d = h.get<float>(264);
        const double s = 1.0 - (b * b + c * c + d * d);
        const double a = s > 0 ? std::sqrt(s) : 0.0;
        const double R[3][3] = {{a * a + b * b - c * c - d * d, 2 * (b * c - a * d), 2 * (b * d + a * c)},
                                {2 * (b * c + a * d), a * a + c * c - b * b - d * d, 2 * (c * d - a * b)},
                                {2 * (b * d - a * c), 2 * (c * d + a * b), a * a + d * d - c * c - b * b}};
        const double qfac = pixdim[0] < 0 ? -1.0 : 1.0;
        const double scale[3] = {pixdim[1], pixdim[2], qfac * pixdim[3]};
        for (int r = 0; r < 3; ++r) {
            for (int col = 0; col < 3; ++col) affine[r][col] = R[r][col] * scale[col];
            affine[r][3] = h.get<float>(268 + 4 * size_t(r));
        }
        method = "qform";
    } else {
        for (int r = 0; r < 3; ++r) affine[r][r] = pixdim[r + 1];
        method = "pixdim (no qform or sform)";
    }
    for (int c = 0; c < 3; ++c) {
        const double len = std::sqrt(affine[0][c] * affine[0][c] + affine[1][c] * affine[1][c] + affine[2][c] * affine[2][c]);
        if (!(len > 0) || !std::isfinite(len))
            fail("the voxel size along axis " + std::to_string(c) + " is " + fmt(len) + " (from the " + method +
                 "; field pixdim[" + std::to_string(c + 1) + "] is " + fmt(pixdim[c + 1]) + "): must be positive");
        image.spacing[size_t(c)] = len;
        for (int r = 0; r < 3; ++r) image.direction[3 * size_t(r) + size_t(c)] = affine[r][c] / len;
    }
    for (int r = 0; r < 3; ++r) image.origin[size_t(r)] = affine[r][3];
    // The standard defines every method's coordinates as RAS+ (also the pixdim-only one,
    // "Analyze" orientation, which has no real frame but is RAS by convention).
    image.frame = ImageFrame::Ras;

    // Voxels.
    double slope = h.get<float>(112), inter = h.get<float>(116);
    if (!std::isfinite(slope) || slope == 0) slope = 1;
    if (!std::isfinite(inter)) inter = 0;
    VoxelType type = VoxelType::U8;
    switch (datatype) {
        case 256: type = VoxelType::I8; break;
        case 4: type = VoxelType::I16; break;
        case 512: type = VoxelType::U16; break;
        case 8: type = VoxelType::I32; break;
        case 768: type = VoxelType::U32; break;
        case 16: type = VoxelType::F32; break;
        case 64: type = VoxelType::F64; break;
        default: break;
    }
    decode_labels(reinterpret_cast<const unsigned char*>(bytes.data()) + start, type, h.swap, slope, inter,
                  "scl_slope/scl_inter", image, name);
    if (notes) {
        static const char* const units[] = {"", "m", "mm", "um"};
        const int unit = h.get<uint8_t>(123) & 7;
        notes->push_back("NIfTI-1 label image: " + std::to_string(image.size[0]) + " x " + std::to_string(image.size[1]) +
                         " x " + std::to_string(image.size[2]) + " voxels of " + nifti_type_name(datatype) +
                         ", voxel size " + fmt(image.spacing[0]) + " x " + fmt(image.spacing[1]) + " x " +
                         fmt(image.spacing[2]) + (unit >= 1 && unit <= 3 ? std::string(" ") + units[unit] : std::string()) +
                         ", placed by the " + method);
    }
    return image;
}

}  // namespace bpm::detail
