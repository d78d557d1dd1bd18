#pragma once
// What the input says about the patches of a surface: a name per patch and the two
// materials the patch separates (spec/bpm-format.md §5.2, /patch_info). Kept next to the
// surfaces (BpmFile::patch_info) rather than in Surface, which most of bpm uses without
// needing names.
//
// Sources (bpm/surface_io.h, SurfaceReadReport::patch_info):
//   Amira HyperSurface  each Patches entry: front = OuterRegion, back = InnerRegion (the
//                       triangles' normals point from the inner to the outer region)
//   Gmsh MSH            $PhysicalNames of dimension 2 name the patches; a name that
//                       materials_from_patch_name() splits gives the two materials, in
//                       no known order (oriented = false)
//   Wavefront OBJ       the same convention for `g` group names, when at least one group
//                       name gives materials (else the groups say nothing, see below)
//   one file per material (read_surface of a path): file "dir/A.stl", if its format
//                       says nothing about its patches, encloses material "A": every
//                       patch gets front = "exterior", back = "A"; an interface fused from two files
//                       (--merge-duplicate-triangles) separates the two files' materials; in
//                       one file whose patches share triangles (a closed surface per label),
//                       patch P encloses "A_P" instead
//   label image (NIfTI, one patch per pair of touching labels A < B: front = A's material,
//   NRRD)               back = B's ("exterior" for label 0, else "label_<L>" or a Slicer
//                       .seg.nrrd's segment name), name "<back>|<front>" (bpm/label_image.h)

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bpm/surface.h"

namespace bpm {

// The material on the outer side of a file that encloses one material, and the one a
// meshed region defaults to when it is outside everything (compared case-insensitively).
inline const char* const kExteriorMaterial = "exterior";

struct PatchInfo {
    int32_t patch = 0;    // the patch id (Surface::patches), unique in a list
    std::string name;     // e.g. "liver|Exterior", "pair_bone_muscle", "A|exterior"; may be empty
    // The materials on the two sides; empty = not known. Front is where the coarse (and
    // original) triangles' normals point (right-hand rule), back the other side. With
    // oriented = false the patch separates the two but which is on which side is unknown.
    std::string front, back;
    bool oriented = true;

    bool has_materials() const { return !front.empty() && !back.empty(); }
    bool operator==(const PatchInfo& o) const {
        return patch == o.patch && name == o.name && front == o.front && back == o.back && oriented == o.oriented;
    }
};

// The entry for `patch`, or nullptr.
const PatchInfo* find_patch_info(const std::vector<PatchInfo>& infos, int32_t patch);
PatchInfo* find_patch_info(std::vector<PatchInfo>& infos, int32_t patch);

// The two materials a physical surface name gives, by the conventions segmentation and
// meshing scripts use: "A|B" (blanks around '|' trimmed; A and B without '|'), or
// "pair_A_B" / "interface_A_B" (A and B without '_'). nullopt for other names, and for
// empty or equal A and B.
std::optional<std::pair<std::string, std::string>> materials_from_patch_name(const std::string& name);

// The first broken rule of a patch info list, empty if none: a patch id listed twice; an
// unordered pair (oriented = false) without both materials; a NUL byte in a name.
std::string patch_info_problem(const std::vector<PatchInfo>& infos);

// The file-per-material convention for one file (see the top), for a file that says
// nothing about its patches (`infos` empty): every patch of `surface` gets front =
// kExteriorMaterial, back = `material` and the name "<material>|exterior". Sorted by
// patch id. Nothing happens when `infos` is not empty or `material` is.
void apply_file_material(std::vector<PatchInfo>& infos, const Surface& surface, const std::string& material);

// The infos after fuse_duplicate_triangles made `fused` (the interfaces): a fused patch
// separates what its joined patches enclose. Its triangles are those of `kept_from` (see
// FusedPatch), so its back is kept_from's back and its front the back of the other
// joined patches (their triangles were the same ones reversed), when all of them say the
// same; it is then named "<back>|<front>", else by the joined patches' names joined
// with '+'. Sorted by patch id afterwards.
void add_fused_patch_info(std::vector<PatchInfo>& infos, const std::vector<FusedPatch>& fused);

}  // namespace bpm
