#pragma once
// A 3-D label image (a CT/MR segmentation: one integer label per voxel) and the
// multi-material surface between its labels, by multi-label surface nets.
//
// The surface (label_image_surface) has one patch per pair of labels that touch, with
// patch_info naming the two materials (spec/bpm-format.md §5.2): label 0 is the background,
// material kExteriorMaterial ("exterior"); label L is material "label_L" unless
// LabelImage::names says otherwise. Every patch is oriented: its triangles face the
// smaller label (front = smaller label's material, back = larger one's; so a label inside
// background has outward normals, as one closed surface per material has), and it is named
// "<back>|<front>" like the other multi-material inputs. bpm-mesh then gives every region
// the material of its label.
//
// Method (Frisken Gibson, "Constrained elastic SurfaceNets", MICCAI 1998; the multi-label
// form of VTK's vtkSurfaceNets3D): voxel centres are the corners of a dual grid of cubes;
// a cube whose 8 voxels (outside the image: background) do not all have one label gets a
// vertex, and every pair of face-adjacent voxels with different labels a quad joining the
// vertices of the 4 cubes around the edge between their centres, split into two triangles
// along the diagonal whose triangles have the better worst aspect ratio (circumradius /
// inradius, measured in model space; of equal ones, the shorter diagonal). Where two voxels of one label touch only along an edge (a
// 2x2 "checkerboard" of voxels around the edge), the label's surface would be pinched
// along the edge, and one vertex per cube cannot represent it (two sheets would pass
// between the same two vertices). Such edges are removed from the image first: one of the
// two other voxels gets the diagonal label (of two diagonal labels, the larger), so that
// the label is face-connected there (LabelSurface::changed_voxels counts them). Then every
// edge of the surface is in exactly two triangles of each material it bounds. Where one
// label touches itself only at a voxel corner, the cube's vertex is split, one per sheet. Then constrained smoothing:
// Jacobi steps towards the mean of the neighbours, each vertex clamped to its cube (shrunk
// by a margin, so that vertices of different cubes never coincide); vertices on a junction
// line (an edge in 3+ quads, where 3+ labels meet) use only their two neighbours on the
// line, so that they move along it; where junction lines end or meet, vertices stay.
// Where the smoothed surface crosses itself (checked with bpm/check.h's exact test) or has
// a triangle of aspect ratio over 30 (smoothing straightens junction lines, and three
// vertices of a quad on one line make a sliver), the four vertices of the quad go back
// towards their unsmoothed places (the centroids of their voxel faces' midpoints; no test
// image crosses itself there, and their triangles measured R/r <= 5.4 on noisy images),
// half way at first, then all the way, until neither is left: the result does not cross
// itself (unless the centroids did; then it is returned as it is and bpm-simplify refuses
// it, naming the crossing) and its worst aspect ratio is at most max(30, the centroids').
//
// Memory: the image itself (compact: 1 byte per voxel for up to 256 distinct labels, else 2;
// plain labels are made compact first, 4 + 1 or 2 bytes a voxel while that runs) plus what
// is proportional to the surface; nothing else per voxel.

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "bpm/context.h"
#include "bpm/patch_info.h"
#include "bpm/surface.h"

namespace bpm {

// The anatomical frame of a label image's world coordinates. The axes of LPS point to the
// patient's Left, Posterior and Superior, those of RAS to the Right, Anterior and
// Superior: the same point is (x, y, z) in one and (-x, -y, z) in the other, a rotation by
// 180 degrees about z (which keeps orientation, so outward normals stay outward). DICOM,
// ITK, MetaImage and 3D Slicer's files use LPS; NIfTI's qform/sform give RAS.
// Unknown: coordinates with no anatomical frame (an NRRD space such as scanner-xyz or
// 3D-right-handed, or none), used as the file gives them.
enum class ImageFrame { Unknown, Lps, Ras };
const char* image_frame_name(ImageFrame frame);  // "LPS", "RAS", "" (Unknown)

struct LabelImage {
    std::array<int64_t, 3> size{0, 0, 0};  // voxels along i, j, k; each >= 1
    // Voxel (i, j, k) has its centre at origin + direction * (spacing ⊙ (i, j, k)):
    // spacing > 0 (model units, usually mm), direction a rotation or reflection given by
    // its columns (row-major 3x3: direction[3 * r + c] is row r of column c), the axes of i,
    // j, k in model space. A reflection (determinant < 0, common in NIfTI and DICOM) is
    // taken into account: the triangles still face the smaller label.
    std::array<double, 3> spacing{1, 1, 1};
    std::array<double, 3> origin{0, 0, 0};
    std::array<double, 9> direction{1, 0, 0, 0, 1, 0, 0, 0, 1};
    // The frame origin and direction are given in (the readers set it: NIfTI Ras, NRRD
    // its 'space', MetaImage Lps); label_image_surface converts to LabelSurfaceOptions::frame.
    ImageFrame frame = ImageFrame::Unknown;
    // size[0] * size[1] * size[2] labels, i fastest then j then k, in one of two forms
    // (label_image_surface takes either; the readers give the compact one). Plain: one
    // int32 per voxel (4 bytes a voxel) in `labels`...
    std::vector<int32_t> labels;
    // ... or, when `labels` is empty, compact: label_values are the distinct labels in
    // increasing order (0, the background outside the image, among them; at most 65536),
    // and each voxel holds the position of its label in label_values: in label_index8
    // (1 byte a voxel) when there are at most 256 values, else in label_index16 (2 bytes).
    // The surface depends only on the labels, not on the form they are given in.
    std::vector<int32_t> label_values;
    std::vector<uint8_t> label_index8;
    std::vector<uint16_t> label_index16;
    // Optional material names of labels (e.g. the segment names of a 3D Slicer file);
    // labels not listed are "label_<L>", label 0 "exterior".
    std::vector<std::pair<int32_t, std::string>> names;

