// Legacy VTK reader (.vtk, "# vtk DataFile Version x.y"), ASCII and BINARY (big endian),
// file versions 1.0 to 5.x, as written by VTK's vtkPolyDataWriter / vtkUnstructuredGridWriter,
// ParaView, 3D Slicer, ITK-SNAP and many simulation codes.
//
// Datasets:
//   POLYDATA           POINTS; POLYGONS (3 corners: a triangle; more: a polygon, refused
//                      unless accept_polygons: the triangulate-polygons repair), TRIANGLE_STRIPS
//                      (split into triangles, every other one flipped so that all keep the
//                      strip's orientation, as vtkTriangleStrip does); VERTICES and LINES are
//                      not surface cells: skipped, counted and noted.
//   UNSTRUCTURED_GRID  POINTS, CELLS, CELL_TYPES: triangles (5), strips (6), polygons (7),
//                      pixels (8) and quads (9) as above; vertices and lines (1-4) skipped;
//                      volume cells (10-16, 42) skipped with a note when there are surface
//                      cells too, refused when there are none (a volume mesh: extract the
//                      boundary first); any other type (quadratic, Lagrange, ...) refused.
//   Anything else (STRUCTURED_POINTS, STRUCTURED_GRID, RECTILINEAR_GRID, FIELD only) is refused.
// Both cell layouts: "POLYGONS n size" followed by n records "count i0 i1 ..." (up to 4.2),
// and "POLYGONS n+1 m" followed by "OFFSETS type" and "CONNECTIVITY type" arrays (5.1).
//
// Attributes:
//   POINT_DATA  every SCALARS, COLOR_SCALARS, VECTORS, NORMALS, TEXTURE_COORDINATES,
//               TENSORS / TENSORS6 and FIELD array becomes a VertexArray (values as double;
//               COLOR_SCALARS of a binary file: unsigned char / 255, as VTK reads them).
//               Names are %-decoded like VTK does; '/' becomes '_' and repeated names get
//               "_2", "_3", ... (bpm files store the arrays by name), with a note. An array
//               with NaN or infinite values is dropped with a note rather than failing the
//               whole file: such values are common as "no data" markers.
//   CELL_DATA   the first 1-component array with whole-number values named patch, material,
//               region, label or physical (any case), failing that one named gmsh:physical,
//               CellEntityIds or RegionId (Gmsh, meshio, Slicer), failing that the array
//               named "scalars" (VTK's name for unnamed scalars: vtkDiscreteMarchingCubes'
//               labels), gives the patch id of every triangle made from the cell. Other
//               cell arrays are ignored (one note).
//   LOOKUP_TABLE sections and METADATA blocks are skipped; string arrays are skipped.
//
// The points must come before the cells (every writer does this), so that each index is
// checked where it is read and an error names its line or byte offset. Counts are checked
// against the bytes left before anything is allocated for them.
#include <algorithm>
#include <string>
#include <unordered_map>
#include <unordered_set>

#include "core/number_text.h"
#include "io/surface_readers.h"
#include "io/vtk_types.h"

namespace bpm::detail {

namespace {


// The name vtkDataWriter writes for an unnamed SCALARS array.
constexpr const char* kUnnamedScalars = "scalars";

char lower_char(char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; }

bool iequals(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (lower_char(a[i]) != lower_char(b[i])) return false;
    return true;
}

bool vtk_type_from_name(std::string_view name, VtkType& type) {
    struct Entry {
        const char* name;
        VtkType type;
    };
    // "long" is 8 bytes: VTK writes sizeof(long) bytes, and the files that matter come from
    // 64-bit Linux and macOS. vtkIdType arrays are written as 32-bit int by vtkDataWriter
    // (cell OFFSETS / CONNECTIVITY use vtktypeint64 instead).
    static const Entry entries[] = {
        {"bit", VtkType::Bit},
        {"char", VtkType::Int8},
        {"signed_char", VtkType::Int8},
        {"unsigned_char", VtkType::UInt8},
        {"short", VtkType::Int16},
        {"unsigned_short", VtkType::UInt16},
        {"int", VtkType::Int32},
        {"unsigned_int", VtkType::UInt32},
        {"long", VtkType::Int64},
        {"unsigned_long", VtkType::UInt64},
        {"long_long", VtkType::Int64},
        {"unsigned_long_long", VtkType::UInt64},
        {"vtkidtype", VtkType::Int32},
        {"vtktypeint8", VtkType::Int8},
        {"vtktypeuint8", VtkType::UInt8},
        {"vtktypeint16", VtkType::Int16},
        {"vtktypeuint16", VtkType::UInt16},
        {"vtktypeint32", VtkType::Int32},
        {"vtktypeuint32", VtkType::UInt32},
        {"vtktypeint64", VtkType::Int64},
        {"vtktypeuint64", VtkType::UInt64},
        {"float", VtkType::Float32},
        {"vtktypefloat32", VtkType::Float32},
        {"double", VtkType::Float64},
        {"vtktypefloat64", VtkType::Float64},
        {"string", VtkType::String},
        {"utf8_string", VtkType::String},
    };
    for (const Entry& e : entries) {
        if (iequals(name, e.name)) {
            type = e.type;
            return true;
        }
    }
    return false;
}


// Bytes that `count` values take at least: their size in a binary file (bits packed eight
// to a byte), a digit and a separator in an ASCII one.
double least_bytes(VtkType type, double count, bool binary) {
    if (type == VtkType::String) return count;  // ASCII: one line each; binary: a length byte each
    if (!binary) return 2 * count;
    if (type == VtkType::Bit) return std::ceil(count / 8);
    return count * static_cast<double>(vtk_type_size(type));
}

// VTK %-encodes names that contain blanks or other special characters ("a%20b").
std::string decode_name(std::string_view raw) {
    auto hex = [](char c) -> int {
        if (c >= '0' && c <= '9') return c - '0';
        if (c >= 'a' && c <= 'f') return c - 'a' + 10;
        if (c >= 'A' && c <= 'F') return c - 'A' + 10;
        return -1;
    };
    std::string out;
    for (size_t i = 0; i < raw.size(); ++i) {
        const int code = raw[i] == '%' && i + 2 < raw.size() && hex(raw[i + 1]) >= 0 && hex(raw[i + 2]) >= 0
                             ? hex(raw[i + 1]) * 16 + hex(raw[i + 2])
                             : -1;
        // Control characters (%00 ...) stay encoded: names end up as HDF5 link names.
        if (code >= 0x20) {
            out += static_cast<char>(code);
            i += 2;
        } else {
            out += raw[i];
        }
    }
    return out;
}

// A cell list (POLYGONS, TRIANGLE_STRIPS, VERTICES, LINES or CELLS) with every index
// checked against the points.
struct CellList {
    std::vector<int64_t> start{0};  // #cells + 1: cell c is connectivity[start[c], start[c+1])
    std::vector<int32_t> connectivity;
    std::vector<size_t> at;  // where each cell is in the file, for messages
    size_t keyword_at = 0;
    bool present = false;
    size_t size() const { return start.size() - 1; }
    int64_t corners(size_t c) const { return start[c + 1] - start[c]; }
};

// One attribute array as read: name, components, values (empty when skipped).
struct VtkArray {
    std::string name;
    size_t at = 0;  // its header, for messages
    int components = 1;
    int64_t tuples = 0;
    VtkType type = VtkType::Float32;
    std::vector<double> values;
    bool finite = true;
    bool whole = true;  // every value an integer that fits in int32
};

class VtkReader {
public:
    VtkReader(std::string_view bytes, const std::string& name, bool accept_polygons)
        : in_(bytes, name), accept_polygons_(accept_polygons) {}

