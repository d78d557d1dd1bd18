#pragma once
// The material of every region of a tetrahedral mesh, from what the input says about the
// patches that bound it (bpm/patch_info.h), or from the user (spec/tetmesh.md §3.7).
//
// Each face on S has a front side (where its coarse triangle's normal points) and a back
// side; each side lies in a region, or in the unbounded outside (not meshed). A patch
// whose PatchInfo gives materials constrains the regions on its sides:
//   oriented      the region on the front side is `front`, the one behind is `back`;
//   unordered     both regions are one of the two, and they differ (so once one side is
//                 known, so is the other; this is propagated until nothing changes).
// "exterior" (any case) on an oriented side of a meshed region is weak: it means only
// "outside this file" (every file of the file-per-material convention has it on its outer
// side, and a file nested in another has the enclosing file's material there), so it names
// the region only when no other constraint does.
// A region's material is the one name every constraint on it allows. If the outside is
// still undecided between names of which one is "exterior" (any case), it is exterior.
// When the oriented reading contradicts itself somewhere (reversed normals in the input),
// the patches are read again as unordered pairs and that reading is kept if it has fewer
// conflicts (reported). A region no constraint decides is a material of its own, named
// "region_<r>"; the user's names (MaterialOptions) override everything.
// Materials are numbered 1, 2, ... in the order of the first region that has them, so
// that a mesh without any patch information gets material r = "region_<r>" for region r.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "bpm/patch_info.h"
#include "bpm/tetmesh.h"

namespace bpm {

struct MaterialOptions {
    // Region id -> material name, e.g. {{1, "bone"}, {2, "marrow"}}; wins over the input.
    std::map<int32_t, std::string> region_names;
};

struct MaterialResult {
    int64_t materials = 0;              // #M
    int64_t regions_from_input = 0;     // regions whose material the patch information decided
    int64_t regions_from_user = 0;      // regions named by MaterialOptions
    // One line per region the input left in doubt, e.g. "region 3: its sides say A and B
    // (conflict); named region_3", or "region 2: either A or B (ambiguous); named region_2".
    std::vector<std::string> problems;
    // The oriented reading had conflicts and the unordered one was kept.
    bool orientation_ignored = false;
};

// Sets mesh.region_material and mesh.material_names as described at the top.
// \pre mesh passes find_tetmesh_inconsistency (faces oriented like their coarse triangles)
// \throw OptionError for a user region id outside 1..num_regions() or an empty name.
MaterialResult assign_materials(TetMesh& mesh, const std::vector<PatchInfo>& patch_info,
                                const MaterialOptions& options = {});

// The patch information after assign_materials, for the files that carry it with the
// mesh: an oriented side that says "exterior" (weak, see the top) but lies in a meshed
// region (the same material on that side of every face of the patch) gets that region's
// material, and a name in the file-per-material form "<back>|<front>" is made again from
// the new pair. So a file nested in another, whose patch the reader named "inner|exterior",
// is "inner|outer" with front "outer" once the mesh shows where it lies (the regions had the
// right materials; /patch_info and the MSH physical names still said exterior). Other
// entries are left as they are. Returns the number of entries changed.
int64_t name_patches_after_regions(const TetMesh& mesh, std::vector<PatchInfo>& patch_info);

// The material id (1..#M) of every tetrahedron; empty when the mesh has no materials.
std::vector<int32_t> tet_materials(const TetMesh& mesh);

// The first broken rule of the material datasets (spec/tetmesh.md §5), starting with the
// dataset name; empty if fine: both empty, or region_material has one entry per region
// id 1..num_regions() with ids in 1..#M, and the names are distinct, non-empty, without
// NUL bytes.
std::string find_material_inconsistency(const TetMesh& mesh);

}  // namespace bpm
