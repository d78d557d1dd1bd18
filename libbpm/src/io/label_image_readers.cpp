// From a label image to what read_surface needs (io/label_image_readers.h).
#include "io/label_image_readers.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <type_traits>
#include <unordered_set>
#include <cstring>
#include <limits>

#include "bpm/errors.h"

namespace bpm::detail {

int voxel_type_size(VoxelType type) {
    switch (type) {
        case VoxelType::U8:
        case VoxelType::I8: return 1;
        case VoxelType::I16:
        case VoxelType::U16: return 2;
        case VoxelType::I32:
        case VoxelType::U32:
        case VoxelType::F32: return 4;
        case VoxelType::F64: return 8;
    }
    return 1;
}

const char* voxel_type_name(VoxelType type) {
    switch (type) {
        case VoxelType::U8: return "uint8";
        case VoxelType::I8: return "int8";
        case VoxelType::I16: return "int16";
        case VoxelType::U16: return "uint16";
        case VoxelType::I32: return "int32";
        case VoxelType::U32: return "uint32";
        case VoxelType::F32: return "float32";
        case VoxelType::F64: return "float64";
    }
    return "?";
}

void decode_labels(const unsigned char* data, VoxelType type, bool swap, double slope, double inter,
                   const std::string& scaled_by, LabelImage& image, const std::string& name) {
    // Straight into the compact form (LabelImage::label_values and an index per voxel, 1 or
    // 2 bytes), in two passes over the file's voxels: the distinct labels, then the
    // indices. The int32 labels (4 bytes a voxel) are never held.
    const int64_t voxels = image.num_voxels();
    image.labels.clear();
    const bool scaled = slope != 1 || inter != 0;
    std::vector<int32_t> values;
    if (type == VoxelType::U8 && !scaled) {
        bool seen[256] = {};
        seen[0] = true;
        for (int64_t v = 0; v < voxels; ++v) seen[data[v]] = true;
        uint8_t position[256] = {};
        for (int b = 0; b < 256; ++b)
            if (seen[b]) position[b] = uint8_t(values.size()), values.push_back(b);
        image.label_index16.clear();
        image.label_index8.resize(size_t(voxels));
        for (int64_t v = 0; v < voxels; ++v) image.label_index8[size_t(v)] = position[data[v]];
        image.label_values = std::move(values);
        return;
    }
    const int size = voxel_type_size(type);
    const auto where = [&](int64_t v) {
        const int64_t i = v % image.size[0], j = (v / image.size[0]) % image.size[1], k = v / (image.size[0] * image.size[1]);
        return "voxel (" + std::to_string(i) + ", " + std::to_string(j) + ", " + std::to_string(k) + ")";
    };
    const auto text = [](double x) {
        char buffer[32];
        std::snprintf(buffer, sizeof buffer, "%.9g", x);
        return std::string(buffer);
    };
    const auto label = [&](int64_t v) -> int32_t {
        unsigned char b[8];
        std::memcpy(b, data + size_t(v) * size_t(size), size_t(size));
        if (swap)
            for (int i = 0; i < size / 2; ++i) std::swap(b[i], b[size - 1 - i]);
        double raw = 0;
        switch (type) {
            case VoxelType::U8: raw = b[0]; break;
            case VoxelType::I8: raw = int8_t(b[0]); break;
            case VoxelType::I16: { int16_t x; std::memcpy(&x, b, 2); raw = x; break; }
            case VoxelType::U16: { uint16_t x; std::memcpy(&x, b, 2); raw = x; break; }
            case VoxelType::I32: { int32_t x; std::memcpy(&x, b, 4); raw = x; break; }
            case VoxelType::U32: { uint32_t x; std::memcpy(&x, b, 4); raw = x; break; }
            case VoxelType::F32: { float x; std::memcpy(&x, b, 4); raw = x; break; }
            case VoxelType::F64: { double x; std::memcpy(&x, b, 8); raw = x; break; }
        }
        const double x = scaled ? slope * raw + inter : raw;
        if (!std::isfinite(x) || x != std::floor(x))
            throw InputError(name, where(v) + " has the value " + text(x) + (scaled ? " (after " + scaled_by + ")" : "") +
                                       " of type " + voxel_type_name(type) + ", which is not an integer label");
        if (x < double(std::numeric_limits<int32_t>::min()) || x > double(std::numeric_limits<int32_t>::max()))
            throw InputError(name, where(v) + " has the label " + text(x) + ", beyond the int32 range");
        return int32_t(x);
    };
    {
        std::unordered_set<int32_t> seen = {0};
        int32_t last = 0;
        for (int64_t v = 0; v < voxels; ++v) {
            const int32_t l = label(v);
            if (l != last) {
                last = l;
                if (seen.insert(l).second && seen.size() > 65536)
                    throw InputError(name, "more than 65536 distinct labels: an intensity image, not a segmentation?");
            }
        }
        values.assign(seen.begin(), seen.end());
        std::sort(values.begin(), values.end());
    }
    const auto fill = [&](auto& index) {
        index.resize(size_t(voxels));
        int32_t last = values[0];
        size_t at = 0;
        for (int64_t v = 0; v < voxels; ++v) {
            const int32_t l = label(v);
            if (l != last) {
                last = l;
                at = size_t(std::lower_bound(values.begin(), values.end(), l) - values.begin());
            }
            index[size_t(v)] = static_cast<typename std::decay_t<decltype(index)>::value_type>(at);
        }
    };
    image.label_index8.clear();
    image.label_index16.clear();
    if (values.size() <= 256) fill(image.label_index8);
    else fill(image.label_index16);
    image.label_values = std::move(values);
}

ReaderOutput label_image_reader_output(LabelImage image, const std::string& name, const LabelSurfaceOptions& options,
                                       const Context& context, std::vector<std::string> notes) {
    if (std::string problem = label_image_problem(image); !problem.empty()) throw InputError(name, problem);
    const ImageFrame file_frame = image.frame;
    LabelSurface extracted;
    try {
        extracted = label_image_surface(std::move(image), options, context);
    } catch (const InputError& e) {
        throw InputError(name, e.what());
    }
    std::string labels;
    for (size_t i = 0; i < extracted.labels.size(); ++i) {
        if (i == 8 && extracted.labels.size() > 10) {
            labels += ", ... (" + std::to_string(extracted.labels.size()) + " in all)";
            break;
        }
        labels += (i ? ", " : "") + std::to_string(extracted.labels[i]);
    }
    if (extracted.surface.triangles.empty())
        throw InputError(name, "every voxel has the label 0 (background): no two labels meet, so there is no surface");
    ReaderOutput out;
    out.notes = std::move(notes);
    if (file_frame == ImageFrame::Unknown)
        out.notes.push_back("coordinates as the file gives them (it names no anatomical frame, LPS or RAS)");
    else if (extracted.frame != file_frame)
        out.notes.push_back(std::string("coordinates in ") + image_frame_name(extracted.frame) + ": the file's " +
                            image_frame_name(file_frame) + " coordinates turned by 180 degrees about z (x and y negated)");
    else
        out.notes.push_back(std::string("coordinates in ") + image_frame_name(extracted.frame) + ", as in the file");
    out.frame = extracted.frame;
    out.notes.push_back("labels " + labels + " (0 = background, material '" + std::string(kExteriorMaterial) + "')");
    out.notes.push_back("surface nets: " + std::to_string(extracted.surface.num_vertices()) + " vertices, " +
                        std::to_string(extracted.surface.num_triangles()) + " triangles, " +
                        std::to_string(extracted.patch_info.size()) + " interfaces (patches), " +
                        std::to_string(extracted.junction_vertices) + " vertices on junction lines, " +
                        std::to_string(extracted.split_vertices) + " cube vertices split where a label touches "
                        "itself at a corner");
    if (extracted.sliver_vertices > 0 || extracted.unsmoothed_vertices > 0)
        out.notes.push_back("smoothing undone in part: " + std::to_string(extracted.sliver_vertices) +
                            " vertices moved back where it made slivers (R/r > 30), " +
                            std::to_string(extracted.unsmoothed_vertices) + " where it made the surface cross itself");
    if (extracted.changed_voxels > 0)
        out.notes.push_back(std::to_string(extracted.changed_voxels) + " voxels relabelled where a label touched itself "
                            "only along a voxel edge (given the label of the two voxels that touched)" +
                            (extracted.unresolved_contacts > 0
                                 ? "; " + std::to_string(extracted.unresolved_contacts) + " such edges remain"
                                 : std::string()));
    out.surface = std::move(extracted.surface);
    out.patch_info = std::move(extracted.patch_info);
    return out;
}

}  // namespace bpm::detail