    ReaderOutput read();

private:
    // ---- errors -----------------------------------------------------------------------
    // At a value: its byte offset in a binary file, its line in an ASCII one.
    [[noreturn]] void fail_at(size_t at, const std::string& message) const {
        if (binary_) in_.fail_offset(at, message);
        in_.fail_line(at, message);
    }
    // Keyword lines are text in binary files too: their errors name the line.
    [[noreturn]] void fail_line(size_t at, const std::string& message) const { in_.fail_line(at, message); }

    // `count` values of `type` must fit into the rest of the file; `what` names them.
    void check_values_fit(size_t at, double count, VtkType type, const std::string& what) const {
        if (count < 0) fail_line(at, "negative number of " + what);
        const double need = least_bytes(type, count, binary_) - (binary_ ? 0 : 1);
        if (need > static_cast<double>(in_.remaining())) {
            fail_line(at, std::to_string(static_cast<int64_t>(count)) + " " + what + " announced, but the " +
                              std::to_string(in_.remaining()) +
                              " bytes left in the file cannot hold that many (truncated, or wrong counts?)");
        }
    }
    void check_index_count(size_t at, int64_t count, const std::string& what) const {
        if (count < 0) fail_line(at, "negative number of " + what + " (" + std::to_string(count) + ")");
        if (count > std::numeric_limits<int32_t>::max()) {
            fail_line(at, std::to_string(count) + " " + what + " announced; bpm supports at most " +
                              std::to_string(std::numeric_limits<int32_t>::max()));
        }
    }

    // ---- keyword lines ----------------------------------------------------------------
    // The next keyword (skipping blank lines); empty at the end of the file.
    std::string_view keyword() { return in_.next_token(); }
    std::string_view word(const char* what) {
        const std::string_view w = in_.token_on_line();
        if (w.empty()) in_.fail_token(w, what);
        return w;
    }
    int64_t line_int(const Label& what) { return in_.line_int(what); }
    VtkType data_type(const char* what) {
        const std::string_view w = word(what);
        VtkType t;
        if (!vtk_type_from_name(w, t)) {
            fail_line(in_.offset_of(w), "unknown VTK data type " + quote_token(w) +
                                            " (expected float, double, int, unsigned_char, vtktypeint64, ...)");
        }
        return t;
    }
    // Ends a keyword line; binary data starts right after its line end.
    void end_line(const char* context) { in_.expect_line_end(context); }

    // ---- values -----------------------------------------------------------------------
    // Where the next value starts (in ASCII after the white space before it).
    size_t value_pos() {
        if (!binary_) in_.skip_space();
        return in_.pos();
    }
    double binary_value(VtkType type, const Label& what) {
        switch (type) {
            case VtkType::Int8: return in_.read_binary<int8_t>(true, what);
            case VtkType::Bit:
            case VtkType::String:
            case VtkType::UInt8: return in_.read_binary<uint8_t>(true, what);
            case VtkType::Int16: return in_.read_binary<int16_t>(true, what);
            case VtkType::UInt16: return in_.read_binary<uint16_t>(true, what);
            case VtkType::Int32: return in_.read_binary<int32_t>(true, what);
            case VtkType::UInt32: return in_.read_binary<uint32_t>(true, what);
            case VtkType::Int64: return static_cast<double>(in_.read_binary<int64_t>(true, what));
            case VtkType::UInt64: return static_cast<double>(in_.read_binary<uint64_t>(true, what));
            case VtkType::Float32: return in_.read_binary<float>(true, what);
            case VtkType::Float64: return in_.read_binary<double>(true, what);
        }
        return 0;
    }
    // An integer value (indices, offsets, counts, cell types).
    int64_t integer(VtkType type, const Label& what) {
        if (!binary_) {
            const std::string_view token = in_.next_token();
            if (vtk_type_is_integer(type)) return in_.to_int(token, what);
            const double v = in_.to_double(token, what);
            if (v != std::floor(v) || std::fabs(v) > 9e15) {
                in_.fail_line(in_.offset_of(token), what.str() + " " + quote_token(token) + " is not an integer");
            }
            return static_cast<int64_t>(v);
        }
        const size_t at = in_.pos();
        if (type == VtkType::Int64) return in_.read_binary<int64_t>(true, what);
        if (type == VtkType::UInt64) {
            const uint64_t v = in_.read_binary<uint64_t>(true, what);
            if (v > static_cast<uint64_t>(std::numeric_limits<int64_t>::max()))
                in_.fail_offset(at, what.str() + " is out of range");
            return static_cast<int64_t>(v);
        }
        const double v = binary_value(type, what);
        if (!std::isfinite(v) || v != std::floor(v) || std::fabs(v) > 9e15)
            in_.fail_offset(at, what.str() + " is not an integer");
        return static_cast<int64_t>(v);
    }
    // A coordinate: finite.
    double coordinate(VtkType type, const Label& what) {
        if (!binary_) {
            const std::string_view token = in_.next_token();
            if (vtk_type_is_integer(type)) return static_cast<double>(in_.to_int(token, what));
            return in_.to_double(token, what);
        }
        const size_t at = in_.pos();
        const double v = binary_value(type, what);
        if (!std::isfinite(v)) in_.fail_offset(at, what.str() + " is " + (std::isnan(v) ? "NaN" : "infinite"));
        return v;
    }
    // `count` values of an attribute array into `out` (nullptr: checked, not kept). Unlike
    // coordinates, NaN and infinities are read (and reported through `finite`).
    void data_values(VtkType type, int64_t count, std::vector<double>* out, bool& finite, const Label& what);
    void skip_strings(int64_t count, const Label& what);

