#pragma once
// deal.II adapter, part 2: a dealii::Triangulation<3> made from the tet mesh of a .bpm file,
// in memory (no file round trip), with phi attached to the surface S.
//
//   bpm::BpmFile file = bpm::read_bpm("femur.bpm");          // must have a /tetmesh group
//   bpm::dealii::BpmTriangulation mesh(file, bpm::dealii::BoundaryMode::Phi);
//   dealii::Triangulation<3>& tria = mesh.triangulation();
//   bpm::dealii::refine_global(mesh);                          // bpm/dealii/global_refinement.h
//
// Level-0 vertex i is tet-mesh vertex i and level-0 cell t is tetrahedron t (checked), with
// its four vertices in the tet mesh's order (positively oriented; deal.II's reference
// tetrahedron (0,0,0), e1, e2, e3 is positive too) and material_id = region (>= 1).
//
// Which faces follow phi: every face of the tet mesh that lies on S, i.e. TetMesh::faces —
// the boundary AND the interfaces between regions. An interface is a piece of S like the
// outer boundary (phi maps it onto the original interface surface, and bpm's own
// refinement, bpm/tet_refine.h, moves its new vertices the same way), so the cells on both
// sides of it refine onto the same curved surface and stay conforming.
//
// Manifold ids: deal.II takes the manifold of a new edge midpoint from the line, not from
// the face (with ids on the faces only, the edges were split flat in our trial with 9.4,
// and set_all_manifold_ids_on_boundary crashed on a tet mesh). But MappingFE, the mapping
// of simplex cells, asserts (Debug) that all entities of a cell have the cell's manifold
// id. So the ids are set only while deal.II refines: the adapter keeps the faces on S
// itself (as vertex triples), gives them and all their lines kPhiManifoldId just before
// refinement, takes the new faces on S from the children (which inherit the id), and then
// resets every manifold id to flat. Between refinements the triangulation is all flat
// (for a P1 mapping the geometry is in the vertices alone), and solvers can use it as is.
//
// BoundaryMode::Flat attaches the same bookkeeping but puts new points at the weighted
// average of the old ones (plain red refinement of the boundary): the comparison series.

#include <deal.II/grid/tria.h>
#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_description.h>
#include <deal.II/grid/tria_iterator.h>

#include <algorithm>
#include <array>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <unordered_set>
#include <vector>

#include "bpm/bpm_file.h"
#include "bpm/dealii/phi_manifold.h"
#include "bpm/errors.h"
#include "bpm/phi_inverse.h"
#include "bpm/predicates.h"
#include "bpm/tetmesh.h"

