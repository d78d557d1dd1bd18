// Reading and writing surfaces: format choice, the read pipeline (parse, requested
// repairs, validation) and the writers. The parsers live in read_<format>.cpp.
#include "bpm/surface_io.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <set>
#include <unordered_map>

#include "bpm/errors.h"
#include "core/edge_uses.h"
#include "core/file_util.h"
#include "core/gzip.h"
#include "core/number_text.h"
#include "io/label_image_readers.h"
#include "io/surface_readers.h"

namespace bpm {

namespace detail {

const char* surface_format_name(SurfaceFormat f) {
    switch (f) {
        case SurfaceFormat::Off: return "OFF";
        case SurfaceFormat::Obj: return "OBJ";
        case SurfaceFormat::Stl: return "STL";
        case SurfaceFormat::Ply: return "PLY";
        case SurfaceFormat::Msh: return "MSH";
        case SurfaceFormat::Msh22: return "MSH 2.2";
        case SurfaceFormat::Vtk: return "VTK";
        case SurfaceFormat::Vtp: return "VTP";
        case SurfaceFormat::Vtu: return "VTU";
        case SurfaceFormat::Surf: return "HyperSurface";
        case SurfaceFormat::Nifti: return "NIfTI";
        case SurfaceFormat::Nrrd: return "NRRD";
        case SurfaceFormat::MetaImage: return "MetaImage";
    }
    return "?";
}

}  // namespace detail

namespace {

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}


// The start tag of a VTK XML file's <VTKFile> element (its first 200 bytes), or empty.
std::string_view vtk_file_tag(std::string_view bytes) {
    const size_t at = bytes.substr(0, 512).find("<VTKFile");
    return at == std::string_view::npos ? std::string_view() : bytes.substr(at, 200);
}

// Whether the head says parallel VTK XML (.pvtp / .pvtu): a list of piece files.
bool is_parallel_vtk_xml(std::string_view bytes) {
    const std::string_view tag = vtk_file_tag(bytes);
    return tag.find("\"PPolyData\"") != std::string_view::npos ||
           tag.find("\"PUnstructuredGrid\"") != std::string_view::npos;
}

// The format a file's head plainly shows, if any.
std::optional<SurfaceFormat> format_from_head(std::string_view bytes) {
    std::optional<SurfaceFormat> seen;
    const std::string_view head = bytes.substr(0, 64);
    if (head.substr(0, 3) == "ply") seen = SurfaceFormat::Ply;
    else if (head.substr(0, 11) == "$MeshFormat") seen = SurfaceFormat::Msh;
    else if (head.substr(0, 3) == "OFF" || head.substr(0, 4) == "COFF" || head.substr(0, 4) == "NOFF") seen = SurfaceFormat::Off;
    else if (head.substr(0, 5) == "solid") seen = SurfaceFormat::Stl;
    else if (head.substr(0, 14) == "# vtk DataFile") seen = SurfaceFormat::Vtk;
    else if (head.substr(0, 14) == "# HyperSurface" || head.substr(0, 13) == "#HyperSurface") seen = SurfaceFormat::Surf;
    else if (bytes.size() >= 348 && (bytes.substr(344, 4) == std::string_view("n+1\0", 4) ||
                                     bytes.substr(344, 4) == std::string_view("ni1\0", 4)))
        seen = SurfaceFormat::Nifti;
    else if (head.substr(0, 7) == "NRRD000") seen = SurfaceFormat::Nrrd;
    else if (head.substr(0, 10) == "ObjectType" && head.find("Image") != std::string_view::npos) seen = SurfaceFormat::MetaImage;
    else if (const std::string_view tag = vtk_file_tag(bytes); !tag.empty()) {
        if (tag.find("\"PolyData\"") != std::string_view::npos) seen = SurfaceFormat::Vtp;
        else if (tag.find("\"UnstructuredGrid\"") != std::string_view::npos) seen = SurfaceFormat::Vtu;
    }
    return seen;
}

// A hint for an error on a file that is plainly of another format than the one chosen.
std::string sniffed_format_hint(std::string_view bytes, SurfaceFormat chosen) {
    const std::optional<SurfaceFormat> seen = format_from_head(bytes);
    // One reader reads both VTK XML types: no hint between them.
    if (seen && (*seen == SurfaceFormat::Vtp || *seen == SurfaceFormat::Vtu) &&
        (chosen == SurfaceFormat::Vtp || chosen == SurfaceFormat::Vtu))
        return "";
    if (!seen || *seen == chosen || (*seen == SurfaceFormat::Msh && chosen == SurfaceFormat::Msh22)) return "";
    return std::string(" (the file looks like ") + detail::surface_format_name(*seen) + ", not " + detail::surface_format_name(chosen) + ")";
}

// The patches whose triangles, taken alone, are closed: every edge in exactly two of them.
std::set<int32_t> closed_patches(const Surface& surface) {
    std::vector<std::array<int32_t, 3>> edges;  // (patch, smaller vertex, larger vertex), one per side
    edges.reserve(3 * surface.triangles.size());
    for (size_t t = 0; t < surface.triangles.size() && t < surface.patches.size(); ++t) {
        const Tri& tri = surface.triangles[t];
        for (int k = 0; k < 3; ++k)
            edges.push_back({surface.patches[t], std::min(tri[k], tri[(k + 1) % 3]), std::max(tri[k], tri[(k + 1) % 3])});
    }
    std::sort(edges.begin(), edges.end());
    std::set<int32_t> closed, open;
    for (size_t i = 0; i < edges.size();) {
        size_t j = i;
        while (j < edges.size() && edges[j] == edges[i]) ++j;
        (j - i == 2 ? closed : open).insert(edges[i][0]);
        i = j;
    }
    for (const int32_t p : open) closed.erase(p);
    return closed;
}

// Whether `info` has what apply_file_material gave the patch: exterior in front, the
// file's material behind (its name is "<material>|exterior", or the file's name for the
// patch, e.g. an OBJ group).
bool is_file_material(const PatchInfo& info, const std::string& material) {
    return info.oriented && info.front == kExteriorMaterial && info.back == material;
}

// One file whose patches share triangles holds one closed surface per material, told
// apart by a label per triangle (a cell array `label` or `material`, as multi-label
// marching cubes writes it: each label's surface includes its interfaces with the other
// labels). If every patch got the file's own material (apply_file_material), its
// interfaces would be sheets with that one material on both sides and all its regions one
// material. So each patch P of such a file encloses its own material, "<material>_<P>".
// Only when every patch that shares triangles has the file's material (a file that names
// its materials keeps them) and was a closed surface on its own before the fuse (the
// evidence of one closed surface per label: a duplicated triangle between two faces of a
// CAD part is not). Returns a note for the log, empty if nothing changed.
std::string split_file_material_by_patch(std::vector<PatchInfo>& infos, const std::vector<FusedPatch>& fused,
                                         const std::set<int32_t>& closed, const std::string& material) {
    if (material.empty() || fused.empty()) return {};
    for (const FusedPatch& f : fused)
        for (const int32_t j : f.joins)
            if (!closed.count(j)) return {};
    const auto has_file_material = [&](const PatchInfo* info) { return info && is_file_material(*info, material); };
    for (const FusedPatch& f : fused)
        for (const int32_t j : f.joins)
            if (!has_file_material(find_patch_info(infos, j))) return {};
    std::string renamed;
    for (PatchInfo& info : infos) {
        if (!has_file_material(&info)) continue;
        const bool default_name = info.name == material + "|" + kExteriorMaterial;
        info.back = material + "_" + std::to_string(info.patch);
        if (default_name) info.name = info.back + "|" + kExteriorMaterial;
        renamed += (renamed.empty() ? "" : ", ") + info.back;
    }
    return "the patches share triangles: one closed surface per material, told apart by the patch ids; materials " +
           renamed + " (one per patch, instead of " + material + " for all)";
}

// The merge-duplicate-triangles repair, with a note per new interface patch. `material`:
// what the one file read encloses (finish_reading), empty for several files together.
void fuse_triangles(Surface& surface, SurfaceReadReport& r, const std::string& prefix, const std::string& material) {
    // Which patches are closed, before the fuse: needed only where the file's patches may
    // be split into materials (several, all with the file's material).
    const bool may_split = !material.empty() && r.patch_info.size() > 1 &&
                           std::all_of(r.patch_info.begin(), r.patch_info.end(),
                                       [&](const PatchInfo& info) { return is_file_material(info, material); });
    const std::set<int32_t> closed = may_split ? closed_patches(surface) : std::set<int32_t>();
    std::vector<FusedPatch> fused;
    const int64_t removed = fuse_duplicate_triangles(surface, &fused);
    r.fused_triangles += removed;
    if (removed == 0) return;
    const std::string split = split_file_material_by_patch(r.patch_info, fused, closed, material);
    add_fused_patch_info(r.patch_info, fused);
    r.notes.push_back(prefix + "removed " + std::to_string(removed) + " duplicate triangles (" +
                      std::to_string(surface.triangles.size()) + " triangles left)");
    for (const FusedPatch& f : fused) {
        std::string joins;
        for (size_t i = 0; i < f.joins.size(); ++i)
            joins += (i == 0 ? "" : i + 1 == f.joins.size() ? " and " : ", ") + std::to_string(f.joins[i]);
        r.notes.push_back(prefix + "patch " + std::to_string(f.patch) + " = the " + std::to_string(f.triangles) +
                          " triangles that patches " + joins + " had in common (fused)");
    }
    if (!split.empty()) r.notes.push_back(prefix + split);
    // A patch whose triangles were all in common with another's (a sphere inside a box,
    // one file per material: every triangle of the sphere's file is the box's too) has
    // none left: its name and materials would describe a patch that is not there (a
    // ball|exterior with 0 triangles, and the ball touches no exterior). Its triangles
    // are the interface patch's, which names both materials, so its row goes.
    std::vector<char> used;
    for (const int32_t p : surface.patches)
        if (p >= 0) {
            if (size_t(p) >= used.size()) used.resize(size_t(p) + 1, 0);
            used[size_t(p)] = 1;
        }
    std::map<int32_t, std::vector<int32_t>> emptied;  // patch -> the fused patches it went into
    for (const FusedPatch& f : fused)
        for (const int32_t j : f.joins)
            if (j >= 0 && (size_t(j) >= used.size() || !used[size_t(j)])) emptied[j].push_back(f.patch);
    for (const auto& [patch, into] : emptied) {
        const auto row = std::find_if(r.patch_info.begin(), r.patch_info.end(),
                                      [patch = patch](const PatchInfo& i) { return i.patch == patch; });
        std::string where;
        for (size_t i = 0; i < into.size(); ++i)
            where += (i == 0 ? "" : i + 1 == into.size() ? " and " : ", ") + std::to_string(into[i]);
        r.notes.push_back(prefix + "patch " + std::to_string(patch) +
                          (row != r.patch_info.end() && !row->name.empty() ? " (\"" + row->name + "\")" : std::string()) +
                          " has no triangles left: all of them were in common with other patches, fused into patch" +
                          (into.size() == 1 ? " " : "es ") + where);
        if (row != r.patch_info.end()) r.patch_info.erase(row);
    }
}

// Why a surface that parsed is still unusable. The repairs that help are listed once at
// the end (throw_surface_problems); only what merging duplicate triangles does to
// materials is said at the problem, since the repair's name does not tell it.
std::string problems_message(const std::vector<SurfaceProblem>& problems, const Surface& surface, size_t limit) {
    using Kind = SurfaceProblem::Kind;
    std::string message;
    const size_t shown = std::min<size_t>(problems.size(), 3);
    bool explained = false;
    for (size_t i = 0; i < shown; ++i) {
        if (i > 0) message += "; ";
        message += describe_problem(problems[i], surface);
        if (problems[i].kind == Kind::DuplicateTriangle && !explained) {
            message += " (merged, an interface between two materials becomes a patch of its own)";
            explained = true;
        }
    }
    if (problems.size() > shown) {
        message += problems.size() >= limit ? "; and more problems"
                                            : "; and " + std::to_string(problems.size() - shown) + " more problem" +
                                                  (problems.size() - shown == 1 ? "" : "s");
    }
    return message;
}

// Every repair `surface` needs that `options` does not ask for: those its problems call
// for, then those the problems left after applying them call for (merging duplicate
// vertices is what reveals the duplicate triangles of one closed surface per material),
// so that one error lists them all. In the order the repairs are applied.
std::vector<SurfaceRepair> repairs_needed(Surface surface, const std::vector<SurfaceProblem>& first,
                                          const SurfaceReadOptions& options, const ValidateOptions& validate) {
    using Kind = SurfaceProblem::Kind;
    bool merge = false, drop = false, fuse = false;
    std::vector<SurfaceProblem> problems = first;
    for (int round = 0; round < 3; ++round) {
        bool added = false;
        for (const SurfaceProblem& p : problems) {
            if (p.kind == Kind::DuplicateVertex && !merge && !options.merge_duplicate_vertices) merge = added = true;
            if (p.kind == Kind::UnreferencedVertex && !drop && !options.drop_unreferenced_vertices) drop = added = true;
            if (p.kind == Kind::DuplicateTriangle && !fuse && !options.merge_duplicate_triangles) fuse = added = true;
        }
        if (!added) break;
        // Apply what is known so far, in the reader's order, and look again.
        if (merge) merge_duplicate_vertices(surface);
        if (drop) drop_unreferenced_vertices(surface);
        if (fuse) fuse_duplicate_triangles(surface);
        problems = validate_surface(surface, validate);
    }
    std::vector<SurfaceRepair> out;
    if (merge) out.push_back(SurfaceRepair::MergeDuplicateVertices);
    if (drop) out.push_back(SurfaceRepair::DropUnreferencedVertices);
    if (fuse) out.push_back(SurfaceRepair::MergeDuplicateTriangles);
    return out;
}

std::string repair_words(SurfaceRepair r) {
    switch (r) {
        case SurfaceRepair::TriangulatePolygons: return "triangulate polygons";
        case SurfaceRepair::MergeDuplicateVertices: return "merge duplicate vertices";
        case SurfaceRepair::DropUnreferencedVertices: return "drop unreferenced vertices";
        case SurfaceRepair::MergeDuplicateTriangles: return "merge duplicate triangles";
    }
    return "?";
}

// The error for a validated surface with problems: InputNeedsRepair when repairs help.
// `polygons` (empty: none) is the reader's note of the polygon faces it triangulated
// although the options did not ask for it (ReaderOutput::triangulated_polygons): they
// were triangulated only so that this one error can name every repair the input needs.
[[noreturn]] void throw_surface_problems(const std::string& where, const std::string& prefix,
                                         const std::string& polygons,
                                         const std::vector<SurfaceProblem>& problems, const Surface& surface,
                                         const SurfaceReadOptions& options, const ValidateOptions& validate) {
    std::string message = prefix;
    std::vector<SurfaceRepair> repairs;
    if (!polygons.empty()) {
        message += polygons + "; only triangles are accepted";
        repairs.push_back(SurfaceRepair::TriangulatePolygons);
    }
    if (!problems.empty()) {
        message += (polygons.empty() ? "" : "; ") + problems_message(problems, surface, validate.max_problems);
        const std::vector<SurfaceRepair> more = repairs_needed(surface, problems, options, validate);
        repairs.insert(repairs.end(), more.begin(), more.end());
    }
    // Degenerate triangles have no repair option (removing them could open the surface):
    // say so, and what to do, instead of leaving the user to look for a flag.
    const bool degenerate = std::any_of(problems.begin(), problems.end(), [](const SurfaceProblem& p) {
        return p.kind == SurfaceProblem::Kind::RepeatedCorner || p.kind == SurfaceProblem::Kind::ZeroArea;
    });
    if (degenerate)
        message += "; bpm has no repair option for degenerate triangles: remove them from the input (e.g. MeshLab's "
                   "Remove Zero Area Faces), closing any hole that leaves";
    if (repairs.empty()) throw InputError(where, message);
    message += repairs.size() == 1 ? "; the repair it needs: " : "; the repairs it needs, all together: ";
    for (size_t i = 0; i < repairs.size(); ++i) message += (i ? ", " : "") + repair_words(repairs[i]);
    throw InputNeedsRepair(where, message, repairs);
}

}  // namespace

