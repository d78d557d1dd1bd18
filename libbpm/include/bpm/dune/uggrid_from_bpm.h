#pragma once
// A Dune::UGGrid<3> from the tet mesh of a .bpm file, with phi as its boundary geometry,
// and the parameter points of its boundary vertices after refinement.
//
// Compiling: Debian's dune-uggrid 2.9 is built for MPI, so code including this header
// needs -DModelP -DENABLE_MPI=1 -DHAVE_MPI=1 -DHAVE_DUNE_UGGRID=1 and MPI's include path
// and libraries (CMake: find_package(MPI), find_package(dune-grid); link `dunegrid`, which
// brings duneuggrid and its compile definitions; examples/dune/CMakeLists.txt does this),
// and the program must create Dune::MPIHelper::instance(argc, argv) before the grid.
//
// What becomes of the bpm mesh:
// - level-0 vertex with insertion index i = tetmesh vertex i (UG itself stores boundary
//   vertices first; GridFactory::insertionIndex translates), element insertion index t =
//   tetrahedron t;
// - one boundary segment per face of the tet mesh on the domain boundary (a face of
//   exactly one tetrahedron; each is a face in /tetmesh/faces), whose geometry is phi on
//   that face's part of its coarse triangle (bpm/dune/boundary_segment.h);
// - faces of /tetmesh/faces between two tetrahedra (interfaces between regions, or sheets
//   inside one) are *not* boundary segments: UG has no interior boundaries, so UG refines
//   them flat (new vertices at edge midpoints). level0_interface_faces records their
//   coarse triangles; BoundaryParameterPoints (with follow_interfaces) gives the vertices
//   UG creates on them parameter points too, and repair_uggrid then moves them towards phi
//   like boundary vertices (as far as no element inverts). The per-region volumes that
//   bpm-torsion reports show the difference.
//
// After each refinement: BoundaryParameterPoints::update, then repair_uggrid
// (bpm/dune/uggrid_repair.h), so that no element is inverted. make_uggrid installs
// bpm/dune/uggrid_refinement_rules.h's hook, without which UG's next refinement rebuilds
// elements whose corners the repair moved.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <dune/geometry/referenceelements.hh>
#include <dune/grid/common/gridfactory.hh>
#include <dune/grid/uggrid.hh>

#include "bpm/bpm_file.h"
#include "bpm/dune/boundary_segment.h"
#include "bpm/dune/uggrid_refinement_rules.h"
#include "bpm/errors.h"
#include "bpm/geometry.h"
#include "bpm/phi_evaluation.h"
#include "bpm/surface_point.h"