    // ---- sections ---------------------------------------------------------------------
    void read_points(size_t at);
    void read_cells(CellList& cells, size_t at, std::string_view section);
    void read_cell_types(size_t at);
    void read_attribute(std::string_view keyword, size_t at);
    void read_field(size_t at, bool keep);
    void read_array_values(VtkArray& array, bool keep, const std::string& what);
    void skip_lookup_table(size_t at);
    void skip_metadata();
    void take_array(VtkArray&& array);
    void assemble();

    InputCursor in_;
    bool accept_polygons_ = false;
    bool binary_ = false;
    ReaderOutput out_;
    enum class Dataset { None, PolyData, UnstructuredGrid } dataset_ = Dataset::None;
    bool have_points_ = false;
    CellList verts_, lines_, polys_, strips_, cells_;
    std::vector<uint8_t> cell_types_;  // unstructured grid: one per cell (values above 255 refused)
    bool have_cell_types_ = false;
    size_t first_volume_at_ = 0;  // position of the first volume cell's type, for messages
    int64_t first_volume_cell_ = -1;
    int first_volume_type_ = 0;
    enum class Attribute { None, Point, Cell } attribute_ = Attribute::None;
    int64_t num_cells_ = 0;
    // The patch array: the first one with a primary name (rank 0), else a secondary one (1).
    std::vector<double> patch_values_;
    static constexpr int kNoPatchRank = 3;  // take_array's rank of a cell array that is no patch id
    int patch_rank_ = kNoPatchRank;
    std::string patch_name_;
    std::vector<std::string> ignored_cell_arrays_;
    std::vector<std::string> dropped_arrays_;
    std::unordered_set<std::string> used_names_;
    std::unordered_map<std::string, int> next_suffix_;
};

void VtkReader::data_values(VtkType type, int64_t count, std::vector<double>* out, bool& finite, const Label& what) {
    if (out) out->reserve(static_cast<size_t>(count));
    if (type == VtkType::Bit && binary_) {
        // Packed eight to a byte, most significant bit first.
        const size_t bytes = static_cast<size_t>((count + 7) / 8);
        in_.require(bytes, what);
        const std::string_view raw = in_.bytes().substr(in_.pos(), bytes);
        if (out) {
            for (int64_t i = 0; i < count; ++i) {
                const unsigned char byte = static_cast<unsigned char>(raw[static_cast<size_t>(i / 8)]);
                out->push_back((byte >> (7 - i % 8)) & 1);
            }
        }
        in_.seek(in_.pos() + bytes);
        return;
    }
    if (binary_) {
        const size_t bytes = static_cast<size_t>(count) * vtk_type_size(type);
        in_.require(bytes, what);
        if (!out) {
            // Skipped values still have to be finite for `finite` to mean anything; they are
            // not kept, so only floats need a look.
            if (type == VtkType::Float32 || type == VtkType::Float64) {
                for (int64_t i = 0; i < count; ++i) finite &= std::isfinite(binary_value(type, what));
            } else {
                in_.seek(in_.pos() + bytes);
            }
            return;
        }
        for (int64_t i = 0; i < count; ++i) {
            const double v = binary_value(type, what);
            finite &= std::isfinite(v);
            out->push_back(v);
        }
        return;
    }
    for (int64_t i = 0; i < count; ++i) {
        const std::string_view token = in_.next_token();
        double v = 0;
        if (vtk_type_is_integer(type)) {
            v = static_cast<double>(in_.to_int(token, what));
        } else {
            // nan / inf / -nan as VTK writes them are numbers here; `finite` reports them.
            std::string_view t = token;
            if (t.size() > 1 && t[0] == '+' && t[1] != '-' && t[1] != '+') t.remove_prefix(1);
            const auto [end, ec] = detail::parse_double(t.data(), t.data() + t.size(), v);  // out of range: +-inf, +-0
            if (t.empty() || end != t.data() + t.size() || ec != std::errc()) {
                in_.fail_token(token, what.str() + " (a number)");
            }
        }
        finite &= std::isfinite(v);
        if (out) out->push_back(v);
    }
}

// String arrays (rare in point data, common in the dataset's FIELD): ASCII one per line,
// binary each with a length prefix whose two top bits give its size (1, 2, 4 or 8 bytes).
void VtkReader::skip_strings(int64_t count, const Label& what) {
    if (!binary_) {
        for (int64_t i = 0; i < count; ++i) {
            if (in_.at_end()) in_.fail_line(in_.pos(), "the file ends inside " + what.str());
            in_.skip_line();
        }
        return;
    }
    for (int64_t i = 0; i < count; ++i) {
        const size_t at = in_.pos();
        const uint8_t first = in_.read_binary<uint8_t>(true, what);
        uint64_t length = first & 0x3f;
        const int extra = (first >> 6) == 3 ? 0 : (first >> 6) == 2 ? 1 : (first >> 6) == 1 ? 3 : 7;
        for (int k = 0; k < extra; ++k) length = (length << 8) | in_.read_binary<uint8_t>(true, what);
        if (length > in_.remaining())
            in_.fail_offset(
                at, what.str() + ": a string of " + std::to_string(length) + " bytes runs past the end of the file");
        in_.seek(in_.pos() + static_cast<size_t>(length));
    }
}

void VtkReader::read_points(size_t at) {
    if (dataset_ == Dataset::None) fail_line(at, "POINTS before the DATASET line");
    if (have_points_) fail_line(at, "a second POINTS section");
    const int64_t n = line_int("the number of points");
    const VtkType type = data_type("the data type of the points");
    if (type == VtkType::Bit || type == VtkType::String)
        fail_line(at, "points cannot have the data type bit or string");
    end_line("after 'POINTS <n> <type>'");
    check_index_count(at, n, "points");
    check_values_fit(at, 3.0 * static_cast<double>(n), type, "point coordinates");
    Surface& s = out_.surface;
    s.vertices.resize(static_cast<size_t>(n));
    for (int64_t i = 0; i < n; ++i) {
        static const char* const axis[3] = {"x", "y", "z"};
        for (int k = 0; k < 3; ++k)
            s.vertices[static_cast<size_t>(i)][k] = coordinate(type, Label("point ", i, ": coordinate ", axis[k]));
    }
    have_points_ = true;
}

void VtkReader::read_cells(CellList& cells, size_t at, std::string_view section) {
    const std::string kw(section);
    if (!have_points_) fail_line(at, kw + " before POINTS (bpm needs the points first)");
    if (cells.present) fail_line(at, "a second " + kw + " section");
    cells.present = true;
    cells.keyword_at = at;
    const int64_t n = line_int("the number of cells after " + kw);
    const int64_t size = line_int("the size of the cell list after " + kw);
    end_line(("after '" + kw + " <n> <size>'").c_str());
    const int64_t nv = static_cast<int64_t>(out_.surface.vertices.size());
    const std::string index_label = "a point index of " + kw;
    auto check_index = [&](int64_t index, size_t where, size_t cell) {
        if (index < 0 || index >= nv) {
            fail_at(where, kw + " cell " + std::to_string(cell) + ": point index " + std::to_string(index) +
                               " is out of range (the file has " + std::to_string(nv) + " points)");
        }
    };

    // The 5.1 layout announces its arrays by keyword; the old one starts with a number.
    const size_t saved = in_.pos();
    const std::string_view next = binary_ ? in_.bytes().substr(in_.pos(), 7) : in_.next_token();
    in_.seek(saved);
    if (iequals(next, "OFFSETS")) {
        // n offsets (#cells + 1), size connectivity entries.
        check_index_count(at, n, "cell offsets");
        check_index_count(at, size, "connectivity entries");
        const std::string_view okw = keyword();
        const size_t offsets_at = in_.offset_of(okw);
        const VtkType otype = data_type("the data type of OFFSETS");
        if (!vtk_type_is_integer(otype) || otype == VtkType::Bit)
            fail_line(offsets_at, "OFFSETS must have an integer type");
        end_line("after 'OFFSETS <type>'");
        check_values_fit(at, static_cast<double>(n) + static_cast<double>(size), otype,
                         "cell offsets and connectivity entries");
        const int64_t cells_n = n > 0 ? n - 1 : 0;
        cells.start.clear();
        cells.start.reserve(static_cast<size_t>(n > 0 ? n : 1));
        for (int64_t i = 0; i < n; ++i) {
            const size_t where = value_pos();
            const int64_t o = integer(otype, Label("cell offset ", i));
            const int64_t previous = i == 0 ? 0 : cells.start.back();
            if ((i == 0 && o != 0) || o < previous || o > size) {
                fail_at(where,
                        kw + " offset " + std::to_string(i) + " is " + std::to_string(o) + "; expected " +
                            (i == 0 ? std::string("0")
                                    : "a value from " + std::to_string(previous) + " to " + std::to_string(size)));
            }
            cells.start.push_back(o);
        }
        if (n == 0) cells.start.push_back(0);
        if (cells.start.back() != size) {
            fail_line(at, kw + ": the last offset is " + std::to_string(cells.start.back()) +
                              ", but the connectivity has " + std::to_string(size) + " entries");
        }
        const std::string_view ckw = keyword();
        if (!iequals(ckw, "CONNECTIVITY")) in_.fail_token(ckw, "CONNECTIVITY after the OFFSETS of " + kw);
        const size_t ckw_at = in_.offset_of(ckw);
        const VtkType ctype = data_type("the data type of CONNECTIVITY");
        if (!vtk_type_is_integer(ctype) || ctype == VtkType::Bit)
            fail_line(ckw_at, "CONNECTIVITY must have an integer type");
        end_line("after 'CONNECTIVITY <type>'");
        check_values_fit(ckw_at, static_cast<double>(size), ctype, "connectivity entries");
        cells.connectivity.reserve(static_cast<size_t>(size));
        cells.at.reserve(static_cast<size_t>(cells_n));
        size_t cell = 0;
        for (int64_t k = 0; k < size; ++k) {
            const size_t where = value_pos();
            while (cell < static_cast<size_t>(cells_n) && cells.start[cell] == k) {
                cells.at.push_back(where);
                ++cell;
            }
            const int64_t index = integer(ctype, index_label);
            // The cell this entry belongs to: the last one starting at or before k.
            check_index(index, where, cell == 0 ? 0 : cell - 1);
            cells.connectivity.push_back(static_cast<int32_t>(index));
        }
        const size_t end_at = value_pos();
        while (cells.at.size() < static_cast<size_t>(cells_n)) cells.at.push_back(end_at);  // empty cells at the end
        return;
    }

    // Old layout: n records "count i0 i1 ...", size integers in all, 32-bit in binary files.
    check_index_count(at, n, "cells");
    check_index_count(at, size, "cell list entries");
    if (n > size)
        fail_line(at, kw + ": " + std::to_string(n) + " cells cannot fit into a list of " + std::to_string(size) +
                          " integers");
    check_values_fit(at, static_cast<double>(size), VtkType::Int32, "cell list entries");
    cells.start.reserve(static_cast<size_t>(n) + 1);
    cells.at.reserve(static_cast<size_t>(n));
    cells.connectivity.reserve(static_cast<size_t>(size - n));
    int64_t used = 0;
    for (int64_t c = 0; c < n; ++c) {
        const size_t where = value_pos();
        const int64_t count = integer(VtkType::Int32, Label("the point count of cell ", c));
        if (count < 0 || count > size - used - 1) {
            fail_at(where, kw + " cell " + std::to_string(c) + " has " + std::to_string(count) + " points, but only " +
                               std::to_string(std::max<int64_t>(size - used - 1, 0)) + " of the " +
                               std::to_string(size) + " announced entries are left (wrong size on the " + kw +
                               " line?)");
        }
        cells.at.push_back(where);
        for (int64_t k = 0; k < count; ++k) {
            const size_t index_at = value_pos();
            const int64_t index = integer(VtkType::Int32, Label("a point index of cell ", c));
            check_index(index, index_at, static_cast<size_t>(c));
            cells.connectivity.push_back(static_cast<int32_t>(index));
        }
        used += count + 1;
        cells.start.push_back(static_cast<int64_t>(cells.connectivity.size()));
    }
    if (used != size) {
        fail_line(at, kw + ": " + std::to_string(n) + " cells use " + std::to_string(used) + " integers, but " +
                          std::to_string(size) + " were announced");
    }
}

void VtkReader::read_cell_types(size_t at) {
    if (dataset_ != Dataset::UnstructuredGrid) fail_line(at, "CELL_TYPES outside an UNSTRUCTURED_GRID");
    if (!cells_.present) fail_line(at, "CELL_TYPES before CELLS");
    if (have_cell_types_) fail_line(at, "a second CELL_TYPES section");
    have_cell_types_ = true;
    const int64_t n = line_int("the number of cell types");
    end_line("after 'CELL_TYPES <n>'");
    if (n != static_cast<int64_t>(cells_.size())) {
        fail_line(at,
                  "CELL_TYPES " + std::to_string(n) + " for the " + std::to_string(cells_.size()) + " cells of CELLS");
    }
    check_values_fit(at, static_cast<double>(n), VtkType::Int32, "cell types");
    cell_types_.reserve(static_cast<size_t>(n));
    for (int64_t c = 0; c < n; ++c) {
        const size_t where = value_pos();
        const int64_t type = integer(VtkType::Int32, Label("the type of cell ", c));
        if (type < 0 || type > 255)
            fail_at(where, "cell " + std::to_string(c) + ": unknown VTK cell type " + std::to_string(type));
        const bool volume = (type >= 10 && type <= 16) || type == 42;
        if (volume && first_volume_cell_ < 0) {
            first_volume_cell_ = c;
            first_volume_at_ = where;
            first_volume_type_ = static_cast<int>(type);
        }
        cell_types_.push_back(static_cast<uint8_t>(type));
    }
}

void VtkReader::skip_metadata() {
    // "METADATA" then INFORMATION / COMPONENT_NAMES lines up to an empty line.
    in_.skip_line();
    while (!in_.at_end()) {
        const std::string_view line = in_.rest_of_line();
        bool blank = true;
        for (char c : line) blank &= is_space(c);
        if (blank) break;
    }
}

void VtkReader::skip_lookup_table(size_t at) {
    (void)word("the name of the lookup table");
    const int64_t n = line_int("the size of the lookup table");
    end_line("after 'LOOKUP_TABLE <name> <size>'");
    check_index_count(at, n, "lookup table entries");
    bool finite = true;
    if (binary_) {
        check_values_fit(at, 4.0 * static_cast<double>(n), VtkType::UInt8, "lookup table values");
        data_values(VtkType::UInt8, 4 * n, nullptr, finite, "a lookup table value");
    } else {
        check_values_fit(at, 4.0 * static_cast<double>(n), VtkType::Float32, "lookup table values");
        data_values(VtkType::Float32, 4 * n, nullptr, finite, "a lookup table value");
    }
}

void VtkReader::read_array_values(VtkArray& a, bool keep, const std::string& what) {
    const double count = static_cast<double>(a.tuples) * a.components;
    if (a.type == VtkType::String) {
        check_values_fit(a.at, count, VtkType::UInt8, what + " strings");
        skip_strings(static_cast<int64_t>(count), Label(what));
        a.values.clear();
        return;
    }
    check_values_fit(a.at, count, a.type, what + " values");
    data_values(a.type, static_cast<int64_t>(count), keep ? &a.values : nullptr, a.finite, Label(what));
    for (double v : a.values) {
        a.whole &=
            v == std::floor(v) && v >= std::numeric_limits<int32_t>::min() && v <= std::numeric_limits<int32_t>::max();
    }
}

// FIELD name n, then n arrays "name components tuples type" (or NULL_ARRAY).
void VtkReader::read_field(size_t at, bool keep) {
    (void)word("the name of the field");
    const int64_t n = line_int("the number of arrays of the field");
    end_line("after 'FIELD <name> <number of arrays>'");
    check_index_count(at, n, "field arrays");
    check_values_fit(at, static_cast<double>(n), VtkType::UInt8, "field arrays");
    for (int64_t i = 0; i < n; ++i) {
        const std::string_view name = keyword();
        if (name.empty()) in_.fail_token(name, Label("field array ", i, " of the FIELD section"));
        VtkArray a;
        a.at = in_.offset_of(name);
        if (name == "NULL_ARRAY") {
            end_line("after NULL_ARRAY");
            continue;
        }
        a.name = decode_name(name);
        const int64_t components = line_int(Label("the number of components of field array ", i));
        a.tuples = line_int(Label("the number of tuples of field array ", i));
        a.type = data_type("the data type of the field array");
        end_line("after '<array name> <components> <tuples> <type>'");
        if (components < 1 || components > 1 << 20) {
            fail_line(a.at, "field array " + quote_token(name) + ": " + std::to_string(components) +
                                " components (expected 1 or more)");
        }
        a.components = static_cast<int>(components);
        check_index_count(a.at, a.tuples, "tuples");
        const bool matches =
            keep && a.type != VtkType::String &&
            a.tuples ==
                (attribute_ == Attribute::Point ? static_cast<int64_t>(out_.surface.vertices.size()) : num_cells_);
        read_array_values(a, matches, "field array '" + a.name + "'");
        if (keep && !matches) {
            dropped_arrays_.push_back(
                "'" + a.name + "' (" +
                (a.type == VtkType::String
                     ? std::string("strings")
                     : std::to_string(a.tuples) + " tuples for " +
                           std::to_string(attribute_ == Attribute::Point ? out_.surface.vertices.size()
                                                                         : static_cast<size_t>(num_cells_)) +
                           (attribute_ == Attribute::Point ? " points" : " cells")) +
                ")");
        } else if (matches) {
            take_array(std::move(a));
        }
        const size_t saved = in_.pos();
        if (iequals(in_.next_token(), "METADATA"))
            skip_metadata();
        else
            in_.seek(saved);
    }
}

void VtkReader::read_attribute(std::string_view kw, size_t at) {
    if (attribute_ == Attribute::None) fail_line(at, quote_token(kw) + " outside POINT_DATA and CELL_DATA");
    const int64_t expected =
        attribute_ == Attribute::Point ? static_cast<int64_t>(out_.surface.vertices.size()) : num_cells_;
    VtkArray a;
    a.at = at;
    a.tuples = expected;
    a.name = decode_name(word("the name of the array"));
    const std::string what = std::string(kw) + " '" + a.name + "'";
    if (iequals(kw, "SCALARS")) {
        a.type = data_type("the data type of the scalars");
        if (!in_.at_line_end()) {
            const int64_t c = line_int("the number of components of the scalars");
            if (c < 1 || c > 4) fail_line(at, what + ": " + std::to_string(c) + " components (SCALARS have 1 to 4)");
            a.components = static_cast<int>(c);
        }
        end_line("after 'SCALARS <name> <type> [<components>]'");
        // LOOKUP_TABLE <name> (required; "default" in most files).
        const std::string_view lt = keyword();
        if (!iequals(lt, "LOOKUP_TABLE")) in_.fail_token(lt, "LOOKUP_TABLE after " + what);
        (void)word("the name of the lookup table");
        end_line("after 'LOOKUP_TABLE <name>'");
    } else if (iequals(kw, "COLOR_SCALARS")) {
        const int64_t c = line_int("the number of values of the color scalars");
        if (c < 1 || c > 4) fail_line(at, what + ": " + std::to_string(c) + " values per color (expected 1 to 4)");
        a.components = static_cast<int>(c);
        a.type = binary_ ? VtkType::UInt8 : VtkType::Float32;
        end_line("after 'COLOR_SCALARS <name> <values>'");
    } else if (iequals(kw, "TEXTURE_COORDINATES")) {
        const int64_t c = line_int("the dimension of the texture coordinates");
        if (c < 1 || c > 3) fail_line(at, what + ": dimension " + std::to_string(c) + " (expected 1 to 3)");
        a.components = static_cast<int>(c);
        a.type = data_type("the data type of the texture coordinates");
        end_line("after 'TEXTURE_COORDINATES <name> <dimension> <type>'");
    } else {
        // VECTORS, NORMALS, TENSORS, TENSORS6
        a.components = iequals(kw, "TENSORS") ? 9 : iequals(kw, "TENSORS6") ? 6 : 3;
        a.type = data_type("the data type of the array");
        end_line(("after '" + std::string(kw) + " <name> <type>'").c_str());
    }
    if (a.type == VtkType::String) fail_line(at, what + ": string values are not allowed here");
    read_array_values(a, true, what);
    if (iequals(kw, "COLOR_SCALARS") && binary_) {
        for (double& v : a.values) v /= 255.0;
    }
    take_array(std::move(a));
    const size_t saved = in_.pos();
    if (iequals(in_.next_token(), "METADATA"))
        skip_metadata();
    else
        in_.seek(saved);
}

// A point array becomes vertex data; a cell array may give the patches.
void VtkReader::take_array(VtkArray&& a) {
    if (!a.finite) {
        dropped_arrays_.push_back("'" + a.name + "' (NaN or infinite values)");
        return;
    }
    if (attribute_ == Attribute::Cell) {
        auto is_one_of = [&](std::initializer_list<const char*> names) {
            for (const char* n : names)
                if (iequals(a.name, n)) return true;
            return false;
        };
        // "scalars" is the name vtkDataWriter gives an unnamed SCALARS array, such as the
        // labels vtkDiscreteMarchingCubes puts on its triangles (one closed surface per
        // label): taken only when no array is named as patches, and only with whole values.
        const int rank = is_one_of({"patch", "material", "region", "label", "physical"}) ? 0
                         : is_one_of({"gmsh:physical", "CellEntityIds", "RegionId"})     ? 1
                         : a.name == kUnnamedScalars                                     ? 2
                                                                                         : kNoPatchRank;
        if (rank < patch_rank_ && a.components == 1 && a.whole) {
            if (patch_rank_ < kNoPatchRank) ignored_cell_arrays_.push_back(patch_name_);
            patch_rank_ = rank;
            patch_name_ = a.name;
            patch_values_ = std::move(a.values);
        } else {
            ignored_cell_arrays_.push_back(a.name);
        }
        return;
    }
    VertexArray v;
    v.name = a.name;
    bool renamed = false;
    for (char& c : v.name) {
        if (c == '/') c = '_', renamed = true;
    }
    if (v.name.empty() || v.name == ".") v.name = "_", renamed = true;
    // A set of the names and, per name, the next suffix to try: files with thousands of
    // arrays of one name must not take quadratic time.
    std::string unique = v.name;
    if (used_names_.count(unique)) {
        int& k = next_suffix_[v.name];
        if (k < 2) k = 2;
        while (used_names_.count(unique = v.name + "_" + std::to_string(k))) ++k;
        renamed = true;
    }
    used_names_.insert(unique);
    if (renamed) out_.notes.push_back("point data array '" + a.name + "' stored as '" + unique + "'");
    v.name = unique;
    v.components = a.components;
    v.values = std::move(a.values);
    out_.surface.vertex_data.push_back(std::move(v));
}

ReaderOutput VtkReader::read() {
    const std::string_view bytes = in_.bytes();
    if (bytes.empty()) in_.fail("the file is empty");
    {
        const std::string_view header = in_.rest_of_line();
        const std::string_view magic = "# vtk DataFile Version";
        if (header.size() < magic.size() || !iequals(header.substr(0, magic.size()), magic)) {
            in_.fail_line(0, "not a legacy VTK file: the first line must be '# vtk DataFile Version x.y', found " +
                                 quote_token(header));
        }
        std::string_view version = header.substr(magic.size());
        while (!version.empty() && is_space(version.front())) version.remove_prefix(1);
        while (!version.empty() && is_space(version.back())) version.remove_suffix(1);
        if (version.empty() || version[0] < '1' || version[0] > '5' || (version.size() > 1 && version[1] != '.')) {
            in_.fail_line(0,
                          "unsupported VTK file version " + quote_token(version) + " (bpm reads versions 1.0 to 5.1)");
        }
    }
    if (in_.at_end()) in_.fail_line(in_.pos(), "the file ends after the header line (expected a title line)");
    (void)in_.rest_of_line();  // the title
    {
        const std::string_view encoding = in_.token_on_line();
        if (iequals(encoding, "BINARY"))
            binary_ = true;
        else if (!iequals(encoding, "ASCII"))
            in_.fail_token(encoding, "ASCII or BINARY on the third line");
        in_.expect_line_end("after the file type");
    }

    for (;;) {
        const std::string_view kw = keyword();
        if (kw.empty()) break;
        const size_t at = in_.offset_of(kw);
        if (iequals(kw, "DATASET")) {
            if (dataset_ != Dataset::None) fail_line(at, "a second DATASET line");
            const std::string_view type = word("the dataset type");
            if (iequals(type, "POLYDATA")) {
                dataset_ = Dataset::PolyData;
            } else if (iequals(type, "UNSTRUCTURED_GRID")) {
                dataset_ = Dataset::UnstructuredGrid;
            } else if (iequals(type, "STRUCTURED_POINTS") || iequals(type, "STRUCTURED_GRID") ||
                       iequals(type, "RECTILINEAR_GRID")) {
                fail_line(at,
                          "DATASET " + std::string(type) +
                              " is a grid, not a surface: bpm reads POLYDATA and UNSTRUCTURED_GRID (extract a surface, "
                              "e.g. with a contour filter, first)");
            } else {
                fail_line(in_.offset_of(type),
                          "unknown dataset type " + quote_token(type) + " (bpm reads POLYDATA and UNSTRUCTURED_GRID)");
            }
            in_.expect_line_end("after the dataset type");
        } else if (iequals(kw, "POINTS")) {
            read_points(at);
        } else if (iequals(kw, "POLYGONS") || iequals(kw, "TRIANGLE_STRIPS") || iequals(kw, "VERTICES") ||
                   iequals(kw, "LINES")) {
            if (dataset_ != Dataset::PolyData) fail_line(at, quote_token(kw) + " outside a POLYDATA dataset");
            if (attribute_ != Attribute::None) fail_line(at, quote_token(kw) + " after POINT_DATA / CELL_DATA");
            CellList& cells = iequals(kw, "POLYGONS")          ? polys_
                              : iequals(kw, "TRIANGLE_STRIPS") ? strips_
                              : iequals(kw, "VERTICES")        ? verts_
                                                               : lines_;
            read_cells(cells, at,
                       iequals(kw, "POLYGONS")          ? "POLYGONS"
                       : iequals(kw, "TRIANGLE_STRIPS") ? "TRIANGLE_STRIPS"
                       : iequals(kw, "VERTICES")        ? "VERTICES"
                                                        : "LINES");
        } else if (iequals(kw, "CELLS")) {
            if (dataset_ != Dataset::UnstructuredGrid) fail_line(at, "CELLS outside an UNSTRUCTURED_GRID dataset");
            if (attribute_ != Attribute::None) fail_line(at, "CELLS after POINT_DATA / CELL_DATA");
            read_cells(cells_, at, "CELLS");
        } else if (iequals(kw, "CELL_TYPES")) {
            read_cell_types(at);
        } else if (iequals(kw, "POINT_DATA") || iequals(kw, "CELL_DATA")) {
            const bool point = iequals(kw, "POINT_DATA");
            if (!have_points_) fail_line(at, std::string(kw) + " before POINTS");
            const int64_t n =
                line_int(point ? "the number of points of POINT_DATA" : "the number of cells of CELL_DATA");
            in_.expect_line_end("after the count");
            if (dataset_ == Dataset::UnstructuredGrid && !have_cell_types_ && !point)
                fail_line(at, "CELL_DATA before CELL_TYPES");
            num_cells_ = dataset_ == Dataset::UnstructuredGrid
                             ? static_cast<int64_t>(cells_.size())
                             : static_cast<int64_t>(verts_.size() + lines_.size() + polys_.size() + strips_.size());
            const int64_t expected = point ? static_cast<int64_t>(out_.surface.vertices.size()) : num_cells_;
            if (n != expected) {
                fail_line(at, std::string(kw) + " " + std::to_string(n) + ", but the file has " +
                                  std::to_string(expected) + (point ? " points" : " cells"));
            }
            attribute_ = point ? Attribute::Point : Attribute::Cell;
        } else if (iequals(kw, "SCALARS") || iequals(kw, "COLOR_SCALARS") || iequals(kw, "VECTORS") ||
                   iequals(kw, "NORMALS") || iequals(kw, "TEXTURE_COORDINATES") || iequals(kw, "TENSORS") ||
                   iequals(kw, "TENSORS6")) {
            read_attribute(kw, at);
        } else if (iequals(kw, "FIELD")) {
            // Inside POINT_DATA / CELL_DATA: arrays of the points or cells. Before them: the
            // dataset's own field data (time values, names), checked but not kept.
            read_field(at, attribute_ != Attribute::None);
        } else if (iequals(kw, "LOOKUP_TABLE")) {
            skip_lookup_table(at);
        } else if (iequals(kw, "METADATA")) {
            skip_metadata();
        } else {
            fail_line(at, "unknown keyword " + quote_token(kw) +
                              " (expected DATASET, POINTS, POLYGONS, TRIANGLE_STRIPS, CELLS, CELL_TYPES, POINT_DATA, "
                              "CELL_DATA, SCALARS, FIELD, ...)");
        }
    }
    if (dataset_ == Dataset::None) in_.fail("the file has no DATASET line");
    if (!have_points_) in_.fail("the file has no POINTS section");
    if (dataset_ == Dataset::UnstructuredGrid && cells_.present && !have_cell_types_)
        in_.fail("CELLS without CELL_TYPES");
    assemble();
    return std::move(out_);
}

const char* cell_type_name(int type) {
    switch (type) {
        case 10: return "a tetrahedron";
        case 11: return "a voxel";
        case 12: return "a hexahedron";
        case 13: return "a wedge";
        case 14: return "a pyramid";
        case 15: return "a pentagonal prism";
        case 16: return "a hexagonal prism";
        case 42: return "a polyhedron";
        case 21: return "a quadratic edge";
        case 22: return "a quadratic triangle";
        case 23: return "a quadratic quad";
        case 69: return "a Lagrange triangle";
        case 70: return "a Lagrange quadrilateral";
        default: return "a cell";
    }
}

// Turns the cells into triangles (and polygons), in cell order, with their patches.
void VtkReader::assemble() {
    Surface& s = out_.surface;
    std::vector<Tri>& tris = s.triangles;
    std::vector<int32_t>& patches = s.patches;
    int64_t skipped_points = 0, skipped_lines = 0, skipped_volume = 0, degenerate_strip = 0;
    const bool have_patches = patch_rank_ < kNoPatchRank;
    auto patch_of = [&](int64_t cell) {
        return have_patches ? static_cast<int32_t>(patch_values_[static_cast<size_t>(cell)]) : 0;
    };

    auto add_polygon = [&](const CellList& cells, size_t c, int64_t cell_id, const std::string& what,
                           const int* order) {
        const int64_t n = cells.corners(c);
        if (n < 3) {
            fail_at(cells.at[c], what + " " + std::to_string(cell_id) + " has " + std::to_string(n) +
                                     " points; a polygon needs at least 3");
        }
        const int32_t* v = cells.connectivity.data() + cells.start[c];
        if (n == 3) {
            tris.push_back({v[0], v[1], v[2]});
            patches.push_back(patch_of(cell_id));
            return;
        }
        if (!accept_polygons_) {
            fail_at(cells.at[c], what + " " + std::to_string(cell_id) + " has " + std::to_string(n) +
                                     " corners; only triangles are accepted (the triangulate-polygons repair splits "
                                     "polygons into triangles)");
        }
        PolygonFace polygon;
        polygon.position = tris.size();
        polygon.face = cell_id;
        polygon.offset = cells.at[c];
        polygon.patch = patch_of(cell_id);
        for (int64_t k = 0; k < n; ++k) polygon.corners.push_back(order ? v[order[k]] : v[k]);
        out_.polygons.push_back(std::move(polygon));
    };
    auto add_strip = [&](const CellList& cells, size_t c, int64_t cell_id, const std::string& what) {
        const int64_t n = cells.corners(c);
        if (n < 3)
            fail_at(cells.at[c], what + " " + std::to_string(cell_id) + " has " + std::to_string(n) +
                                     " points; a strip needs at least 3");
        const int32_t* v = cells.connectivity.data() + cells.start[c];
        for (int64_t i = 0; i + 2 < n; ++i) {
            // As vtkTriangleStrip: every odd triangle swaps its first two corners, which keeps
            // the orientation of the strip.
            Tri t = i % 2 == 0 ? Tri{v[i], v[i + 1], v[i + 2]} : Tri{v[i + 1], v[i], v[i + 2]};
            // Strips repeat a point to turn a corner: those triangles have no area and are
            // part of the encoding, not of the surface.
            if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
                ++degenerate_strip;
                continue;
            }
            tris.push_back(t);
            patches.push_back(patch_of(cell_id));
        }
    };