std::optional<SurfaceFormat> surface_format_from_name(const std::string& name) {
    const std::string n = lower(name);
    if (n == "off") return SurfaceFormat::Off;
    if (n == "obj") return SurfaceFormat::Obj;
    if (n == "stl") return SurfaceFormat::Stl;
    if (n == "ply") return SurfaceFormat::Ply;
    if (n == "msh") return SurfaceFormat::Msh;
    if (n == "msh22") return SurfaceFormat::Msh22;
    if (n == "vtk") return SurfaceFormat::Vtk;
    if (n == "vtp") return SurfaceFormat::Vtp;
    if (n == "vtu") return SurfaceFormat::Vtu;
    if (n == "pvtp") return SurfaceFormat::Vtp;  // parallel: its pieces are read (read_surface)
    if (n == "pvtu") return SurfaceFormat::Vtu;
    if (n == "surf") return SurfaceFormat::Surf;
    if (n == "nii" || n == "nifti") return SurfaceFormat::Nifti;
    if (n == "nrrd") return SurfaceFormat::Nrrd;  // also .seg.nrrd (3D Slicer)
    if (n == "mha" || n == "mhd" || n == "metaimage") return SurfaceFormat::MetaImage;
    return std::nullopt;
}

std::optional<SurfaceFormat> surface_format_from_path(const std::string& compressed_or_not) {
    const std::string path = detail::without_gz_suffix(compressed_or_not);  // femur.off.gz: off
    const size_t slash = path.find_last_of('/');
    const size_t dot = path.find_last_of('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return std::nullopt;
    return surface_format_from_name(path.substr(dot + 1));
}

static Surface finish_reading(detail::ReaderOutput parsed, SurfaceFormat format, const std::string& name,
                              const SurfaceReadOptions& options, SurfaceReadReport* report,
                              const std::string& material = {});

// `load`: reads a file that a header names (a MetaImage data file), null from memory.
// `release`: `bytes` itself when the caller lets the reader free them once a label image
// is decoded (read_surface of a path), so that the file's voxels and the extraction's
// memory are not needed at the same time; null otherwise.
static Surface read_from_memory(const std::string& bytes, SurfaceFormat format, const std::string& name,
                                const SurfaceReadOptions& options, SurfaceReadReport* report,
                                const std::string& material, const detail::DataFileLoader& load = {},
                                std::string* release = nullptr) {
    const auto decoded = [&] {
        if (release) std::string().swap(*release);
    };
    detail::ReaderOutput parsed;
    // Polygon faces are always parsed and triangulated, so that one error can name every
    // repair the input needs (the duplicates of a polygon file show only once it is read);
    // finish_reading refuses them unless the triangulate_polygons repair was asked for.
    constexpr bool polygons = true;
    try {
        switch (format) {
            case SurfaceFormat::Off: parsed = detail::read_off(bytes, name, polygons); break;
            case SurfaceFormat::Obj: parsed = detail::read_obj(bytes, name, polygons); break;
            case SurfaceFormat::Stl: parsed = detail::read_stl(bytes, name); break;
            case SurfaceFormat::Ply: parsed = detail::read_ply(bytes, name, polygons); break;
            case SurfaceFormat::Msh:
            case SurfaceFormat::Msh22: parsed = detail::read_msh(bytes, name); break;
            case SurfaceFormat::Vtk: parsed = detail::read_vtk(bytes, name, polygons); break;
            case SurfaceFormat::Vtp:
            case SurfaceFormat::Vtu: parsed = detail::read_vtk_xml(bytes, name, polygons); break;
            case SurfaceFormat::Surf: parsed = detail::read_surf(bytes, name); break;
            case SurfaceFormat::Nifti: {
                std::vector<std::string> notes;
                LabelImage image = detail::read_nifti_image(bytes, name, &notes);
                decoded();
                parsed = detail::label_image_reader_output(std::move(image), name, options.label_image,
                                                           options.context ? *options.context : Context{}, std::move(notes));
                break;
            }
            case SurfaceFormat::Nrrd: {
                std::vector<std::string> notes;
                LabelImage image = detail::read_nrrd_image(bytes, name, &notes);
                decoded();
                parsed = detail::label_image_reader_output(std::move(image), name, options.label_image,
                                                           options.context ? *options.context : Context{}, std::move(notes));
                break;
            }
            case SurfaceFormat::MetaImage: {
                std::vector<std::string> notes;
                LabelImage image = detail::read_metaimage_image(bytes, name, load, &notes);
                decoded();
                parsed = detail::label_image_reader_output(std::move(image), name, options.label_image,
                                                           options.context ? *options.context : Context{}, std::move(notes));
                break;
            }
        }
    } catch (const InputError& e) {
        const std::string hint = sniffed_format_hint(bytes, format);
        if (hint.empty()) throw;
        throw InputError(e.where(), e.what() + hint);
    }
    return finish_reading(std::move(parsed), format, name, options, report, material);
}

Surface read_surface_from_memory(const std::string& bytes, SurfaceFormat format, const std::string& name,
                                 const SurfaceReadOptions& options, SurfaceReadReport* report) {
    if (detail::looks_like_gzip(bytes))
        return read_from_memory(detail::decompress_if_gzip(bytes, name, false), format, name, options, report, {});
    return read_from_memory(bytes, format, name, options, report, {});
}

// The pieces of a parallel VTK XML file (.pvtp / .pvtu), read from the files its <Piece
// Source=...> elements name (relative to its directory) and joined into one surface:
// triangles and patches in piece order, the point data arrays every piece has, and the
// points that several pieces share (their borders) merged.
static detail::ReaderOutput read_parallel_vtk_xml(const std::string& path, const std::string& name,
                                                  const std::string& bytes) {
    const std::vector<std::string> sources = detail::parallel_vtk_xml_sources(bytes, name);
    const std::filesystem::path dir = std::filesystem::path(path).parent_path();
    detail::ReaderOutput all;
    Surface& s = all.surface;
    std::vector<std::string> dropped;  // point data arrays not in every piece
    for (size_t k = 0; k < sources.size(); ++k) {
        const std::string piece_path = (dir / sources[k]).string();
        std::string piece_bytes;
        try {
            piece_bytes = detail::read_whole_input(piece_path);
        } catch (const InputError& e) {
            throw InputError(name, "piece " + std::to_string(k) + " (Source " + detail::quote_token(sources[k]) + "): " +
                                       e.where() + ": " + e.what());
        }
        if (is_parallel_vtk_xml(piece_bytes)) {
            throw InputError(name, "piece " + std::to_string(k) + " (Source " + detail::quote_token(sources[k]) +
                                       ") is a parallel file itself; the pieces must be .vtp or .vtu files");
        }
        // Polygons always triangulated, as in read_from_memory.
        detail::ReaderOutput part = detail::read_vtk_xml(piece_bytes, detail::display_name(piece_path), true);
        if (all.triangulated_polygons.empty() && !part.triangulated_polygons.empty())
            all.triangulated_polygons = "piece " + std::to_string(k) + " (Source " + detail::quote_token(sources[k]) +
                                        "): " + part.triangulated_polygons;
        const int32_t offset = s.num_vertices();
        if (int64_t(offset) + part.surface.num_vertices() > std::numeric_limits<int32_t>::max())
            throw InputError(name, "the pieces have more than 2147483647 points together");
        s.vertices.insert(s.vertices.end(), part.surface.vertices.begin(), part.surface.vertices.end());
        for (Tri t : part.surface.triangles) {
            for (int32_t& v : t) v += offset;
            s.triangles.push_back(t);
        }
        s.patches.insert(s.patches.end(), part.surface.patches.begin(), part.surface.patches.end());
        if (k == 0) {
            s.vertex_data = std::move(part.surface.vertex_data);
        } else {
            std::vector<VertexArray> kept;
            for (VertexArray& a : s.vertex_data) {
                auto match = std::find_if(part.surface.vertex_data.begin(), part.surface.vertex_data.end(),
                                          [&](const VertexArray& b) { return b.name == a.name && b.components == a.components; });
                if (match == part.surface.vertex_data.end()) {
                    dropped.push_back(a.name);
                    continue;
                }
                a.values.insert(a.values.end(), match->values.begin(), match->values.end());
                kept.push_back(std::move(a));
            }
            for (const VertexArray& b : part.surface.vertex_data)
                if (std::none_of(kept.begin(), kept.end(), [&](const VertexArray& a) { return a.name == b.name; }))
                    dropped.push_back(b.name);
            s.vertex_data = std::move(kept);
        }
        all.skipped_elements += part.skipped_elements;
        for (std::string& note : part.notes) all.notes.push_back(sources[k] + ": " + note);
    }
    std::sort(dropped.begin(), dropped.end());
    dropped.erase(std::unique(dropped.begin(), dropped.end()), dropped.end());
    for (const std::string& d : dropped)
        all.notes.push_back("point data " + detail::quote_token(d) + " left out: not in every piece (or not with the same components)");
    const int64_t merged = merge_duplicate_vertices(s);
    all.notes.push_back(std::to_string(sources.size()) + (sources.size() == 1 ? " piece" : " pieces") + " joined; " +
                        std::to_string(merged) + " points that pieces share merged");
    return all;
}

// Edges with exactly two triangles that run along them the same way: the two triangles
// face opposite sides of the surface (e.g. triangles flipped in an STL export). Accepted
// (bpm-simplify and bpm-check work on them), but the front side that patch_info's
// materials refer to changes there, and phi's pieces turn by up to 180 degrees; before,
// nothing said so. Empty when the orientation is consistent.
static std::string orientation_warning(const detail::EdgeUses& edges) {
    int64_t same_way = 0;
    std::pair<int32_t, int32_t> first_triangles{-1, -1};  // the smallest pair, for a stable message
    std::pair<int32_t, int32_t> first_edge{-1, -1};
    edges.for_each_edge([&](int32_t a, int32_t b, const detail::EdgeUses::Use* uses, size_t count) {
        if (count != 2 || uses[0].ascending() != uses[1].ascending()) return;
        const std::pair<int32_t, int32_t> triangles{uses[0].triangle(), uses[1].triangle()};
        if (same_way++ == 0 || triangles < first_triangles) first_triangles = triangles, first_edge = {a, b};
    });
    if (same_way == 0) return {};
    return "the triangles are not consistently oriented: at " + std::to_string(same_way) + " edge" +
           (same_way == 1 ? "" : "s") + " two neighbours face opposite sides (first: triangles " +
           std::to_string(first_triangles.first) + " and " + std::to_string(first_triangles.second) +
           " at the edge of vertices " + std::to_string(first_edge.first) + " and " +
           std::to_string(first_edge.second) +
           "); bpm keeps them as they are, so the materials of their front and back sides and phi's "
           "normals flip there (phi turns such pieces by up to 180 degrees). Orient the input consistently "
           "(e.g. MeshLab: Re-Orient all faces coherently)";
}

static std::string short_number(double x) { return detail::three_digit_text(x); }

// The merge_vertices_within repair on `surface` (a file, or several together), refused
// when it would collapse a triangle: a tolerance that large merges the model's own
// vertices, not a seam's.
static void merge_within(Surface& surface, double tolerance, const std::string& name, SurfaceReadReport& r) {
    if (!(tolerance >= 0 && tolerance < 1))
        throw OptionError("the vertex merge tolerance must be a fraction of the bounding-box diagonal, >= 0 and < 1 "
                          "(got " + short_number(tolerance) + ")");
    const double diagonal = bounding_box_diagonal(surface.vertices);
    if (!(diagonal > 0) || !std::isfinite(diagonal)) return;  // validate_surface() says why
    const CloseVertexMerge m = merge_close_vertices(surface, tolerance * diagonal);
    if (m.collapsed_triangle >= 0) {
        const auto [a, b] = m.collapsed_corners;
        const double apart = distance(surface.vertices[size_t(a)], surface.vertices[size_t(b)]) / diagonal;
        throw InputError(name, "merging vertices within " + short_number(tolerance) +
                                   " of the bounding-box diagonal would join vertices " + std::to_string(a) + " and " +
                                   std::to_string(b) + " of triangle " + std::to_string(m.collapsed_triangle) +
                                   ", which are " + short_number(apart) +
                                   " of the diagonal apart: the tolerance must be well below the length of the "
                                   "triangles' edges (seams left open by rounding are about 1e-9 of the diagonal)");
    }
    r.merged_vertices += m.merged;
    r.largest_merge_move = std::max(r.largest_merge_move, m.largest_move / diagonal);
    if (m.merged > 0)
        r.notes.push_back("merged " + std::to_string(m.merged) + " vertices within " + short_number(tolerance) +
                          " of the bounding-box diagonal (the largest move: " +
                          short_number(m.largest_move / diagonal) + " of the diagonal)");
}

// The open seam of a valid surface, if any, and the merge tolerance that closes it.
// `boundary`: the surface's boundary edges (EdgeUses::boundary_edges()).
static void find_seam(const Surface& surface, const std::vector<std::pair<int32_t, int32_t>>& boundary,
                      SurfaceReadReport& r) {
    r.open_seam.reset();
    r.seam_merge_tolerance = 0.0;
    if (boundary.empty()) return;  // closed: no seam
    const double diagonal = bounding_box_diagonal(surface.vertices);
    if (!(diagonal > 0) || !std::isfinite(diagonal)) return;
    std::optional<OpenSeam> seam = detail::find_open_seam(surface, boundary, kOpenSeamMaxGap * diagonal);
    if (!seam) return;
    r.seam_merge_tolerance = seam_merge_tolerance(surface, *seam, diagonal);
    seam->gap /= diagonal;
    r.open_seam = seam;
}

// After a reader: the repairs asked for, then the validation. `material`: the material
// the file encloses if its format says nothing about its patches (apply_file_material).
static Surface finish_reading(detail::ReaderOutput parsed, SurfaceFormat format, const std::string& name,
                              const SurfaceReadOptions& options, SurfaceReadReport* report,
                              const std::string& material) {
    Surface surface = std::move(parsed.surface);
    if (const std::vector<std::string> bad = vertex_data_problems(surface); !bad.empty()) {
        std::string message = bad[0];
        for (size_t i = 1; i < bad.size() && i < 10; ++i) message += "; " + bad[i];
        throw InputError(name, message);
    }

    SurfaceReadReport local;
    SurfaceReadReport& r = report ? *report : local;
    r = SurfaceReadReport{};
    r.format = format;
    r.skipped_elements = parsed.skipped_elements;
    r.frame = parsed.frame;
    r.notes = std::move(parsed.notes);
    r.patch_info = std::move(parsed.patch_info);
    apply_file_material(r.patch_info, surface, material);
    // Names without materials (OBJ groups): on the file's material where it applies, else
    // alone. Only for patches that have triangles (as apply_file_material).
    if (!parsed.patch_names.empty()) {
        const std::set<int32_t> used(surface.patches.begin(), surface.patches.end());
        for (auto& [patch, patch_name] : parsed.patch_names) {
            if (!used.count(patch)) continue;
            if (PatchInfo* info = find_patch_info(r.patch_info, patch)) {
                if (is_file_material(*info, material)) info->name = std::move(patch_name);
            } else {
                r.patch_info.push_back(PatchInfo{patch, std::move(patch_name), {}, {}, true});
            }
        }
        std::sort(r.patch_info.begin(), r.patch_info.end(),
                  [](const PatchInfo& a, const PatchInfo& b) { return a.patch < b.patch; });
    }
    if (options.merge_duplicate_vertices) r.merged_vertices = merge_duplicate_vertices(surface);
    if (options.merge_vertices_within != 0) merge_within(surface, options.merge_vertices_within, name, r);
    if (options.drop_unreferenced_vertices) r.dropped_vertices = drop_unreferenced_vertices(surface);
    if (options.merge_duplicate_triangles) fuse_triangles(surface, r, "", material);

    if (surface.triangles.empty()) {
        std::string message = "the surface has no triangles";
        if (!surface.vertices.empty() || r.dropped_vertices > 0) {
            message += " (" + std::to_string(surface.vertices.size() + static_cast<size_t>(r.dropped_vertices)) +
                       " vertices and no faces: a point cloud?)";
        }
        if (r.skipped_elements > 0) message += "; " + std::to_string(r.skipped_elements) + " non-triangle elements were skipped";
        // VTK: what was skipped ("12 line cells skipped") says what the file holds instead.
        if (format == SurfaceFormat::Vtk || format == SurfaceFormat::Vtp || format == SurfaceFormat::Vtu)
            for (const std::string& note : r.notes) message += "; " + note;
        throw InputError(name, message);
    }
    ValidateOptions validate;
    validate.max_problems = 100;
    const std::vector<SurfaceProblem> problems = validate_surface(surface, validate);
    const std::string polygons = options.triangulate_polygons ? std::string() : parsed.triangulated_polygons;
    if (!problems.empty() || !polygons.empty()) {
        // A volume mesh (gmsh -3, a VTK unstructured grid) read as a surface: its cells are
        // skipped, and the vertices inside the volume are then "not used by any triangle".
        // Without the why, that error read like a broken file.
        std::string prefix;
        const bool unreferenced = std::any_of(problems.begin(), problems.end(), [](const SurfaceProblem& p) {
            return p.kind == SurfaceProblem::Kind::UnreferencedVertex;
        });
        if (unreferenced && r.skipped_elements > 0)
            prefix = std::to_string(r.skipped_elements) + " element" + (r.skipped_elements == 1 ? " that is" : "s that are") +
                     " not triangles skipped (the cells of a volume mesh?), so vertices only they use are used by no "
                     "triangle: ";
        throw_surface_problems(name, prefix, polygons, problems, surface, options, validate);
    }
    // The edges are grouped once, for both the orientation and the seam.
    const detail::EdgeUses edges(surface);
    if (std::string w = orientation_warning(edges); !w.empty()) r.warnings.push_back(std::move(w));
    find_seam(surface, edges.boundary_edges(), r);
    return surface;
}

Surface read_surface(const std::string& path, const SurfaceReadOptions& options, SurfaceReadReport* report) {
    const std::string name = detail::display_name(path);
    std::optional<SurfaceFormat> format = options.format;
    if (!format) format = surface_format_from_path(path);
    if (!format && path == "-") throw InputError(name, "the format of standard input must be given explicitly");
    std::string bytes = detail::read_whole_input(path);
    // A .bpm file (HDF5) passed where a surface belongs, e.g. to simplify it further: the
    // error was "cannot tell the surface format from the file name", or with a format given
    // a parse error at byte 0.
    if (bytes.compare(0, 8, "\x89HDF\r\n\x1a\n") == 0)
        throw InputError(name, "an HDF5 file (a .bpm?), not a surface: the surface readers take .off, .obj, .stl, "
                               ".ply, .msh, .vtk, .vtp, .vtu and .surf files. A .bpm file's coarse surface is written "
                               "out by bpm-refine FILE --levels 0 -o coarse.off");
    // One file per material: the material is the file's name without directory and extension.
    const std::string material =
        path == "-" ? std::string() : std::filesystem::path(detail::without_gz_suffix(path)).stem().string();
    if ((!format || format == SurfaceFormat::Vtp || format == SurfaceFormat::Vtu) && is_parallel_vtk_xml(bytes))
        return finish_reading(read_parallel_vtk_xml(path, name, bytes), format.value_or(SurfaceFormat::Vtp),
                              name, options, report, material);
    // No (known) extension: only a HyperSurface head is taken as the format (a first line
    // "# HyperSurface" cannot be mistaken for anything else); every other format needs its
    // extension or an explicit choice.
    if (!format && format_from_head(bytes) == SurfaceFormat::Surf) format = SurfaceFormat::Surf;
    if (!format && format_from_head(bytes) == SurfaceFormat::Nifti) format = SurfaceFormat::Nifti;
    if (!format && format_from_head(bytes) == SurfaceFormat::Nrrd) format = SurfaceFormat::Nrrd;
    if (!format && format_from_head(bytes) == SurfaceFormat::MetaImage) format = SurfaceFormat::MetaImage;
    if (!format) {
        throw InputError(name, "cannot tell the surface format from the file name; expected the extension .off, "
                               ".obj, .stl, .ply, .msh, .vtk, .vtp, .vtu, .pvtp, .pvtu, .surf, .nii (.nii.gz), .nrrd, .mha or .mhd, or an explicit "
                               "format");
    }
    // A MetaImage header's data file: next to the header, read as it is (no gzip sniffing:
    // raw voxels may start with any bytes; .zraw is zlib data the reader inflates).
    // Only a regular file: a header naming /dev/zero or a FIFO would read until memory ran
    // out or hang. (An absolute name or "../" is followed, as ITK does.)
    const detail::DataFileLoader load = [&](const std::string& file) -> std::string {
        if (path == "-") throw InputError(name, "standard input has no directory to find it in");
        const std::filesystem::path data_path = std::filesystem::path(path).parent_path() / file;
        std::error_code ec;
        if (std::filesystem::exists(data_path, ec) && !std::filesystem::is_regular_file(data_path, ec))
            throw InputError(data_path.string(), "the header's ElementDataFile is not a regular file");
        std::ifstream in(data_path, std::ios::binary);
        if (!in) throw InputError(data_path.string(), "cannot open it");
        std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        if (in.bad()) throw InputError(data_path.string(), "cannot read it");
        return data;
    };
    return read_from_memory(bytes, *format, name, options, report, material, load, &bytes);
}

Surface read_surfaces(const std::vector<std::string>& paths, const SurfaceReadOptions& options,
                      SurfaceReadReport* report) {
    if (paths.size() == 1) return read_surface(paths[0], options, report);
    if (paths.empty()) throw OptionError("no input surface given");
    for (const std::string& path : paths)
        if (path == "-") throw OptionError("'-' (standard input) can only be the one input, not one of several");
    SurfaceReadReport local;
    SurfaceReadReport& r = report ? *report : local;
    r = SurfaceReadReport{};
    std::vector<Surface> parts;
    std::vector<std::vector<PatchInfo>> part_infos;
    std::string names;
    for (size_t i = 0; i < paths.size(); ++i) {
        const std::string name = detail::display_name(paths[i]);
        names += (i ? " + " : "") + name;
        SurfaceReadReport one;
        parts.push_back(read_surface(paths[i], options, &one));
        if (i == 0) r.format = one.format, r.frame = one.frame;
        if (one.frame != r.frame) r.frame = ImageFrame::Unknown;
        r.merged_vertices += one.merged_vertices;
        r.dropped_vertices += one.dropped_vertices;
        r.fused_triangles += one.fused_triangles;
        r.largest_merge_move = std::max(r.largest_merge_move, one.largest_merge_move);
        r.skipped_elements += one.skipped_elements;
        for (const std::string& note : one.notes) r.notes.push_back(name + ": " + note);
        for (const std::string& warning : one.warnings) r.warnings.push_back(name + ": " + warning);
        part_infos.push_back(std::move(one.patch_info));
    }
    std::vector<std::pair<int, int32_t>> origin;
    std::vector<std::string> dropped;
    Surface surface = combine_surfaces(parts, &origin, &dropped);
    for (size_t p = 0; p < origin.size(); ++p) {
        r.notes.push_back("patch " + std::to_string(p) + " = " + detail::display_name(paths[size_t(origin[p].first)]) +
                          " patch " + std::to_string(origin[p].second));
        if (const PatchInfo* info = find_patch_info(part_infos[size_t(origin[p].first)], origin[p].second)) {
            r.patch_info.push_back(*info);
            r.patch_info.back().patch = static_cast<int32_t>(p);
        }
    }
    for (const std::string& name : dropped)
        r.notes.push_back("vertex data '" + name + "' left out: not every input has it (with the same components)");
    // Inputs that touch share positions, not vertices, until the repair merges them.
    if (options.merge_duplicate_vertices) r.merged_vertices += merge_duplicate_vertices(surface);
    if (options.merge_vertices_within != 0) merge_within(surface, options.merge_vertices_within, names, r);
    // Then the interfaces that two files both have are the same triangles.
    if (options.merge_duplicate_triangles) fuse_triangles(surface, r, "the inputs together: ", "");
    ValidateOptions validate;
    validate.max_problems = 100;
    validate.allow_unreferenced_vertices = options.drop_unreferenced_vertices;
    const std::vector<SurfaceProblem> problems = validate_surface(surface, validate);
    if (!problems.empty())
        throw_surface_problems(names, "the inputs together (vertices and triangles numbered across the files in order): ", "",
                               problems, surface, options, validate);
    // Of all inputs together: files that touch close each other's boundaries.
    find_seam(surface, detail::EdgeUses(surface).boundary_edges(), r);
    return surface;
}

}  // namespace bpm