namespace bpm::dune {

using UGGrid3 = Dune::UGGrid<3>;

struct UGGridFromBpm {
    std::unique_ptr<UGGrid3> grid;
    // [boundary segment index] = coarse triangle of that segment (the grid's
    // Intersection::boundarySegmentIndex()).
    std::vector<int32_t> segment_coarse_triangle;
    // [level-0 element index in grid->levelIndexSet(0)] = region id of that tetrahedron.
    std::vector<int32_t> level0_element_region;
    // Parameter points of the level-0 vertices on S (boundary and interfaces), keyed by
    // global id.
    std::map<UGGrid3::GlobalIdSet::IdType, SurfacePoint> level0_parameter_points;
    // Positions of the level-0 vertices as built (the tet mesh's), keyed by global id: a
    // solver's repair may move interior ones later (smoothing), and repair_uggrid puts them
    // back where refinement made moved fathers inverted children.
    std::map<UGGrid3::GlobalIdSet::IdType, Vec3> level0_positions;
    // [level-0 element index][DUNE face number] = coarse triangle of that face if it is a
    // face of /tetmesh/faces shared by two tetrahedra (an interface), else -1.
    std::vector<std::array<int32_t, 4>> level0_interface_faces;
};

enum class BoundaryGeometry {
    Phi,   // segments evaluate phi: new boundary vertices land on the original surface
    Flat,  // plane segments: new boundary vertices at edge midpoints (comparison runs)
};

namespace detail {
inline std::array<int32_t, 3> sorted_face(int32_t a, int32_t b, int32_t c) {
    std::array<int32_t, 3> f{a, b, c};
    std::sort(f.begin(), f.end());
    return f;
}
}  // namespace detail

// Builds the grid. `phi` (evaluating file.param) is required for BoundaryGeometry::Phi and
// shared by all segments; file.param and phi must outlive the grid.
// \throw InputError if the file has no tet mesh, or a boundary face of the tet mesh is not
//        in /tetmesh/faces, or a face corner has no parameter point in the face's coarse
//        triangle; std::invalid_argument if phi is null with BoundaryGeometry::Phi;
//        Dune::GridError from UG.
inline UGGridFromBpm make_uggrid(const BpmFile& file, std::shared_ptr<const PhiEvaluator> phi,
                                 BoundaryGeometry geometry = BoundaryGeometry::Phi) {
    if (!file.tetmesh) throw InputError("/tetmesh", "the .bpm file has no tet mesh (/tetmesh): run bpm-mesh first");
    if (geometry == BoundaryGeometry::Phi && !phi) throw std::invalid_argument("make_uggrid: phi is null");
    const TetMesh& mesh = *file.tetmesh;
    const Surface& coarse = file.param.coarse;

    // Faces of exactly one tetrahedron are the domain boundary.
    std::map<std::array<int32_t, 3>, int> face_count;
    for (const Tet& t : mesh.tetrahedra) {
        ++face_count[detail::sorted_face(t[1], t[2], t[3])];
        ++face_count[detail::sorted_face(t[0], t[2], t[3])];
        ++face_count[detail::sorted_face(t[0], t[1], t[3])];
        ++face_count[detail::sorted_face(t[0], t[1], t[2])];
    }

    Dune::GridFactory<UGGrid3> factory;
    for (const Vec3& x : mesh.vertices) factory.insertVertex({x[0], x[1], x[2]});
    for (const Tet& t : mesh.tetrahedra)
        factory.insertElement(Dune::GeometryTypes::tetrahedron,
                              {static_cast<unsigned>(t[0]), static_cast<unsigned>(t[1]),
                               static_cast<unsigned>(t[2]), static_cast<unsigned>(t[3])});

    UGGridFromBpm out;
    size_t boundary_faces_listed = 0;
    for (size_t f = 0; f < mesh.faces.size(); ++f) {
        const Tri& face = mesh.faces[f];
        if (face_count[detail::sorted_face(face[0], face[1], face[2])] != 1) continue;  // interface
        ++boundary_faces_listed;
        const int32_t t = mesh.face_coarse_triangle[f];
        std::array<Vec3, 3> corner_barycentric;
        std::array<Vec3, 3> corner_position;
        for (int i = 0; i < 3; ++i) {
            const int32_t v = face[i];
            const SurfacePoint& p = mesh.vertex_parameter_points[v];
            const auto b = p.valid() ? barycentric_in_triangle(coarse, p, t) : std::nullopt;
            if (!b)
                throw InputError("/tetmesh", "/tetmesh: vertex " + std::to_string(v) + " of boundary face " + std::to_string(f) +
                                 " has no parameter point in the face's coarse triangle " + std::to_string(t));
            corner_barycentric[i] = *b;
            corner_position[i] = mesh.vertices[v];
        }
        std::shared_ptr<Dune::BoundarySegment<3>> segment;
        if (geometry == BoundaryGeometry::Phi)
            segment = std::make_shared<PhiBoundarySegment>(phi, t, corner_barycentric);
        else
            segment = std::make_shared<FlatBoundarySegment>(corner_position);
        // Insertion order = corner order of the face: the segment's local coordinates
        // refer to these corners (boundary_segment.h).
        factory.insertBoundarySegment({static_cast<unsigned>(face[0]), static_cast<unsigned>(face[1]),
                                       static_cast<unsigned>(face[2])},
                                      segment);
        out.segment_coarse_triangle.push_back(t);
    }
    size_t boundary_faces = 0;
    for (const auto& [key, count] : face_count) boundary_faces += (count == 1);
    if (boundary_faces != boundary_faces_listed)
        throw InputError("/tetmesh", "/tetmesh: " + std::to_string(boundary_faces - boundary_faces_listed) +
                         " boundary faces of the tet mesh are not in /tetmesh/faces");

    out.grid = factory.createGrid();
    // Vertices will move (repair, smoothing): UG must not re-choose the rules of elements
    // it has refined (bpm/dune/uggrid_refinement_rules.h).
    keep_uggrid_refinement_rules();
    // UG numbers the segments in insertion order; every boundary face has one, so
    // boundarySegmentIndex() is an index into segment_coarse_triangle.
    const auto level0 = out.grid->levelGridView(0);
    const auto& ids = out.grid->globalIdSet();
    out.level0_element_region.assign(static_cast<size_t>(level0.size(0)), 0);
    std::map<std::array<int32_t, 3>, int32_t> interface_triangle;
    for (size_t f = 0; f < mesh.faces.size(); ++f) {
        const Tri& face = mesh.faces[f];
        const auto key = detail::sorted_face(face[0], face[1], face[2]);
        if (face_count[key] == 2) interface_triangle.emplace(key, mesh.face_coarse_triangle[f]);
    }
    const auto& tet = Dune::referenceElement<double, 3>(Dune::GeometryTypes::tetrahedron);
    out.level0_interface_faces.assign(static_cast<size_t>(level0.size(0)), {-1, -1, -1, -1});
    for (const auto& element : elements(level0)) {
        const auto t = factory.insertionIndex(element);
        const auto e = level0.indexSet().index(element);
        out.level0_element_region[e] = mesh.regions.at(t);
        if (interface_triangle.empty()) continue;
        for (int face = 0; face < 4; ++face) {
            std::array<int32_t, 3> v;
            for (int c = 0; c < 3; ++c)
                v[c] = static_cast<int32_t>(
                    factory.insertionIndex(element.template subEntity<3>(tet.subEntity(face, 1, c, 3))));
            const auto it = interface_triangle.find(detail::sorted_face(v[0], v[1], v[2]));
            if (it != interface_triangle.end()) out.level0_interface_faces[e][face] = it->second;
        }
    }
    for (const auto& vertex : vertices(level0)) {
        const auto v = factory.insertionIndex(vertex);
        const SurfacePoint p = mesh.vertex_parameter_points.at(v);
        if (p.valid()) out.level0_parameter_points.emplace(ids.id(vertex), p);
        const auto c = vertex.geometry().corner(0);
        out.level0_positions.emplace(ids.id(vertex), Vec3{c[0], c[1], c[2]});
    }
    return out;
}

// Parameter points of the boundary vertices of a refined UGGrid, keyed by global id (UG
// keeps a vertex's id on every level it appears on), and with follow_interfaces those of
// the vertices UG creates on interfaces (faces of /tetmesh/faces between two tetrahedra).
//
// update() visits levels 1..maxLevel and, for each boundary face there whose corners are
// not known yet, takes the corner's position in its father element (geometryInFather):
// UG's tetrahedron rules only put new vertices at midpoints of the father's edges, and UG
// computes a new boundary vertex as the segment at the midpoint of the edge's ends in the
// segment's parameter domain. The edge lies on one segment, so both ends are expressed in
// that segment's coarse triangle and averaged there: exactly the point phi was evaluated at.
// Interfaces are no segments: a child face is on an interface when its three corners lie
// on an interface face of its father (by geometryInFather), which gives its coarse
// triangle; its new vertices get the midpoints of their edge ends' parameter points in that
// triangle, as on the boundary, although UG left them at the flat midpoint.
class BoundaryParameterPoints {
public:
    using IdType = UGGrid3::GlobalIdSet::IdType;