namespace bpm::dealii {

enum class BoundaryMode {
    Phi,   // new points on S at phi of the combined parameter points
    Flat,  // new points at the weighted average of the surrounding points (no phi)
};

// A deal.II triangulation of a .bpm file's tet mesh, with the bookkeeping of the parameter
// points of its vertices on S. Keeps a reference to `file`, which must outlive it and not
// change. Refine it through bpm/dealii/global_refinement.h only (deal.II 9.4 refines
// tetrahedral meshes correctly only globally).
class BpmTriangulation {
public:
    // \throw InputError if the file has no tet mesh; AlgorithmError if deal.II renumbered
    //        the vertices or cells, or the faces on S are not faces of the cells.
    BpmTriangulation(const BpmFile& file, BoundaryMode mode) : file_(file), mode_(mode) {
        if (!file.tetmesh) throw InputError("", "the .bpm file has no tetrahedral mesh (/tetmesh): run bpm-mesh on it first");
        const TetMesh& m = *file.tetmesh;
        std::vector<::dealii::Point<3>> vertices(m.vertices.size());
        for (size_t i = 0; i < vertices.size(); ++i) vertices[i] = to_dealii_point(m.vertices[i]);
        std::vector<::dealii::CellData<3>> cells(m.tetrahedra.size(), ::dealii::CellData<3>(4));
        for (size_t t = 0; t < cells.size(); ++t) {
            for (unsigned k = 0; k < 4; ++k) cells[t].vertices[k] = static_cast<unsigned>(m.tetrahedra[t][k]);
            cells[t].material_id = static_cast<::dealii::types::material_id>(m.regions[t]);
        }
        tria_.create_triangulation(vertices, cells, ::dealii::SubCellData());

        // The tet mesh's numbering is what the parameter points and regions refer to.
        const auto& v = tria_.get_vertices();
        if (v.size() != vertices.size()) throw AlgorithmError("deal.II changed the number of vertices of the tet mesh");
        for (size_t i = 0; i < v.size(); ++i)
            if (v[i] != vertices[i]) throw AlgorithmError("deal.II renumbered the vertices of the tet mesh");
        for (const auto& cell : tria_.active_cell_iterators())
            for (unsigned k = 0; k < 4; ++k)
                if (cell->vertex_index(k) != cells[static_cast<size_t>(cell->index())].vertices[k])
                    throw AlgorithmError("deal.II renumbered or reordered the cells of the tet mesh");

        for (const Tri& f : m.faces) surface_faces_.insert(face_key(f[0], f[1], f[2]));
        const int64_t marked = mark_surface();
        if (marked != static_cast<int64_t>(m.faces.size()))
            throw AlgorithmError("only " + std::to_string(marked) + " of the " + std::to_string(m.faces.size()) +
                                 " tet-mesh faces on S are faces of its tetrahedra");
        tria_.set_all_manifold_ids(::dealii::numbers::flat_manifold_id);

        boundary_ = std::make_shared<PhiBoundary>(file.param, mode == BoundaryMode::Phi);
        for (size_t i = 0; i < m.vertices.size(); ++i)
            if (m.vertex_parameter_points[i].valid()) boundary_->remember(m.vertices[i], m.vertex_parameter_points[i]);
        // Positions the boundary does not know (a vertex moved by code other than the
        // adapter's) are taken to the parameter point of their closest point on S0.
        auto inverse = std::make_shared<const PhiInverse>(file.param);
        boundary_->inverse = [inverse](const Vec3& x) { return inverse->from_position(x).point; };
        tria_.set_manifold(kPhiManifoldId, PhiManifold(boundary_));
        level0_coarse_vertex_ = m.vertex_coarse_vertex;
    }
    BpmTriangulation(const BpmTriangulation&) = delete;
    BpmTriangulation& operator=(const BpmTriangulation&) = delete;

    ::dealii::Triangulation<3>& triangulation() { return tria_; }
    const ::dealii::Triangulation<3>& triangulation() const { return tria_; }
    const std::shared_ptr<PhiBoundary>& boundary() const { return boundary_; }
    BoundaryMode mode() const { return mode_; }
    const BpmFile& file() const { return file_; }
    int levels_refined() const { return static_cast<int>(tria_.n_levels()) - 1; }

    // The faces on S of the active mesh, as sorted vertex triples (deal.II vertex indices).
    using FaceKey = std::array<unsigned, 3>;
    struct FaceKeyHash {
        size_t operator()(const FaceKey& k) const {
            return (static_cast<size_t>(k[0]) * 0x9E3779B97F4A7C15ull) ^ (static_cast<size_t>(k[1]) * 0xC2B2AE3D27D4EB4Full) ^
                   static_cast<size_t>(k[2]);
        }
    };
    static FaceKey face_key(int64_t a, int64_t b, int64_t c) {
        FaceKey k{static_cast<unsigned>(a), static_cast<unsigned>(b), static_cast<unsigned>(c)};
        std::sort(k.begin(), k.end());
        return k;
    }
    template <class FaceIterator>
    static FaceKey face_key(const FaceIterator& face) {
        return face_key(face->vertex_index(0), face->vertex_index(1), face->vertex_index(2));
    }
    const std::unordered_set<FaceKey, FaceKeyHash>& surface_faces() const { return surface_faces_; }

    // Gives every face on S and each of its lines kPhiManifoldId (see the top of this file);
    // returns how many faces on S it found among the active cells' faces.
    int64_t mark_surface() {
        std::unordered_set<unsigned> found;
        for (const auto& cell : tria_.active_cell_iterators())
            for (const unsigned f : cell->face_indices()) {
                const auto face = cell->face(f);
                if (!surface_faces_.count(face_key(face))) continue;
                found.insert(face->index());
                face->set_manifold_id(kPhiManifoldId);
                for (unsigned l = 0; l < face->n_lines(); ++l) face->line(l)->set_manifold_id(kPhiManifoldId);
            }
        return static_cast<int64_t>(found.size());
    }