    int64_t num_voxels() const { return size[0] * size[1] * size[2]; }
    bool compact() const { return labels.empty() && !label_values.empty(); }
    int32_t label_at(int64_t voxel) const {  // either form
        return !compact() ? labels[size_t(voxel)]
               : label_values.size() <= 256 ? label_values[label_index8[size_t(voxel)]]
                                            : label_values[label_index16[size_t(voxel)]];
    }
};

// Turns `image`'s plain labels into the compact form (LabelImage::labels emptied).
// \throw InputError (where = "label image") for more than 65536 distinct labels.
void compact_labels(LabelImage& image);

struct LabelSurfaceOptions {
    int smoothing_iterations = 20;  // 0: the vertices stay at the centroids of their quads' midpoints
    double relaxation = 0.5;        // fraction of the way to the neighbours' mean per step, in (0, 1]
    // How far a vertex may come to the faces of its cube, as a fraction of the voxel; in
    // (0, 0.5). Keeps vertices of neighbouring cubes apart.
    double margin = 0.05;
    // The frame of the output coordinates. An image in the other frame (LPS or RAS) is turned
    // by 180 degrees about z (x and y negated; orientation and outward normals are kept);
    // an image of frame Unknown keeps its own coordinates (LabelSurface::frame says which).
    // Unknown here: every image keeps its own frame (a NIfTI file RAS, a Slicer file LPS).
    ImageFrame frame = ImageFrame::Lps;
};

struct LabelSurface {
    Surface surface;                    // patches 0, 1, ... = the label pairs in increasing order
    std::vector<PatchInfo> patch_info;  // one per patch, sorted by patch id
    std::vector<std::array<int32_t, 2>> patch_labels;  // per patch: (smaller, larger) label
    std::vector<int32_t> labels;        // the distinct labels of the image, increasing
    int64_t split_vertices = 0;         // cube vertices split into two or more (one per sheet)
    int64_t changed_voxels = 0;         // voxels relabelled where a label touched itself along an edge only
    int64_t unresolved_contacts = 0;    // such edges left (normally 0)
    // Vertices moved back towards their unsmoothed place (in the last round) because the
    // smoothing made the surface cross itself there.
    int64_t unsmoothed_vertices = 0;
    // Vertices moved back towards their unsmoothed place because the smoothing had made a
    // triangle around them a sliver (circumradius / inradius > 30).
    int64_t sliver_vertices = 0;
    int64_t junction_vertices = 0;      // vertices where three or more labels meet
    // The frame of the surface's coordinates: LabelSurfaceOptions::frame (when not Unknown)
    // for an image in LPS or RAS; the image's own frame otherwise.
    ImageFrame frame = ImageFrame::Unknown;
};

// The material name of `label` in `image` (see LabelImage::names).
std::string label_material_name(const LabelImage& image, int32_t label);

// The problem that makes `image` unusable, empty if none: a size < 1, more than 2^31
// vertices possible, labels.size() not the voxel count (or, compact, the index vector's
// size; label_values not increasing, without 0, or more than 65536; an index beyond them), a spacing not finite and > 0, a
// direction that is not invertible or not finite, a non-finite origin.
std::string label_image_problem(const LabelImage& image);

// The multi-material surface of `image` (see the top). An image of one label only has
// no surface: the result is then empty (no triangles). Deterministic. Reports progress
// (fractions of the extraction, then the smoothing) through `context`. The image is taken
// by value (voxels may be relabelled, see the top): move it in to avoid the copy.
// \throw InputError (where = "label image") when label_image_problem() names one.
LabelSurface label_image_surface(LabelImage image, const LabelSurfaceOptions& options = {},
                                 const Context& context = {});

}  // namespace bpm