    // A boundary vertex that update() found at the midpoint of its father's edge (ends).
    struct NewVertex {
        IdType vertex;
        std::array<IdType, 2> ends;
    };

    // With follow_interfaces = false, interface vertices created by refinement get no
    // parameter point (they stay where UG puts them: flat).
    explicit BoundaryParameterPoints(const UGGridFromBpm& built, const Surface& coarse, bool follow_interfaces = true)
        : built_(built), coarse_(coarse), follow_interfaces_(follow_interfaces) {
        for (const auto& [id, p] : built.level0_parameter_points) points_.emplace(id, p);
    }

    // Returns the boundary vertices it added, coarser levels first, with the ends of the
    // edges they split (what bpm::repair_boundary needs to put them back at midpoints).
    // \throw AlgorithmError if a new boundary vertex is not an edge midpoint of its
    //        father or its father's corners have no known parameter point.
    std::vector<NewVertex> update(const UGGrid3& grid) {
        std::vector<NewVertex> added;
        const auto& ids = grid.globalIdSet();
        const auto& tet = Dune::referenceElement<double, 3>(Dune::GeometryTypes::tetrahedron);
        for (int level = 1; level <= grid.maxLevel(); ++level) {
            for (const auto& element : elements(grid.levelGridView(level))) {
                if (!element.hasBoundaryIntersections()) continue;
                for (const auto& is : intersections(grid.levelGridView(level), element)) {
                    if (!is.boundary()) continue;
                    const int32_t t = built_.segment_coarse_triangle.at(is.boundarySegmentIndex());
                    const int face = is.indexInInside();
                    for (int c = 0; c < 3; ++c) {
                        const int corner = tet.subEntity(face, 1, c, 3);
                        const IdType id = ids.subId(element, corner, 3);
                        if (points_.count(id)) continue;
                        NewVertex v{id, {id, id}};
                        points_.emplace(id, from_father(element, corner, t, ids, v.ends));
                        if (v.ends[0] != id) added.push_back(v);
                    }
                }
            }
        }
        if (follow_interfaces_) update_interfaces(grid, added);
        for (const NewVertex& v : added) ends_.emplace(v.vertex, v.ends);
        return added;
    }