    // After deal.II's refinement of a marked mesh: the faces on S are the active faces that
    // inherited kPhiManifoldId; then every manifold id is reset to flat. Returns their count.
    int64_t collect_surface_and_unmark() {
        surface_faces_.clear();
        for (const auto& cell : tria_.active_cell_iterators())
            for (const unsigned f : cell->face_indices()) {
                const auto face = cell->face(f);
                if (face->manifold_id() == kPhiManifoldId) surface_faces_.insert(face_key(face));
            }
        tria_.set_all_manifold_ids(::dealii::numbers::flat_manifold_id);
        return static_cast<int64_t>(surface_faces_.size());
    }

    // The parameter point of every vertex (deal.II index): valid for the vertices on S,
    // invalid for interior ones. From the positions PhiBoundary knows, else its inverse.
    std::vector<SurfacePoint> vertex_parameter_points() const {
        const auto& v = tria_.get_vertices();
        std::vector<SurfacePoint> out(v.size());
        std::unordered_set<unsigned> on_s;
        for (const FaceKey& k : surface_faces_) on_s.insert(k.begin(), k.end());
        for (unsigned i : on_s) out[i] = boundary_->parameter_point(to_vec3(v[i]));
        return out;
    }

    // Where plain refinement of the triangulation as it now is puts each vertex (#V, deal.II
    // indices): for a vertex refinement created at the midpoint of a line (deal.II's
    // refinement of tetrahedra creates vertices nowhere else), the midpoint of that line's
    // ends at their current positions; for the others (level 0) their position. What
    // bpm::repair_boundary takes as plain positions for its retreat (step 5,
    // bpm/boundary_repair.h): for a vertex of this refinement it is where deal.II put it
    // (the repair lets deal.II place new points at their midpoints), for one of an earlier
    // refinement the midpoint of its line's ends as they have moved since.
    std::vector<Vec3> plain_positions() const {
        const auto& v = tria_.get_vertices();
        std::vector<Vec3> out(v.size());
        for (size_t i = 0; i < v.size(); ++i) out[i] = to_vec3(v[i]);
        // Every line of a cell of any level (deal.II keeps its raw line iterators private in
        // 3D); a refined one has children (v0, midpoint), (midpoint, v1).
        for (const auto& cell : tria_.cell_iterators())
            for (unsigned l = 0; l < cell->n_lines(); ++l) {
                const auto line = cell->line(l);
                if (!line->has_children()) continue;
                const unsigned mid = line->child(0)->vertex_index(1);
                out[mid] = 0.5 * (to_vec3(v[line->vertex_index(0)]) + to_vec3(v[line->vertex_index(1)]));
            }
        return out;
    }

    // Moves the vertices to `positions` (#V, deal.II indices; cell->vertex(k) = x, which
    // moves the vertex in every cell and level that has it) and records the parameter
    // points `points` (#V, invalid for interior vertices) at the new positions, forgetting
    // the old ones. 	hrow std::invalid_argument if the sizes differ from n_vertices().
    void move_vertices(const std::vector<Vec3>& positions, const std::vector<SurfacePoint>& points) {
        const size_t nv = tria_.n_vertices();
        if (positions.size() != nv || points.size() != nv)
            throw std::invalid_argument("move_vertices: " + std::to_string(positions.size()) + " positions and " +
                                        std::to_string(points.size()) + " parameter points for " + std::to_string(nv) +
                                        " vertices");
        std::vector<bool> done(nv, false);
        for (const auto& cell : tria_.active_cell_iterators())
            for (unsigned k = 0; k < cell->n_vertices(); ++k) {
                const unsigned i = cell->vertex_index(k);
                if (done[i]) continue;
                done[i] = true;
                cell->vertex(k) = to_dealii_point(positions[i]);
            }
        boundary_->forget_all();
        for (size_t i = 0; i < nv; ++i)
            if (points[i].valid()) boundary_->remember(positions[i], points[i]);
    }

