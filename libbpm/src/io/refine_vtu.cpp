// A small VTK XML unstructured-grid writer (ASCII) for refined surfaces: triangles
// (VTK cell type 5), the patch id as Int32 cell data, any further point/cell arrays as
// Float64. Files open in ParaView and the vtk Python module.

#include <cstdio>
#include <sstream>

#include "bpm/errors.h"
#include "bpm/refine.h"
#include "core/file_util.h"

namespace bpm {

namespace {

void write_array(std::ostringstream& os, const VtuArray& a, size_t count, const std::string& where) {
    if (a.components < 1 || a.values.size() != count * size_t(a.components))
        throw OutputError(where, "VTU array '" + a.name + "' has " + std::to_string(a.values.size()) +
                                     " values, expected " + std::to_string(count) + " x " +
                                     std::to_string(a.components));
    os << "        <DataArray type=\"Float64\" Name=\"" << a.name << "\" NumberOfComponents=\"" << a.components
       << "\" format=\"ascii\">\n";
    char buf[40];
    for (size_t i = 0; i < a.values.size(); ++i) {
        std::snprintf(buf, sizeof buf, "%.17g", a.values[i]);
        os << (i % size_t(a.components) == 0 ? "          " : " ") << buf;
        if ((i + 1) % size_t(a.components) == 0) os << '\n';
    }
    os << "        </DataArray>\n";
}

}  // namespace

void write_vtu(const std::string& path, const Surface& surface, const std::vector<VtuArray>& point_data,
               const std::vector<VtuArray>& cell_data) {
    const std::string where = detail::display_name(path);
    const size_t nv = surface.vertices.size(), nt = surface.triangles.size();
    if (surface.patches.size() != nt) throw OutputError(where, "patches and triangles differ in number");
    for (const Tri& t : surface.triangles)
        for (int32_t v : t)
            if (v < 0 || size_t(v) >= nv) throw OutputError(where, "triangle index out of range");
    std::ostringstream os;
    os << "<?xml version=\"1.0\"?>\n"
       << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
       << "  <UnstructuredGrid>\n"
       << "    <Piece NumberOfPoints=\"" << nv << "\" NumberOfCells=\"" << nt << "\">\n";
    os << "      <PointData>\n";
    for (const VtuArray& a : point_data) write_array(os, a, nv, where);
    os << "      </PointData>\n      <CellData>\n";
    os << "        <DataArray type=\"Int32\" Name=\"patch\" format=\"ascii\">\n";
    for (size_t t = 0; t < nt; ++t) os << (t % 16 == 0 ? "          " : " ") << surface.patches[t] << ((t % 16 == 15 || t + 1 == nt) ? "\n" : "");
    os << "        </DataArray>\n";
    for (const VtuArray& a : cell_data) write_array(os, a, nt, where);
    os << "      </CellData>\n      <Points>\n"
       << "        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    char buf[160];
    for (const Vec3& x : surface.vertices) {
        std::snprintf(buf, sizeof buf, "          %.17g %.17g %.17g\n", x[0], x[1], x[2]);
        os << buf;
    }
    os << "        </DataArray>\n      </Points>\n      <Cells>\n"
       << "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
    for (const Tri& t : surface.triangles) os << "          " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
    os << "        </DataArray>\n        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
    for (size_t t = 0; t < nt; ++t) os << (t % 16 == 0 ? "          " : " ") << 3 * (t + 1) << ((t % 16 == 15 || t + 1 == nt) ? "\n" : "");
    os << "        </DataArray>\n        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
    for (size_t t = 0; t < nt; ++t) os << (t % 16 == 0 ? "          " : " ") << 5 << ((t % 16 == 15 || t + 1 == nt) ? "\n" : "");
    os << "        </DataArray>\n      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
    detail::write_file_atomically(path, os.str());
}

}  // namespace bpm
