// VTK XML UnstructuredGrid (.vtu) output, for surfaces (triangles, with point and cell
// data) and tetrahedral meshes. Both are described as one grid (points, cells of one type,
// named data arrays) and written by one function. Doubles with 17 significant digits,
// independent of the C locale.

#include <charconv>
#include <cstdint>

#include "bpm/errors.h"
#include "bpm/tetmesh_materials.h"
#include "core/file_util.h"
#include "io/mesh_writers.h"

namespace bpm {

namespace detail {

namespace {

// One <DataArray>. Values are integers or reals by type; the ASCII layout (values per
// line, see VtuGrid::indent) is the caller's, so that each kind of file keeps its look.
struct VtuDataArray {
    const char* type;                // "Int32", "Int64", "UInt8", "Float64"
    std::string name;                // no Name attribute when empty (the points)
    int components = 1;
    bool components_attribute = false;  // write NumberOfComponents
    std::vector<int64_t> integers;   // for the integer types
    std::vector<double> reals;       // for Float64
    size_t per_line = 1;             // values per line of text

    size_t size() const { return reals.empty() ? integers.size() : reals.size(); }
};

struct VtuGrid {
    int64_t points = 0, cells = 0;
    std::string indent;  // before the first value of every line
    std::string point_scalars, cell_scalars;  // the Scalars attribute of PointData / CellData, if any
    std::vector<VtuDataArray> point_data, cell_data;
    VtuDataArray coordinates, connectivity, offsets, types;
};

std::string num(int64_t v) { return std::to_string(v); }

void append_double(std::string& out, double x) {
    char buffer[40];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, x, std::chars_format::general, 17);
    out.append(buffer, result.ptr);
}

void write_array(std::string& out, const VtuDataArray& a, const std::string& indent) {
    out += std::string("        <DataArray type=\"") + a.type + "\"";
    if (!a.name.empty()) out += " Name=\"" + a.name + "\"";
    if (a.components_attribute) out += " NumberOfComponents=\"" + num(a.components) + "\"";
    out += " format=\"ascii\">\n";
    const size_t n = a.size();
    for (size_t i = 0; i < n; ++i) {
        out += i % a.per_line == 0 ? indent : std::string(" ");
        if (a.reals.empty())
            out += num(a.integers[i]);
        else
            append_double(out, a.reals[i]);
        if (i % a.per_line == a.per_line - 1 || i + 1 == n) out += '\n';
    }
    out += "        </DataArray>\n";
}

std::string write_vtu_text(const VtuGrid& g) {
    std::string out =
        "<?xml version=\"1.0\"?>\n"
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
        "  <UnstructuredGrid>\n";
    out += "    <Piece NumberOfPoints=\"" + num(g.points) + "\" NumberOfCells=\"" + num(g.cells) + "\">\n";
    out += g.point_scalars.empty() ? "      <PointData>\n" : "      <PointData Scalars=\"" + g.point_scalars + "\">\n";
    for (const VtuDataArray& a : g.point_data) write_array(out, a, g.indent);
    out += "      </PointData>\n";
    out += g.cell_scalars.empty() ? "      <CellData>\n" : "      <CellData Scalars=\"" + g.cell_scalars + "\">\n";
    for (const VtuDataArray& a : g.cell_data) write_array(out, a, g.indent);
    out += "      </CellData>\n      <Points>\n";
    write_array(out, g.coordinates, g.indent);
    out += "      </Points>\n      <Cells>\n";
    write_array(out, g.connectivity, g.indent);
    write_array(out, g.offsets, g.indent);
    write_array(out, g.types, g.indent);
    out += "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
    return out;
}

VtuDataArray coordinates_of(const std::vector<Vec3>& vertices) {
    VtuDataArray a{"Float64", "", 3, true, {}, {}, 3};
    a.reals.reserve(3 * vertices.size());
    for (const Vec3& p : vertices) a.reals.insert(a.reals.end(), p.begin(), p.end());
    return a;
}

// Cells of `corners` vertices each, all of VTK type `type`.
template <class Cell>
void set_cells(VtuGrid& g, const std::vector<Cell>& cells, int type, size_t scalars_per_line) {
    const size_t corners = std::tuple_size<Cell>::value;
    g.connectivity = {"Int64", "connectivity", 1, false, {}, {}, corners};
    g.offsets = {"Int64", "offsets", 1, false, {}, {}, scalars_per_line};
    g.types = {"UInt8", "types", 1, false, {}, {}, scalars_per_line};
    for (size_t c = 0; c < cells.size(); ++c) {
        for (int32_t v : cells[c]) g.connectivity.integers.push_back(v);
        g.offsets.integers.push_back(int64_t(corners * (c + 1)));
    }
    g.types.integers.assign(cells.size(), type);
}

VtuDataArray integer_array(const char* name, const std::vector<int32_t>& values, size_t per_line) {
    return {"Int32", name, 1, false, std::vector<int64_t>(values.begin(), values.end()), {}, per_line};
}

}  // namespace

// Surfaces: values indented, integer scalars 16 to a line (a level-6 refinement has
// millions of them), tuples one to a line.
std::string vtu_of_surface(const Surface& surface, const std::vector<VtuArray>& point_data,
                           const std::vector<VtuArray>& cell_data, const std::string& where) {
    const size_t nv = surface.vertices.size(), nt = surface.triangles.size();
    auto float_array = [&](const VtuArray& a, size_t count) {
        if (a.components < 1 || a.values.size() != count * size_t(a.components))
            throw OutputError(where, "VTU array '" + a.name + "' has " + std::to_string(a.values.size()) +
                                         " values, expected " + std::to_string(count) + " x " +
                                         std::to_string(a.components));
        return VtuDataArray{"Float64", a.name, a.components, true, {}, a.values, size_t(a.components)};
    };
    VtuGrid g;
    g.points = int64_t(nv);
    g.cells = int64_t(nt);
    g.indent = "          ";
    for (const VtuArray& a : point_data) g.point_data.push_back(float_array(a, nv));
    g.cell_data.push_back(integer_array("patch", surface.patches, 16));
    for (const VtuArray& a : cell_data) g.cell_data.push_back(float_array(a, nt));
    g.coordinates = coordinates_of(surface.vertices);
    set_cells(g, surface.triangles, 5, 16);
    return write_vtu_text(g);
}

// Tetrahedral meshes: one value (or tuple) to a line, not indented.
std::string vtu_of_tetmesh(const TetMesh& m) {
    VtuGrid g;
    g.points = m.num_vertices();
    g.cells = m.num_tetrahedra();
    // Material names are not written as a VTK string array (FieldData): meshio 5 refuses
    // the whole file on one ("Illegal data type 'String'"); the names are in the .bpm, MSH
    // and MEDIT outputs, the VTU has the material ids.
    g.point_scalars = "coarse_vertex";
    g.point_data.push_back(integer_array("coarse_vertex", m.vertex_coarse_vertex, 1));
    g.cell_scalars = "region";
    g.cell_data.push_back(integer_array("region", m.regions, 1));
    if (!m.region_material.empty()) g.cell_data.push_back(integer_array("material", tet_materials(m), 1));
    if (!m.tet_ancestor.empty()) g.cell_data.push_back(integer_array("ancestor", m.tet_ancestor, 1));
    g.coordinates = coordinates_of(m.vertices);
    set_cells(g, m.tetrahedra, 10, 1);
    return write_vtu_text(g);
}

}  // namespace detail

void write_surface_vtu(const std::string& path, const Surface& surface, const std::vector<VtuArray>& point_data,
                       const std::vector<VtuArray>& cell_data) {
    const std::string where = detail::display_name(path);
    const size_t nv = surface.vertices.size(), nt = surface.triangles.size();
    if (surface.patches.size() != nt) throw OutputError(where, "patches and triangles differ in number");
    for (const Tri& t : surface.triangles)
        for (int32_t v : t)
            if (v < 0 || size_t(v) >= nv) throw OutputError(where, "triangle index out of range");
    detail::write_file_atomically(path, detail::vtu_of_surface(surface, point_data, cell_data, where));
}

}  // namespace bpm
