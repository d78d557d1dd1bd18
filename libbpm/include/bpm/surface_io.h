#pragma once
// Reading and writing triangulated surfaces in the common mesh formats.
//
// Supported (chosen by file extension or explicitly):
//   OFF   (.off)         ASCII; polygons with more than 3 corners are rejected (OFF, OBJ,
//                        PLY), unless the triangulate_polygons repair is asked for
//   OBJ   (.obj)         `v`/`f` records; `g` and `usemtl` groups become patch ids
//   STL   (.stl)         ASCII and binary; vertices are merged by exact position
//   PLY   (.ply)         ASCII, binary_little_endian, binary_big_endian; a face property
//                        named patch / material / region / label / physical becomes the patch id
//   MSH   (.msh)         Gmsh 2.2 and 4.1, ASCII and binary; triangles only (other elements
//                        are skipped and counted); the physical tag is the patch id.
//                        The format name "msh22" reads the same (any version) and writes
//                        MSH 2.2 ASCII (for DUNE 2.9's GmshReader and older tools)
//   VTK   (.vtk)         legacy VTK 1.0-5.1, ASCII and BINARY, POLYDATA (polygons, triangle
//                        strips) and UNSTRUCTURED_GRID (triangles, quads, polygons, strips);
//                        vertex, line and (next to surface cells) volume cells are skipped and
//                        counted; every POINT_DATA array becomes a VertexArray; a CELL_DATA
//                        array named patch / material / region / label / physical (or
//                        gmsh:physical, CellEntityIds, RegionId) gives the patch id. Read only:
//                        write_surface refuses VTK.
//   VTP, VTU (.vtp .vtu) VTK XML PolyData / UnstructuredGrid (read only): ascii, binary and
//                        appended data, raw or base64, zlib-compressed or not; triangles,
//                        strips (split), polygons and quads (with triangulate_polygons);
//                        other cells skipped with a note. PointData arrays become vertex
//                        data; a CellData array named patch / material / region / label /
//                        physical / gmsh:physical / CellEntityIds / RegionId the patch id
//   SURF  (.surf)        Amira / Avizo HyperSurface 0.1, ASCII and BINARY (read only): each
//                        Patches entry is a patch (0, 1, ... in file order; the notes and
//                        patch_info name its InnerRegion / OuterRegion); Parameters, BoundaryCurves and
//                        Surfaces are parsed and not used. Details in read_surf.cpp.
//   NIfTI (.nii .nii.gz) NIfTI-1 label images (read only): a segmentation with one integer
//                        label per voxel becomes its multi-material surface by surface nets
//                        (bpm/label_image.h): one patch per pair of labels that touch, named
//                        and given materials in patch_info (label 0 = "exterior", label L =
//                        "label_L"). Details in read_nifti.cpp.
//   NRRD  (.nrrd)        NRRD label images (read only), 3D Slicer's .seg.nrrd included (its
//                        segment names name the materials): raw, gzip and ascii encodings,
//                        attached data. Details in read_nrrd.cpp.
//   MetaImage (.mha .mhd) ITK MetaImage label images (read only): one file (.mha, or .mhd
//                        with ElementDataFile LOCAL) or a header with its data file (.mhd +
//                        .raw/.zraw, found next to the header: read_surface of a path only),
//                        zlib-compressed or not. Details in read_metaimage.cpp.
// Label images' surfaces come out in one anatomical frame (SurfaceReadOptions::label_image).
// Every triangle gets a patch id (0 when the format has none). In detail:
//   OBJ  each distinct (group names, material) pair is a patch, numbered 0, 1, ... in the
//        order faces first use it; but when there is no `usemtl` and every face is in a
//        group named `patch_<N>` (as write_surface writes them), N is the patch id.
//   STL  ASCII: each `solid ... endsolid` block is a patch (0, 1, ...); binary: 0.
//        Vertices are numbered in order of first use by the triangles.
//   PLY  the first such face property in header order; integer values only.
//   MSH  2.2: the first element tag (physical); 4.1: the first physical tag of the
//        element's entity in $Entities; 0 when there is none. $PhysicalNames of
//        dimension 2 name the patches (patch_info; "A|B" or "pair_A_B" names give materials).
//        A file with the section $BpmPatchIds holding k (as bpm writes, k = 1) has patch
//        = physical tag - k, names too; a triangle tagged below k is an error.
//   VTK  the first such integer-valued 1-component cell array (SCALARS or FIELD); the
//        triangles of a strip or polygon keep their cell's id. Details in read_vtk.cpp.
// Polygons (faces with more than three corners) are never triangulated silently: without
// triangulate_polygons the read fails with InputNeedsRepair naming that repair and every
// other one the triangulated surface needs.
//
// The format is chosen by options.format, else by the extension; a file without a known
// extension whose first line starts with "# HyperSurface" is read as SURF, one with NIfTI-1's
// magic as NIfTI, one starting "NRRD000" as NRRD, one starting "ObjectType = Image" as MetaImage.
//
// Compressed input: gzip data (a file, standard input or a buffer that starts with the
// gzip magic bytes) is decompressed first, and the format of FILE.EXT.gz is told by EXT
// (femur.off.gz is OFF). A name ending in .gz must hold gzip data; truncated or corrupt
// gzip data is an InputError saying so.
//
// Parallel VTK XML (.pvtp / .pvtu, read_surface only: the pieces are other files): the
// files its <Piece Source=...> name, relative to its directory, are read as VTP / VTU and
// joined in order, and the points that pieces share (their borders) are merged; point
// data arrays not in every piece are left out with a note. Ghost levels above 0 are
// refused (the ghost cells would be there twice).
//
// Errors: every malformed input throws bpm::InputError naming the file and the line
// (text formats) or element / byte offset (binary formats). Counts in headers are never
// trusted for allocation before they are checked against the size of the input. A file
// without triangles (e.g. a point cloud) is an error too.

