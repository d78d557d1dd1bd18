// A minimal reader for the ASCII UnstructuredGrid .vtu files psurface-simplify writes:
//   <Piece NumberOfCells=".." NumberOfPoints="..">
//     <Points><DataArray ... NumberOfComponents="3" format="ascii"> x y z ... </DataArray></Points>
//     <Cells><DataArray Name="connectivity"> ..</DataArray><DataArray Name="offsets"> ..
//            <DataArray Name="types"> ..</DataArray></Cells>
// No XML library: the DataArray elements are found by their attributes. Binary/appended
// data and pieces other than the first are refused.

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "bpm/errors.h"
#include "metrics.h"

namespace bpm::bench {
namespace {

// The text of the attribute `name` in the tag that starts at `tag_begin`; "" if absent.
std::string attribute(const std::string& text, size_t tag_begin, const std::string& name) {
    const size_t tag_end = text.find('>', tag_begin);
    const std::string key = " " + name + "=\"";
    const size_t at = text.find(key, tag_begin);
    if (at == std::string::npos || at > tag_end) return "";
    const size_t value = at + key.size();
    return text.substr(value, text.find('"', value) - value);
}

// The numbers inside the first <DataArray ...> after `from` whose Name is `name` (or the
// first DataArray at all if `name` is empty).
template <class T>
std::vector<T> data_array(const std::string& text, const std::string& path, size_t from, const std::string& name) {
    size_t at = from;
    while ((at = text.find("<DataArray", at)) != std::string::npos) {
        if (name.empty() || attribute(text, at, "Name") == name) break;
        ++at;
    }
    if (at == std::string::npos) throw InputError(path, "no DataArray named '" + name + "'");
    const std::string format = attribute(text, at, "format");
    if (format != "ascii") throw InputError(path, "DataArray '" + name + "' has format '" + format + "', only ascii is read");
    const size_t begin = text.find('>', at) + 1;
    const size_t end = text.find("</DataArray>", begin);
    if (end == std::string::npos) throw InputError(path, "unterminated DataArray '" + name + "'");
    std::istringstream in(text.substr(begin, end - begin));
    std::vector<T> values;
    T v;
    while (in >> v) values.push_back(v);
    if (!in.eof()) throw InputError(path, "non-numeric value in DataArray '" + name + "'");
    return values;
}

}  // namespace

Surface read_vtu(const std::string& path, int64_t* dropped_vertices) {
    std::ifstream file(path, std::ios::binary);
    if (!file) throw InputError(path, "cannot open");
    std::stringstream buffer;
    buffer << file.rdbuf();
    const std::string text = buffer.str();

    const size_t piece = text.find("<Piece");
    if (piece == std::string::npos) throw InputError(path, "no <Piece> (not an UnstructuredGrid .vtu?)");
    if (text.find("<Piece", piece + 1) != std::string::npos) throw InputError(path, "more than one <Piece>");
    const long num_points = std::stol("0" + attribute(text, piece, "NumberOfPoints"));
    const long num_cells = std::stol("0" + attribute(text, piece, "NumberOfCells"));

    const size_t points = text.find("<Points", piece);
    const size_t cells = text.find("<Cells", piece);
    if (points == std::string::npos || cells == std::string::npos) throw InputError(path, "no <Points> or <Cells>");
    const std::vector<double> xyz = data_array<double>(text, path, points, "");
    const std::vector<long> connectivity = data_array<long>(text, path, cells, "connectivity");
    const std::vector<long> offsets = data_array<long>(text, path, cells, "offsets");
    const std::vector<int> types = data_array<int>(text, path, cells, "types");
    if (static_cast<long>(xyz.size()) != 3 * num_points)
        throw InputError(path, "Points has " + std::to_string(xyz.size()) + " values, expected 3 x " + std::to_string(num_points));
    if (static_cast<long>(offsets.size()) != num_cells || static_cast<long>(types.size()) != num_cells)
        throw InputError(path, "offsets/types do not have NumberOfCells entries");

    Surface s;
    std::vector<int32_t> new_index(static_cast<size_t>(num_points), -1);
    long previous = 0;
    for (long c = 0; c < num_cells; ++c) {
        if (types[c] != 5) throw InputError(path, "cell " + std::to_string(c) + " has VTK type " + std::to_string(types[c]) + ", only triangles (5) are read");
        if (offsets[c] != previous + 3 || offsets[c] > static_cast<long>(connectivity.size()))
            throw InputError(path, "cell " + std::to_string(c) + ": bad offset");
        Tri t{};
        for (int k = 0; k < 3; ++k) {
            const long v = connectivity[previous + k];
            if (v < 0 || v >= num_points) throw InputError(path, "cell " + std::to_string(c) + ": vertex index out of range");
            if (new_index[v] < 0) {
                new_index[v] = static_cast<int32_t>(s.vertices.size());
                s.vertices.push_back({xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]});
            }
            t[k] = new_index[v];
        }
        s.triangles.push_back(t);
        previous = offsets[c];
    }
    s.patches.assign(s.triangles.size(), 0);
    if (dropped_vertices) *dropped_vertices = num_points - static_cast<long>(s.vertices.size());
    return s;
}

}  // namespace bpm::bench