    // The active cells as a bpm::TetMesh: all vertices (by deal.II index), cells in active
    // order with their deal.II vertex order, regions = material ids, the faces on S oriented
    // like their coarse triangles, the parameter point of every vertex on S, level and
    // level-0 ancestors. What bpm's measurements (tetmesh_stats) and the boundary repair
    // take. \throw AlgorithmError if a vertex on S has no parameter point (a new point made
    // without phi's bookkeeping, see PhiBoundary::fallbacks) or a face on S lies in no
    // single coarse triangle.
    TetMesh to_tetmesh() const {
        TetMesh out = cells_as_tetmesh();
        const Surface& coarse = file_.param.coarse;
        const size_t nv = out.vertices.size();
        out.vertex_coarse_vertex.assign(nv, -1);
        for (size_t i = 0; i < level0_coarse_vertex_.size() && i < nv; ++i) out.vertex_coarse_vertex[i] = level0_coarse_vertex_[i];
        out.vertex_parameter_points.assign(nv, SurfacePoint{});
        std::set<unsigned> seen;
        for (const auto& cell : tria_.active_cell_iterators())
            for (const unsigned f : cell->face_indices()) {
                const auto face = cell->face(f);
                if (!surface_faces_.count(face_key(face)) || !seen.insert(face->index()).second) continue;
                Tri tri;
                std::vector<SurfacePoint> p(3);
                for (unsigned k = 0; k < 3; ++k) {
                    tri[k] = static_cast<int32_t>(face->vertex_index(k));
                    p[k] = boundary_->parameter_point(out.vertices[static_cast<size_t>(tri[k])]);
                    if (!p[k].valid())
                        throw AlgorithmError("vertex " + std::to_string(tri[k]) + " on S has no parameter point");
                    out.vertex_parameter_points[static_cast<size_t>(tri[k])] = p[k];
                }
                int32_t t = -1;
                Vec3 b[3];
                for (int32_t cand : boundary_->candidate_triangles(p[0])) {
                    if (boundary_->express_in(p[0], cand, b[0]) && boundary_->express_in(p[1], cand, b[1]) &&
                        boundary_->express_in(p[2], cand, b[2])) {
                        t = cand;
                        break;
                    }
                }
                if (t < 0) throw AlgorithmError("a face on S with vertices " + std::to_string(tri[0]) + ", " +
                                                std::to_string(tri[1]) + ", " + std::to_string(tri[2]) +
                                                " lies in no single coarse triangle");
                // Orientation in the parameter triangle (coordinates b1, b2 are a positively
                // oriented affine frame of it): the stored faces turn like their coarse triangle.
                const int o = orient2d(Vec2{b[0][1], b[0][2]}, Vec2{b[1][1], b[1][2]}, Vec2{b[2][1], b[2][2]});
                if (o < 0) std::swap(tri[1], tri[2]);
                out.faces.push_back(tri);
                out.face_coarse_triangle.push_back(t);
                out.face_patches.push_back(coarse.patches[static_cast<size_t>(t)]);
            }
        out.level = (file_.tetmesh ? file_.tetmesh->level : 0) + levels_refined();
        if (levels_refined() > 0) {
            out.tet_ancestor.reserve(out.tetrahedra.size());
            for (const auto& cell : tria_.active_cell_iterators()) {
                ::dealii::Triangulation<3>::cell_iterator c = cell;  // not an active iterator: it climbs to parents
                while (c->level() > 0) c = c->parent();
                out.tet_ancestor.push_back(c->index());
            }
        }
        return out;
    }

    // Vertices, active cells and regions only (what tetmesh_stats needs: inverted cells by
    // exact orient3d, dihedral angles, region volumes).
    TetMesh cells_as_tetmesh() const {
        TetMesh out;
        const auto& v = tria_.get_vertices();
        out.vertices.resize(v.size());
        for (size_t i = 0; i < v.size(); ++i) out.vertices[i] = to_vec3(v[i]);
        out.tetrahedra.reserve(tria_.n_active_cells());
        out.regions.reserve(tria_.n_active_cells());
        for (const auto& cell : tria_.active_cell_iterators()) {
            out.tetrahedra.push_back(Tet{static_cast<int32_t>(cell->vertex_index(0)), static_cast<int32_t>(cell->vertex_index(1)),
                                         static_cast<int32_t>(cell->vertex_index(2)), static_cast<int32_t>(cell->vertex_index(3))});
            out.regions.push_back(static_cast<int32_t>(cell->material_id()));
        }
        return out;
    }

private:
    const BpmFile& file_;
    BoundaryMode mode_;
    ::dealii::Triangulation<3> tria_;
    std::shared_ptr<PhiBoundary> boundary_;
    std::vector<int32_t> level0_coarse_vertex_;
    std::unordered_set<FaceKey, FaceKeyHash> surface_faces_;
};

}  // namespace bpm::dealii