#include <cstdint>
#include <istream>
#include <optional>
#include <string>
#include <vector>

#include "bpm/context.h"
#include "bpm/errors.h"
#include "bpm/label_image.h"
#include "bpm/mesh_encoding.h"
#include "bpm/patch_info.h"
#include "bpm/surface.h"

namespace bpm {

// Vtp, Vtu: VTK XML PolyData / UnstructuredGrid, read only (bpm-refine writes .vtu with
// its own writer, write_surface_vtu in bpm/write_vtu.h). Surf: Amira HyperSurface, read only.
// Msh writes MSH 4.1, Msh22 MSH 2.2; both read every MSH version.
// Nifti, Nrrd, MetaImage: label images, read only (their surface is extracted, bpm/label_image.h).
enum class SurfaceFormat { Off, Obj, Stl, Ply, Msh, Msh22, Vtk, Vtp, Vtu, Surf, Nifti, Nrrd, MetaImage };

// "off", "obj", "stl", "ply", "msh", "msh22", "vtk", "vtp", "vtu", "surf", "nii", "nrrd", "mha", "mhd" (case-insensitive)
// -> format; nullopt otherwise. The extension .msh is Msh.
std::optional<SurfaceFormat> surface_format_from_name(const std::string& name);
// Format from the extension of `path` (before a final .gz); nullopt if unknown.
std::optional<SurfaceFormat> surface_format_from_path(const std::string& path);

struct SurfaceReadOptions {
    std::optional<SurfaceFormat> format;      // overrides the extension; required for "-"
    bool merge_duplicate_vertices = false;    // repair: merge vertices at identical positions
    // Repair: merge vertices within this fraction of the bounding-box diagonal (0 = off;
    // merge_close_vertices in bpm/surface.h, duplicates included), for a seam that an
    // export left open by rounding. With several inputs, each file is merged with its own
    // diagonal, then the files together with theirs (so files that touch are joined too).
    // A tolerance that would give a triangle two equal corners is refused (InputError).
    double merge_vertices_within = 0.0;
    bool drop_unreferenced_vertices = false;  // repair: remove vertices no triangle uses
    // Repair: fuse triangles with the same three vertices into one (fuse_duplicate_triangles
    // in bpm/surface.h; after merge_duplicate_vertices): the shared interfaces of one closed
    // surface per material become patches of their own (reported in notes).
    bool merge_duplicate_triangles = false;
    // Repair: split faces with more than three corners (OFF, OBJ, PLY, VTK) into triangles by
    // ear clipping in the face's plane (reported in SurfaceReadReport::notes); a face that
    // is not a simple polygon seen along its normal is still refused.
    bool triangulate_polygons = false;
    // Progress and log lines of a slow read (the surface extraction of a label image);
    // may be null. Must outlive the call.
    const Context* context = nullptr;
    // Label images (NIfTI, NRRD, MetaImage): how their surface is extracted, and the frame
    // of its coordinates (label_image.frame, LPS by default: one segmentation gives the same
    // coordinates from every format; SurfaceReadReport::frame says what was done).
    LabelSurfaceOptions label_image;
};

// What a read did besides producing the surface, for the tool to report.
struct SurfaceReadReport {
    SurfaceFormat format = SurfaceFormat::Off;
    int64_t merged_vertices = 0;       // by the requested repair
    int64_t dropped_vertices = 0;      // by the requested repair
    int64_t fused_triangles = 0;       // removed by the requested repair (merge_duplicate_triangles)
    int64_t skipped_elements = 0;      // non-triangle elements of MSH files, non-surface cells of VTK files, that were ignored
    std::vector<std::string> notes;    // other human-readable remarks
    // Remarks on what the input is likely to get wrong although it is accepted, e.g. a
    // surface whose triangles are not consistently oriented (front sides, and so the
    // materials of patch_info, differ between neighbours).
    std::vector<std::string> warnings;
    // Names and materials of the patches (bpm/patch_info.h), sorted by patch id: from the
    // format (SURF regions, MSH $PhysicalNames), else, for read_surface of a path, the
    // file-per-material convention (material = the file name without directory and
    // extension); fused interfaces get theirs from the patches they join. Empty when
    // nothing is known (standard input or memory in a format without names).
    std::vector<PatchInfo> patch_info;
    // The largest distance a vertex moved in merge_vertices_within, as a fraction of the
    // bounding-box diagonal.
    double largest_merge_move = 0.0;
    // The anatomical frame of the coordinates: that of a label image's surface
    // (SurfaceReadOptions::label_image.frame, unless the image has none); Unknown for other
    // inputs, and for several inputs that are not all label images of one frame.
    ImageFrame frame = ImageFrame::Unknown;
    // An open seam the surface (all inputs together) still has: boundary edges that pair
    // up with others within 1e-6 of the diagonal (find_open_seam; its gap here as a
    // fraction of the diagonal). Open surfaces are accepted, but they do not enclose a
    // volume (bpm-mesh), and the seam is usually an export's rounding.
    std::optional<OpenSeam> open_seam;
    // A merge_vertices_within (a power of 10) that closes those edges without collapsing
    // a triangle; 0 if there is none.
    double seam_merge_tolerance = 0.0;
};

// The repairs of SurfaceReadOptions, named for InputNeedsRepair.
enum class SurfaceRepair {
    TriangulatePolygons,  // SurfaceReadOptions::triangulate_polygons (faces with more than three corners)
    MergeDuplicateVertices,
    DropUnreferencedVertices,
    MergeDuplicateTriangles
};

// An input that parsed but is unusable as it is, and that the listed repairs would make
// usable (problems other than these may remain). All repairs are listed at once: the
// ones the problems found ask for, and those that problems revealed by applying them ask
// for (duplicate triangles appear only once duplicate vertices are merged, as in one
// closed surface per material). The message describes the first problems.
class InputNeedsRepair : public InputError {
public:
    InputNeedsRepair(std::string where, const std::string& message, std::vector<SurfaceRepair> repairs)
        : InputError(std::move(where), message), repairs_(std::move(repairs)) {}
    const std::vector<SurfaceRepair>& repairs() const { return repairs_; }

private:
    std::vector<SurfaceRepair> repairs_;
};

// Reads and validates a surface (see validate_surface in bpm/surface.h): NaN/Inf,
// out-of-range indices, zero-area and duplicate triangles, unreferenced and duplicate
// vertices are errors unless the matching repair option is set. "-" reads standard input.
// \throw InputNeedsRepair when repairs would help (listing every one needed), InputError
//        for other problems.
Surface read_surface(const std::string& path, const SurfaceReadOptions& options = {},
                     SurfaceReadReport* report = nullptr);

// Several surfaces read as one (one file per material, say): each is read as above, then
// combined by combine_surfaces (bpm/surface.h; patches of different files stay apart,
// notes say which new patch is which file's), the merge repair is applied across the
// files, and the combination is validated again (touching inputs share positions: without
// --merge-duplicate-vertices that is reported as duplicate vertices). One path is
// read_surface(); "-" may only be the one path (throws OptionError otherwise).
Surface read_surfaces(const std::vector<std::string>& paths, const SurfaceReadOptions& options = {},
                      SurfaceReadReport* report = nullptr);

// Same, from an in-memory buffer; `name` is used in error messages.
Surface read_surface_from_memory(const std::string& bytes, SurfaceFormat format, const std::string& name,
                                 const SurfaceReadOptions& options = {}, SurfaceReadReport* report = nullptr);

// Writes OFF, OBJ (patches as `g patch_N`), STL (binary), PLY (binary little endian with
// an int `patch` face property when a triangle is not in patch 0), MSH 4.1 ASCII or binary
// (`encoding`, bpm/mesh_encoding.h) or MSH 2.2 ASCII (patch p as physical tag p + 1 named as
// `patch_info` names it, else "patch_<p>", and a section $BpmPatchIds from which bpm reads the
// patch ids back; MSH only: the other formats have no patch names), atomically
// (not VTK, VTP, VTU or SURF: an OutputError):
// to a temporary name in the same directory, renamed when complete. "-" writes stdout.
// Output is deterministic; text formats write doubles with 17 significant digits, so
// reading back gives the same surface bit for bit (patches are lost in OFF; STL stores
// float coordinates, no patches, and numbers vertices in order of first use).
// Throws OutputError for an unwritable path and for a surface that could not be read
// back: patches.size() != triangles.size(), an index out of range, a NaN/Inf coordinate;
// and for an encoding the format lacks (OFF, OBJ, MSH 2.2 binary; anything compressed).
void write_surface(const std::string& path, const Surface& surface,
                   std::optional<SurfaceFormat> format = std::nullopt, MeshEncoding encoding = MeshEncoding::Ascii,
                   const std::vector<PatchInfo>& patch_info = {});

}  // namespace bpm
