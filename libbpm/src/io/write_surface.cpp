// Writing surfaces: the checks that keep a file readable, the choice of writer, and the
// writers of the formats that hold only surfaces (OFF, OBJ, binary STL, binary PLY). MSH
// is written by write_msh.cpp, which also writes tetrahedral meshes.
#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <limits>

#include "bpm/errors.h"
#include "bpm/surface_io.h"
#include "core/file_util.h"
#include "core/number_text.h"
#include "io/mesh_writers.h"
#include "io/surface_readers.h"

namespace bpm {

namespace {


void appendf(std::string& out, const char* format, ...) __attribute__((format(printf, 2, 3)));
void appendf(std::string& out, const char* format, ...) {
    char buffer[256];
    va_list args;
    va_start(args, format);
    const int n = std::vsnprintf(buffer, sizeof buffer, format, args);
    va_end(args);
    if (n > 0) out.append(buffer, std::min(static_cast<size_t>(n), sizeof buffer - 1));
}

// "x y z\n" after `prefix`, each with 17 significant digits (reads back to the same
// bits) and, unlike printf, independent of the C locale's decimal separator.
void append_point(std::string& out, const char* prefix, const Vec3& p) {
    out += prefix;
    for (int k = 0; k < 3; ++k) {
        if (k > 0) out += ' ';
        detail::append_round_trip_text(out, p[k]);
    }
    out += '\n';
}

std::string write_off(const Surface& s) {
    std::string out;
    appendf(out, "OFF\n%d %d 0\n", s.num_vertices(), s.num_triangles());
    for (const Vec3& p : s.vertices) append_point(out, "", p);
    for (const Tri& t : s.triangles) appendf(out, "3 %d %d %d\n", t[0], t[1], t[2]);
    return out;
}

std::string write_obj(const Surface& s) {
    std::string out;
    appendf(out, "# bpm surface: %d vertices, %d triangles; groups patch_N are patch ids\n", s.num_vertices(),
            s.num_triangles());
    for (const Vec3& p : s.vertices) append_point(out, "v ", p);
    for (size_t t = 0; t < s.triangles.size(); ++t) {
        if (t == 0 || s.patches[t] != s.patches[t - 1]) appendf(out, "g patch_%d\n", s.patches[t]);
        const Tri& tri = s.triangles[t];
        appendf(out, "f %d %d %d\n", tri[0] + 1, tri[1] + 1, tri[2] + 1);
    }
    return out;
}

std::string write_stl(const Surface& s) {
    std::string out;
    std::string header = "binary STL written by bpm";
    header.resize(80, ' ');
    out += header;
    detail::append_le<uint32_t>(out, static_cast<uint32_t>(s.triangles.size()));
    for (const Tri& t : s.triangles) {
        const Vec3 n = triangle_normal(s.vertices[t[0]], s.vertices[t[1]], s.vertices[t[2]]);
        for (double x : n) detail::append_le<float>(out, static_cast<float>(x));
        for (int32_t v : t) {
            for (double x : s.vertices[v]) detail::append_le<float>(out, static_cast<float>(x));
        }
        detail::append_le<uint16_t>(out, 0);
    }
    return out;
}

std::string write_ply(const Surface& s) {
    // The per-face `patch` property only when there is more than patch 0: readers take a
    // missing one as patch 0 (bpm's does), and meshio 5's binary PLY reader fails on any
    // face property besides the vertex list ("numpy.int32 has no len()"), so the common
    // one-material surface stays readable there.
    bool patches = false;
    for (int32_t p : s.patches) patches = patches || p != 0;
    std::string out;
    appendf(out,
            "ply\nformat binary_little_endian 1.0\ncomment written by bpm\nelement vertex %d\n"
            "property double x\nproperty double y\nproperty double z\nelement face %d\n"
            "property list uchar int vertex_indices\n%send_header\n",
            s.num_vertices(), s.num_triangles(), patches ? "property int patch\n" : "");
    for (const Vec3& p : s.vertices) {
        for (double x : p) detail::append_le<double>(out, x);
    }
    for (size_t t = 0; t < s.triangles.size(); ++t) {
        detail::append_le<uint8_t>(out, 3);
        for (int32_t v : s.triangles[t]) detail::append_le<int32_t>(out, v);
        if (patches) detail::append_le<int32_t>(out, s.patches[t]);
    }
    return out;
}

}  // namespace

void write_surface(const std::string& path, const Surface& surface, std::optional<SurfaceFormat> format,
                   MeshEncoding encoding, const std::vector<PatchInfo>& patch_info) {
    const std::string where = path == "-" ? "<stdout>" : path;
    if (!format) format = surface_format_from_path(path);
    if (!format) {
        throw OutputError(where, path == "-" ? "the format for standard output must be given explicitly"
                                             : "cannot tell the surface format from the file name; expected the "
                                               "extension .off, .obj, .stl, .ply or .msh, or an explicit format");
    }
    if (*format == SurfaceFormat::Vtp || *format == SurfaceFormat::Vtu) {
        throw OutputError(where, std::string("cannot write ") + detail::surface_format_name(*format) +
                                     ": VTK XML is an input format here (write .off, .obj, .stl, .ply or .msh)");
    }
    if (*format == SurfaceFormat::Nifti || *format == SurfaceFormat::Nrrd || *format == SurfaceFormat::MetaImage) {
        throw OutputError(where, std::string("cannot write ") + detail::surface_format_name(*format) +
                                     ": a label image is an input format here (write .off .obj .stl .ply or .msh)");
    }
    if (*format == SurfaceFormat::Surf) {
        // Region names would have to be made up: a bpm patch is not a pair of materials.
        throw OutputError(where, "cannot write Amira HyperSurface (.surf): bpm reads it but writes only .off .obj .stl "
                                 ".ply .msh");
    }
    // Refuse what would make a file no reader (bpm's included) can read back.
    if (surface.patches.size() != surface.triangles.size()) {
        throw OutputError(where, "cannot write: the surface has " + std::to_string(surface.patches.size()) +
                                     " patch ids for " + std::to_string(surface.triangles.size()) + " triangles");
    }
    for (size_t t = 0; t < surface.triangles.size(); ++t) {
        for (int32_t v : surface.triangles[t]) {
            if (v < 0 || v >= surface.num_vertices()) {
                throw OutputError(where, "cannot write: triangle " + std::to_string(t) + " has vertex index " +
                                             std::to_string(v) + " out of range");
            }
        }
    }
    for (size_t v = 0; v < surface.vertices.size(); ++v) {
        for (double x : surface.vertices[v]) {
            if (!std::isfinite(x)) {
                throw OutputError(where, "cannot write: vertex " + std::to_string(v) + " has a NaN or infinite coordinate");
            }
        }
    }
    if (*format == SurfaceFormat::Stl) {
        for (size_t v = 0; v < surface.vertices.size(); ++v) {
            for (double x : surface.vertices[v]) {
                if (std::fabs(x) > static_cast<double>(std::numeric_limits<float>::max())) {
                    throw OutputError(where, "cannot write STL: vertex " + std::to_string(v) +
                                                 " has a coordinate beyond the range of float");
                }
            }
        }
    }
    if (*format == SurfaceFormat::Vtk) {
        // Legacy VTK is read (inputs from VTK, ParaView, Slicer) but not written: bpm writes
        // VTK's XML .vtu where point data matters (bpm-refine --data).
        throw OutputError(where, "cannot write legacy VTK (.vtk): bpm reads it but writes only .off .obj .stl .ply .msh");
    }
    const bool binary_format = *format == SurfaceFormat::Stl || *format == SurfaceFormat::Ply;
    if (encoding == MeshEncoding::BinaryZlib ||
        (encoding == MeshEncoding::Binary && !binary_format && *format != SurfaceFormat::Msh)) {
        throw OutputError(where, std::string("cannot write ") + detail::surface_format_name(*format) + " " +
                                     (encoding == MeshEncoding::Binary ? "as binary" : "compressed") +
                                     " (binary: MSH 4.1; compressed: VTU)");
    }
    std::string bytes;
    switch (*format) {
        case SurfaceFormat::Off: bytes = write_off(surface); break;
        case SurfaceFormat::Obj: bytes = write_obj(surface); break;
        case SurfaceFormat::Stl: bytes = write_stl(surface); break;
        case SurfaceFormat::Ply: bytes = write_ply(surface); break;
        case SurfaceFormat::Msh:
            bytes = detail::msh_of_surface(surface, patch_info, detail::MshVersion::V41, encoding);
            break;
        case SurfaceFormat::Msh22:
            bytes = detail::msh_of_surface(surface, patch_info, detail::MshVersion::V22, encoding);
            break;
        case SurfaceFormat::Vtk: break;  // refused above
        case SurfaceFormat::Vtp:
        case SurfaceFormat::Vtu: break;  // refused above
        case SurfaceFormat::Surf: break;  // refused above
        case SurfaceFormat::Nifti:
        case SurfaceFormat::Nrrd:
        case SurfaceFormat::MetaImage: break;  // refused above
    }
    detail::write_file_atomically(path, bytes);
}

}  // namespace bpm
