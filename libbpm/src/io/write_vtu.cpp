// VTK XML UnstructuredGrid (.vtu) output, for surfaces (triangles, with point and cell
// data) and tetrahedral meshes. Both are described as one grid (points, cells of one type,
// named data arrays) and written by one function. ASCII: doubles with 17 significant
// digits, independent of the C locale. Binary: the arrays' bytes after the XML in one
// <AppendedData encoding="raw"> (little endian, UInt64 headers), raw or in zlib blocks as
// VTK's vtkZLibDataCompressor writes them (VTK, ParaView, meshio and bpm read both).

#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>

#include "bpm/errors.h"
#include "bpm/tetmesh_materials.h"
#include "core/number_text.h"
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

// The appended data of a binary file: every array's block, in the order of the XML.
struct VtuAppended {
    bool zlib = false;
    std::string blob;
};

// An array's values as little-endian bytes of the type it is written as, which is its own
// type except that an Int64 array whose values all fit Int32 is written as Int32: the
// connectivity and offsets are most of a refined surface's bytes, and VTK, ParaView and
// meshio read any integer type there.
std::string binary_bytes(const VtuDataArray& a, const char*& type) {
    std::string bytes;
    type = a.type;
    if (!a.reals.empty() || std::string(a.type) == "Float64") {
        append_le_array(bytes, a.reals.data(), a.reals.size());
        return bytes;
    }
    const std::string t = a.type;
    const bool fits32 = std::all_of(a.integers.begin(), a.integers.end(), [](int64_t v) {
        return v >= std::numeric_limits<int32_t>::min() && v <= std::numeric_limits<int32_t>::max();
    });
    if (t == "Int64" && !fits32) {
        append_le_array(bytes, a.integers.data(), a.integers.size());
        return bytes;
    }
    if (t == "UInt8") {
        const std::vector<uint8_t> narrow(a.integers.begin(), a.integers.end());
        append_le_array(bytes, narrow.data(), narrow.size());
        return bytes;
    }
    type = "Int32";
    const std::vector<int32_t> narrow(a.integers.begin(), a.integers.end());
    append_le_array(bytes, narrow.data(), narrow.size());
    return bytes;
}

// vtkZLibDataCompressor's layout: UInt64 header (number of blocks, block size, size of the
// last block if partial else 0, compressed size of each block), then the blocks.
void append_zlib_blocks(std::string& blob, const std::string& bytes) {
    constexpr size_t block = 32768;
    const size_t blocks = (bytes.size() + block - 1) / block;
    append_le<uint64_t>(blob, blocks);
    append_le<uint64_t>(blob, block);
    append_le<uint64_t>(blob, bytes.size() % block);
    const size_t sizes_at = blob.size();
    blob.resize(sizes_at + blocks * sizeof(uint64_t));
    for (size_t b = 0; b < blocks; ++b) {
        const size_t n = std::min(block, bytes.size() - b * block);
        uLongf packed = compressBound(uLong(n));
        const size_t at = blob.size();
        blob.resize(at + packed);
        if (compress2(reinterpret_cast<Bytef*>(&blob[at]), &packed, reinterpret_cast<const Bytef*>(bytes.data() + b * block),
                      uLong(n), Z_DEFAULT_COMPRESSION) != Z_OK)
            throw OutputError("<vtu>", "zlib failed to compress a block");
        blob.resize(at + packed);
        const uint64_t size = packed;
        std::string word;
        append_le<uint64_t>(word, size);
        std::memcpy(&blob[sizes_at + b * sizeof(uint64_t)], word.data(), sizeof(uint64_t));
    }
}