    // The ends of the edge a vertex returned by an earlier update() split, or nullptr
    // (level-0 vertices, interior vertices, unknown ids).
    const std::array<IdType, 2>* ends_of(IdType id) const {
        const auto it = ends_.find(id);
        return it == ends_.end() ? nullptr : &it->second;
    }

    // Interface faces found by update() so far (on every level).
    size_t interface_faces() const { return interface_faces_count_; }

    // The position a level-0 vertex had when the grid was built, or nullptr for vertices
    // refinement created (and unknown ids).
    const Vec3* level0_position(IdType id) const {
        const auto it = built_.level0_positions.find(id);
        return it == built_.level0_positions.end() ? nullptr : &it->second;
    }

    // The parameter point of a boundary vertex, or nullptr for interior or unknown ones.
    const SurfacePoint* find(IdType id) const {
        const auto it = points_.find(id);
        return it == points_.end() ? nullptr : &it->second;
    }
    size_t size() const { return points_.size(); }

    // Replaces the parameter point of a known boundary vertex (repair_uggrid, when the
    // repair slid the vertex along S0; bpm/boundary_repair.h, step 6). Vertices refined
    // later from its edges take their points from the new one. \pre p is in the same coarse
    // triangles as the old point (the repair keeps its zero coordinates).
    // \throw AlgorithmError for an id without a parameter point.
    void set(IdType id, const SurfacePoint& p) {
        const auto it = points_.find(id);
        if (it == points_.end()) throw AlgorithmError("bpm::dune: set a parameter point of a vertex that has none");
        it->second = p;
    }

private:
    // Records the interface faces of every element (by element id; DUNE face numbers) and
    // gives the new vertices on them parameter points.
    void update_interfaces(const UGGrid3& grid, std::vector<NewVertex>& added) {
        const auto& ids = grid.globalIdSet();
        const auto& tet = Dune::referenceElement<double, 3>(Dune::GeometryTypes::tetrahedron);
        if (interfaces_.empty()) {
            const auto level0 = grid.levelGridView(0);
            for (const auto& element : elements(level0)) {
                const auto& faces = built_.level0_interface_faces.at(level0.indexSet().index(element));
                if (faces != std::array<int32_t, 4>{-1, -1, -1, -1}) {
                    interfaces_.emplace(ids.id(element), faces);
                    for (int32_t t : faces) interface_faces_count_ += (t >= 0);
                }
            }
            if (interfaces_.empty()) return;
        }
        for (int level = 1; level <= grid.maxLevel(); ++level) {
            for (const auto& element : elements(grid.levelGridView(level))) {
                const auto id = ids.id(element);
                if (interfaces_.count(id)) continue;  // done by an earlier update
                const auto father_faces = interfaces_.find(ids.id(element.father()));
                if (father_faces == interfaces_.end()) continue;
                const auto in_father = element.geometryInFather();
                std::array<int32_t, 4> faces{-1, -1, -1, -1};
                for (int face = 0; face < 4; ++face) {
                    for (int f = 0; f < 4; ++f) {
                        const int32_t t = father_faces->second[f];
                        if (t < 0) continue;
                        // A point is on father face f when the barycentric weight of the
                        // father corner opposite f is 0.
                        const int opposite = 6 - tet.subEntity(f, 1, 0, 3) - tet.subEntity(f, 1, 1, 3) - tet.subEntity(f, 1, 2, 3);
                        bool on_face = true;
                        for (int c = 0; c < 3 && on_face; ++c) {
                            const auto local = in_father.corner(tet.subEntity(face, 1, c, 3));
                            const double w = opposite == 0 ? 1.0 - local[0] - local[1] - local[2] : local[opposite - 1];
                            on_face = std::abs(w) < 1e-12;
                        }
                        if (on_face) faces[face] = t;
                    }
                }
                if (faces == std::array<int32_t, 4>{-1, -1, -1, -1}) continue;
                interfaces_.emplace(id, faces);
                for (int face = 0; face < 4; ++face) {
                    if (faces[face] < 0) continue;
                    ++interface_faces_count_;
                    for (int c = 0; c < 3; ++c) {
                        const int corner = tet.subEntity(face, 1, c, 3);
                        const IdType vid = ids.subId(element, corner, 3);
                        if (points_.count(vid)) continue;
                        NewVertex v{vid, {vid, vid}};
                        points_.emplace(vid, from_father(element, corner, faces[face], ids, v.ends));
                        if (v.ends[0] != vid) added.push_back(v);
                    }
                }
            }
        }
    }