    if (dataset_ == Dataset::PolyData) {
        // VTK numbers polydata cells: vertices, lines, polygons, strips.
        skipped_points = static_cast<int64_t>(verts_.size());
        skipped_lines = static_cast<int64_t>(lines_.size());
        int64_t id = skipped_points + skipped_lines;
        size_t reserve = 0;
        for (size_t c = 0; c < polys_.size(); ++c)
            reserve += static_cast<size_t>(std::max<int64_t>(polys_.corners(c) - 2, 0));
        for (size_t c = 0; c < strips_.size(); ++c)
            reserve += static_cast<size_t>(std::max<int64_t>(strips_.corners(c) - 2, 0));
        tris.reserve(reserve);
        patches.reserve(reserve);
        for (size_t c = 0; c < polys_.size(); ++c, ++id) add_polygon(polys_, c, id, "POLYGONS cell", nullptr);
        for (size_t c = 0; c < strips_.size(); ++c, ++id) add_strip(strips_, c, id, "TRIANGLE_STRIPS cell");
    } else {
        bool surface_cells = false;
        for (const uint8_t t : cell_types_) surface_cells |= t >= 5 && t <= 9;
        if (first_volume_cell_ >= 0 && !surface_cells) {
            fail_at(first_volume_at_, "cell " + std::to_string(first_volume_cell_) + " is " +
                                          cell_type_name(first_volume_type_) + " (VTK type " +
                                          std::to_string(first_volume_type_) +
                                          "): bpm reads surfaces; extract the boundary first (e.g. vtkGeometryFilter, "
                                          "ParaView's Extract Surface)");
        }
        static const int pixel_order[4] = {0, 1, 3, 2};
        for (size_t c = 0; c < cells_.size(); ++c) {
            const int type = cell_types_[c];
            const int64_t id = static_cast<int64_t>(c);
            const int64_t n = cells_.corners(c);
            const std::string what = "cell";
            if (type == 1 || type == 2) {
                ++skipped_points;
            } else if (type == 3 || type == 4) {
                ++skipped_lines;
            } else if (type == 5 || type == 7 || type == 8 || type == 9) {
                if ((type == 5 && n != 3) || ((type == 8 || type == 9) && n != 4)) {
                    fail_at(cells_.at[c], "cell " + std::to_string(c) + " of type " + std::to_string(type) + " (" +
                                              (type == 5   ? "triangle"
                                               : type == 8 ? "pixel"
                                                           : "quad") +
                                              ") has " + std::to_string(n) + " points, expected " +
                                              (type == 5 ? "3" : "4"));
                }
                add_polygon(cells_, c, id, what, type == 8 ? pixel_order : nullptr);
            } else if (type == 6) {
                add_strip(cells_, c, id, what);
            } else if ((type >= 10 && type <= 16) || type == 42) {
                ++skipped_volume;
            } else {
                fail_at(cells_.at[c], "cell " + std::to_string(c) + " is " + cell_type_name(type) + " (VTK type " +
                                          std::to_string(type) +
                                          "): bpm reads linear triangles, quads, polygons and triangle strips only");
            }
        }
    }