// One <DataArray>: its values as text, or (with `appended`) an offset into the appended
// data, to which its block is added.
void write_array(std::string& out, const VtuDataArray& a, const std::string& indent, VtuAppended* appended) {
    const char* type = a.type;
    std::string bytes;
    if (appended) bytes = binary_bytes(a, type);
    out += std::string("        <DataArray type=\"") + type + "\"";
    if (!a.name.empty()) out += " Name=\"" + a.name + "\"";
    if (a.components_attribute) out += " NumberOfComponents=\"" + num(a.components) + "\"";
    if (appended) {
        out += " format=\"appended\" offset=\"" + num(int64_t(appended->blob.size())) + "\"/>\n";
        if (appended->zlib) {
            append_zlib_blocks(appended->blob, bytes);
        } else {
            append_le<uint64_t>(appended->blob, bytes.size());
            appended->blob += bytes;
        }
        return;
    }
    out += " format=\"ascii\">\n";
    const size_t n = a.size();
    for (size_t i = 0; i < n; ++i) {
        out += i % a.per_line == 0 ? indent : std::string(" ");
        if (a.reals.empty())
            out += num(a.integers[i]);
        else
            append_round_trip_text(out, a.reals[i]);
        if (i % a.per_line == a.per_line - 1 || i + 1 == n) out += '\n';
    }
    out += "        </DataArray>\n";
}

std::string write_vtu_text(const VtuGrid& g, MeshEncoding encoding) {
    VtuAppended appended{encoding == MeshEncoding::BinaryZlib, {}};
    VtuAppended* binary = encoding == MeshEncoding::Ascii ? nullptr : &appended;
    std::string out =
        "<?xml version=\"1.0\"?>\n"
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\"";
    out += appended.zlib ? " compressor=\"vtkZLibDataCompressor\">\n" : ">\n";
    out += "  <UnstructuredGrid>\n";
    out += "    <Piece NumberOfPoints=\"" + num(g.points) + "\" NumberOfCells=\"" + num(g.cells) + "\">\n";
    out += g.point_scalars.empty() ? "      <PointData>\n" : "      <PointData Scalars=\"" + g.point_scalars + "\">\n";
    for (const VtuDataArray& a : g.point_data) write_array(out, a, g.indent, binary);
    out += "      </PointData>\n";
    out += g.cell_scalars.empty() ? "      <CellData>\n" : "      <CellData Scalars=\"" + g.cell_scalars + "\">\n";
    for (const VtuDataArray& a : g.cell_data) write_array(out, a, g.indent, binary);
    out += "      </CellData>\n      <Points>\n";
    write_array(out, g.coordinates, g.indent, binary);
    out += "      </Points>\n      <Cells>\n";
    write_array(out, g.connectivity, g.indent, binary);
    write_array(out, g.offsets, g.indent, binary);
    write_array(out, g.types, g.indent, binary);
    out += "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n";
    if (binary) {
        out += "  <AppendedData encoding=\"raw\">\n   _";
        out += appended.blob;
        out += "\n  </AppendedData>\n";
    }
    return out + "</VTKFile>\n";
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
                           const std::vector<VtuArray>& cell_data, const std::string& where,
                           MeshEncoding encoding) {
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
    return write_vtu_text(g, encoding);
}

// Tetrahedral meshes: one value (or tuple) to a line, not indented.
std::string vtu_of_tetmesh(const TetMesh& m, MeshEncoding encoding) {
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
    return write_vtu_text(g, encoding);
}

}  // namespace detail

void write_surface_vtu(const std::string& path, const Surface& surface, const std::vector<VtuArray>& point_data,
                       const std::vector<VtuArray>& cell_data, MeshEncoding encoding) {
    const std::string where = detail::display_name(path);
    const size_t nv = surface.vertices.size(), nt = surface.triangles.size();
    if (surface.patches.size() != nt) throw OutputError(where, "patches and triangles differ in number");
    for (const Tri& t : surface.triangles)
        for (int32_t v : t)
            if (v < 0 || size_t(v) >= nv) throw OutputError(where, "triangle index out of range");
    detail::write_file_atomically(path, detail::vtu_of_surface(surface, point_data, cell_data, where, encoding));
}

}  // namespace bpm