    template <class Element, class Ids>
    SurfacePoint from_father(const Element& element, int corner, int32_t t, const Ids& ids,
                             std::array<IdType, 2>& end_ids) const {
        const auto father = element.father();
        const auto local = element.geometryInFather().corner(corner);
        // Father corners at unit reference coordinates: (0,0,0), e1, e2, e3.
        const std::array<double, 4> w{1.0 - local[0] - local[1] - local[2], local[0], local[1], local[2]};
        for (int j = 0; j < 4; ++j) {
            if (std::abs(w[j] - 1.0) < 1e-12) {
                // A corner of the father: its id would have been found unless the father's
                // copy of the vertex is not a boundary vertex, which cannot be.
                const SurfacePoint* p = find(ids.subId(father, j, 3));
                if (!p) throw AlgorithmError("bpm::dune: a boundary vertex of the father has no parameter point");
                return *p;
            }
        }
        std::array<int, 2> ends{-1, -1};
        int n = 0;
        for (int j = 0; j < 4; ++j) {
            if (std::abs(w[j]) < 1e-12) continue;
            if (n == 2 || std::abs(w[j] - 0.5) > 1e-12) { n = 3; break; }
            ends[n++] = j;
        }
        if (n != 2)
            throw AlgorithmError("bpm::dune: UG put a boundary vertex at a point that is not an edge midpoint of its "
                                 "father element (local coordinates " + std::to_string(local[0]) + ", " +
                                 std::to_string(local[1]) + ", " + std::to_string(local[2]) + ")");
        Vec3 b{0, 0, 0};
        for (int k = 0; k < 2; ++k) {
            end_ids[k] = ids.subId(father, ends[k], 3);
            const SurfacePoint* p = find(end_ids[k]);
            const auto in_t = p ? barycentric_in_triangle(coarse_, *p, t) : std::nullopt;
            if (!in_t)
                throw AlgorithmError("bpm::dune: the ends of a refined boundary edge have no parameter points in "
                                     "coarse triangle " + std::to_string(t));
            b = b + 0.5 * *in_t;
        }
        return SurfacePoint{t, b};
    }

    const UGGridFromBpm& built_;
    const Surface& coarse_;
    bool follow_interfaces_ = true;
    std::map<IdType, SurfacePoint> points_;
    std::map<IdType, std::array<IdType, 2>> ends_;  // every vertex update() returned -> its edge ends
    std::map<IdType, std::array<int32_t, 4>> interfaces_;  // element id -> coarse triangle per face, or -1
    size_t interface_faces_count_ = 0;
};

}  // namespace bpm::dune