    const int64_t skipped = skipped_points + skipped_lines + skipped_volume;
    out_.skipped_elements = skipped;
    if (skipped_points > 0) out_.notes.push_back(std::to_string(skipped_points) + " vertex cells skipped");
    if (skipped_lines > 0) out_.notes.push_back(std::to_string(skipped_lines) + " line cells skipped");
    if (skipped_volume > 0) {
        out_.notes.push_back(std::to_string(skipped_volume) + " volume cells skipped (the surface cells are read)");
    }
    if (degenerate_strip > 0) {
        out_.notes.push_back(std::to_string(degenerate_strip) + " zero-area triangles of triangle strips dropped");
    }
    if (have_patches)
        out_.notes.push_back("patch ids from the cell data array '" + patch_name_ + "'" +
                             (patch_name_ == kUnnamedScalars ? " (VTK's name for unnamed cell scalars, such as the "
                                                               "labels of vtkDiscreteMarchingCubes)"
                                                             : ""));
    if (!ignored_cell_arrays_.empty()) {
        std::string list;
        for (size_t i = 0; i < ignored_cell_arrays_.size() && i < 8; ++i)
            list += (i ? ", '" : "'") + ignored_cell_arrays_[i] + "'";
        if (ignored_cell_arrays_.size() > 8) list += ", ...";
        out_.notes.push_back("cell data ignored: " + list);
    }
    if (!dropped_arrays_.empty()) {
        std::string list;
        for (size_t i = 0; i < dropped_arrays_.size() && i < 8; ++i) list += (i ? ", " : "") + dropped_arrays_[i];
        if (dropped_arrays_.size() > 8) list += ", ...";
        out_.notes.push_back("data arrays not read: " + list);
    }
    insert_polygons(in_, binary_, out_);
}

}  // namespace

ReaderOutput read_vtk(std::string_view bytes, const std::string& name, bool accept_polygons) {
    VtkReader reader(bytes, name, accept_polygons);
    return reader.read();
}

}  // namespace bpm::detail
