// Gmsh MSH reader: versions 2.2 and 4.1, ASCII and binary.
//
// Read: $MeshFormat, $Nodes, $Elements, $PhysicalNames (the names of dimension 2 become
// PatchInfo names; "A|B" / "pair_A_B" names also give the two materials, unordered: see
// materials_from_patch_name; those of dimension 3 name materials, below), and for 4.1
// $Entities; every other section ($Periodic, $NodeData, $Comments, ...) is skipped. Node
// tags may be sparse and in any order; vertices are numbered in the order of the nodes in
// the file, triangles in the order of the elements. Element type 2 (3-node triangle)
// becomes a triangle; every other element type is skipped and counted
// (SurfaceReadReport::skipped_elements). Nodes used only by skipped elements are
// unreferenced vertices, so a volume mesh reads only with the drop-unreferenced-vertices
// repair.
//
// Physical volumes (4.1): a volume entity lists the surface entities that bound it, so a
// patch whose name gives no materials gets the two materials on its sides from the
// physical volumes its surface entities bound: the names of the two volumes (a physical
// volume without a name: "volume_<tag>"), or the one volume and "exterior" for a surface
// that bounds one volume only. Unordered (oriented = false): Gmsh signs the bounding
// surfaces, but an OpenCASCADE geometry (gmsh 4.8, a sphere in a box) gives the surface
// between two volumes the same sign in both. Only when every surface entity of the patch
// bounds the same volumes; otherwise, and in MSH 2.2 (which does not say which surfaces
// bound a volume), a note says that the physical volumes were ignored.
//
// Patch ids: 2.2 — the first tag of the element (its physical tag), 0 without tags.
// 4.1 — the first physical tag of the element's entity in $Entities, 0 when the entity
// has none or there is no $Entities section. (Not the entity tag: entities are a
// meshing detail, physical groups are what a user names.)
// Files bpm writes give patch p the physical tag p + 1 (Gmsh and its readers take tag 0
// as "no physical group") and say so in a section of their own, which other readers skip:
//     $BpmPatchIds
//     1
//     $EndBpmPatchIds
// (the number k: the physical tag of patch p is p + k). With it, tag t is read back as
// patch t - k, in the patches and in the names of $PhysicalNames; a tag below k is an
// error. Without it, patch = physical tag.
//
// Binary files: the integer after the version line must be 1 in the file's byte order;
// a file written on a big-endian machine is read by swapping. Only data size 8 (double
// and size_t of 8 bytes) is accepted.
#include <algorithm>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>

#include "io/surface_readers.h"

namespace bpm::detail {

namespace {

// Nodes per element type (Gmsh's numbering); 0 for types this reader does not know.
int nodes_of_element_type(int64_t type) {
    static const int table[] = {0,  2,  3,  4,  4,  8,  6,  5,  3,  6,  9,  10, 27, 18, 14, 1,
                                8,  20, 15, 13, 9,  10, 12, 15, 15, 21, 4,  5,  6,  20, 35, 56};
    if (type >= 0 && type < static_cast<int64_t>(sizeof table / sizeof table[0])) return table[type];
    if (type == 92) return 64;
    if (type == 93) return 125;
    return 0;
}

// Node tag -> vertex index, dense when the tags are, sorted otherwise.
class NodeIndex {
public:
    void add(int64_t tag, size_t at) { pairs_.push_back({tag, static_cast<int32_t>(pairs_.size()), at}); }
    void build(const InputCursor& in, bool binary) {
        int64_t max_tag = 0;
        for (const Entry& e : pairs_) max_tag = std::max(max_tag, e.tag);
        if (max_tag <= static_cast<int64_t>(pairs_.size()) * 2 + 16) {
            dense_.assign(static_cast<size_t>(max_tag) + 1, -1);
            for (const Entry& e : pairs_) {
                if (dense_[static_cast<size_t>(e.tag)] >= 0) duplicate(in, binary, e);
                dense_[static_cast<size_t>(e.tag)] = e.index;
            }
            pairs_.clear();
            pairs_.shrink_to_fit();
        } else {
            std::sort(pairs_.begin(), pairs_.end(), [](const Entry& a, const Entry& b) { return a.tag < b.tag; });
            for (size_t i = 1; i < pairs_.size(); ++i) {
                if (pairs_[i].tag == pairs_[i - 1].tag) duplicate(in, binary, pairs_[i]);
            }
        }
    }
    // -1 if the tag is not a node.
    int32_t find(int64_t tag) const {
        if (!dense_.empty() || pairs_.empty()) {
            return tag >= 0 && tag < static_cast<int64_t>(dense_.size()) ? dense_[static_cast<size_t>(tag)] : -1;
        }
        const auto it = std::lower_bound(pairs_.begin(), pairs_.end(), tag,
                                         [](const Entry& e, int64_t t) { return e.tag < t; });
        return it != pairs_.end() && it->tag == tag ? it->index : -1;
    }

private:
    struct Entry {
        int64_t tag;
        int32_t index;
        size_t at;
    };
    [[noreturn]] static void duplicate(const InputCursor& in, bool binary, const Entry& e) {
        const std::string message = "node tag " + std::to_string(e.tag) + " is used by two nodes";
        if (binary) in.fail_offset(e.at, message);
        in.fail_line(e.at, message);
    }
    std::vector<Entry> pairs_;
    std::vector<int32_t> dense_;
};

class MshReader {
public:
    MshReader(std::string_view bytes, const std::string& name) : in_(bytes, name) {}

    ReaderOutput read() {
        if (in_.size() == 0) in_.fail("the file is empty");
        read_format();
        for (;;) {
            const std::string_view token = in_.next_token();
            if (token.empty()) break;
            if (token.size() < 2 || token[0] != '$') in_.fail_token(token, "a section header such as '$Nodes'");
            const std::string section(token.substr(1));
            if (section == "Nodes") {
                if (have_nodes_) in_.fail_line(in_.offset_of(token), "a second $Nodes section");
                have_nodes_ = true;
                version4_ ? read_nodes4() : read_nodes2();
                expect_end("Nodes");
            } else if (section == "Elements") {
                if (have_elements_) in_.fail_line(in_.offset_of(token), "a second $Elements section");
                have_elements_ = true;
                version4_ ? read_elements4() : read_elements2();
                expect_end("Elements");
            } else if (section == "Entities" && version4_) {
                read_entities();
                expect_end("Entities");
            } else if (section == "PhysicalNames") {
                read_physical_names();
                expect_end("PhysicalNames");
            } else if (section == "BpmPatchIds") {
                const std::string_view value = in_.next_token();
                const int64_t offset = in_.to_int(value, "the physical tag of patch 0 in $BpmPatchIds");
                if (offset < 0 || offset > 1000000) in_.fail_token(value, "a small non-negative number in $BpmPatchIds");
                patch_offset_ = static_cast<int32_t>(offset);
                expect_end("BpmPatchIds");
            } else if (section == "MeshFormat") {
                in_.fail_line(in_.offset_of(token), "a second $MeshFormat section");
            } else {
                skip_section(token, section);
            }
        }
        if (!have_nodes_) in_.fail("no $Nodes section");
        if (!have_elements_) in_.fail("no $Elements section");
        return finish();
    }

private:
    [[noreturn]] void fail_at(size_t at, const std::string& message) const {
        if (binary_) in_.fail_offset(at, message);
        in_.fail_line(at, message);
    }

    void read_format() {
        const std::string_view head = in_.next_token();
        if (head == "$NOD") in_.fail_line(0, "MSH version 1 is not supported; save as MSH 2.2 or 4.1");
        if (head != "$MeshFormat") in_.fail_token(head, "'$MeshFormat' at the start of a Gmsh MSH file");
        const std::string_view version = in_.next_token();
        if (version == "4.1") {
            version4_ = true;
        } else if (version.size() >= 1 && version[0] == '2' && (version.size() == 1 || version[1] == '.')) {
            version4_ = false;
        } else {
            in_.fail_line(in_.offset_of(version), "MSH version " + quote_token(version) +
                                                      " is not supported; save as MSH 2.2 or 4.1");
        }
        const std::string_view type_token = in_.next_token();
        const int64_t file_type = in_.to_int(type_token, "the file type (0 for ASCII, 1 for binary)");
        if (file_type != 0 && file_type != 1) in_.fail_token(type_token, "the file type 0 (ASCII) or 1 (binary)");
        const std::string_view size_token = in_.next_token();
        const int64_t data_size = in_.to_int(size_token, "the data size");
        if (data_size != 8) {
            in_.fail_line(in_.offset_of(size_token), "data size " + std::to_string(data_size) + " is not supported (only 8)");
        }
        binary_ = file_type == 1;
        if (binary_) {
            in_.skip_line();
            const size_t at = in_.pos();
            const uint32_t one = in_.read_binary<uint32_t>(false, "the endianness marker");
            if (one == 1) {
                big_endian_ = false;
            } else if (one == 0x01000000u) {
                big_endian_ = true;
            } else {
                in_.fail_offset(at, "the binary endianness marker is " + std::to_string(one) +
                                        " instead of 1 (damaged file, or not binary)");
            }
        }
        expect_end("MeshFormat");
    }

    void expect_end(const std::string& section) {
        const std::string_view token = in_.next_token();
        if (token != "$End" + section) {
            in_.fail_token(token, "'$End" + section + "'" + (binary_ ? " (wrong counts or data size?)" : " (wrong counts?)"));
        }
    }

    void skip_section(std::string_view token, const std::string& section) {
        const std::string end = "$End" + section;
        const size_t found = in_.bytes().find(end, in_.pos());
        if (found == std::string_view::npos) {
            in_.fail_line(in_.offset_of(token), "section " + quote_token(token) + " has no '" + end + "'");
        }
        in_.seek(found);
        (void)in_.next_token();
    }

    // `n`, then n lines `dim tag "name"` (text also in binary files).
    void read_physical_names() {
        const size_t at = in_.pos();
        const int64_t n = in_.any_int("the number of physical names");
        check_count(in_, at, false, n, 6, "physical names");
        for (int64_t i = 0; i < n; ++i) {
            const int64_t dim = in_.any_int("the dimension of a physical name");
            const std::string_view tag_token = in_.next_token();
            const int64_t tag = in_.to_int(tag_token, "a physical tag");
            in_.skip_blanks();
            const size_t name_at = in_.pos();
            std::string_view name = in_.rest_of_line();
            while (!name.empty() && (name.back() == ' ' || name.back() == '\t')) name.remove_suffix(1);
            if (name.size() < 2 || name.front() != '"' || name.back() != '"')
                in_.fail_line(name_at, "expected a quoted name after physical tag " + std::to_string(tag));
            name = name.substr(1, name.size() - 2);
            if (dim == 3 && tag >= std::numeric_limits<int32_t>::min() && tag <= std::numeric_limits<int32_t>::max())
                volume_names_[static_cast<int32_t>(tag)] = std::string(name);
            if (dim != 2) continue;
            if (tag < std::numeric_limits<int32_t>::min() || tag > std::numeric_limits<int32_t>::max())
                in_.fail_line(in_.offset_of(tag_token), "physical tag " + std::to_string(tag) + " is out of range");
            physical_names_[static_cast<int32_t>(tag)] = std::string(name);
        }
    }

    // ---- values: ASCII tokens or binary of the file's byte order ----
    int64_t read_int(const Label& what) {  // int in binary
        if (!binary_) return in_.any_int(what);
        return in_.read_binary<int32_t>(big_endian_, what);
    }
    int64_t read_size(const Label& what) {  // size_t in binary (4.1)
        if (!binary_) return in_.any_int(what);
        const size_t at = in_.pos();
        const uint64_t v = in_.read_binary<uint64_t>(big_endian_, what);
        if (v > static_cast<uint64_t>(std::numeric_limits<int64_t>::max())) fail_at(at, what.str() + " is out of range");
        return static_cast<int64_t>(v);
    }
    double read_double(const Label& what) {
        if (!binary_) return in_.any_double(what);
        const size_t at = in_.pos();
        const double v = in_.read_binary<double>(big_endian_, what);
        if (!std::isfinite(v)) in_.fail_offset(at, what.str() + " is " + (std::isnan(v) ? "NaN" : "infinite"));
        return v;
    }
    size_t value_pos() {
        if (!binary_) in_.skip_space();
        return in_.pos();
    }
    void check(int64_t count, double ascii_bytes, double binary_bytes, const std::string& what, size_t at) {
        check_count(in_, at, binary_, count, binary_ ? binary_bytes : ascii_bytes, what);
    }

    void add_node(int64_t tag, size_t at, const Vec3& p) {
        if (tag < 0) fail_at(at, "negative node tag " + std::to_string(tag));
        nodes_.add(tag, at);
        vertices_.push_back(p);
    }

    // ---- 2.2 ----
    void read_nodes2() {
        const size_t at = value_pos();
        const int64_t n = in_.any_int("the number of nodes");  // ASCII even in binary files
        if (binary_) in_.skip_line();
        check(n, 8, 28, "nodes", at);
        vertices_.reserve(static_cast<size_t>(n));
        for (int64_t i = 0; i < n; ++i) {
            const size_t node_at = value_pos();
            const int64_t tag = read_int(Label("node ", i, ": its tag"));
            Vec3 p;
            for (int k = 0; k < 3; ++k) p[k] = read_double(Label("node ", i, ": a coordinate"));
            add_node(tag, node_at, p);
        }
    }

    void read_elements2() {
        const size_t at = value_pos();
        const int64_t n = in_.any_int("the number of elements");
        if (binary_) in_.skip_line();
        check(n, 8, 12, "elements", at);
        int64_t done = 0;
        if (!binary_) {
            for (; done < n; ++done) {
                const size_t element_at = value_pos();
                (void)in_.any_int(Label("element ", done, ": its tag"));
                const int64_t type = in_.line_int(Label("element ", done, ": its type"));
                const int64_t ntags = in_.line_int(Label("element ", done, ": its number of tags"));
                if (ntags < 0 || ntags > 1000) fail_at(element_at, "element " + std::to_string(done) + ": implausible number of tags " + std::to_string(ntags));
                if (type != 2) {
                    ++skipped_;
                    in_.skip_line();
                    continue;
                }
                int64_t physical = 0;
                for (int64_t k = 0; k < ntags; ++k) {
                    const int64_t tag = in_.line_int(Label("element ", done, ": a tag"));
                    if (k == 0) physical = tag;
                }
                std::array<int64_t, 3> corner{};
                for (int k = 0; k < 3; ++k) corner[k] = in_.line_int(Label("element ", done, ": a node tag"));
                add_triangle(corner, element_at, physical, {});
                in_.expect_line_end("after the 3 nodes of a triangle");
            }
            return;
        }
        while (done < n) {
            const size_t block_at = in_.pos();
            const int64_t type = read_int("an element block header");
            const int64_t count = read_int("an element block header");
            const int64_t ntags = read_int("an element block header");
            const int nodes = nodes_of_element_type(type);
            if (nodes == 0) fail_at(block_at, "unknown element type " + std::to_string(type) + " (cannot be skipped in a binary file)");
            if (count <= 0 || count > n - done) {
                fail_at(block_at, "element block of " + std::to_string(count) + " elements, but " +
                                      std::to_string(n - done) + " of the announced elements are left");
            }
            if (ntags < 0 || ntags > 1000) fail_at(block_at, "implausible number of tags " + std::to_string(ntags));
            const size_t record = 4 * static_cast<size_t>(1 + ntags + nodes);
            check(count, 0, static_cast<double>(record), "elements in this block", block_at);
            if (type != 2) {
                in_.seek(in_.pos() + record * static_cast<size_t>(count));
                skipped_ += count;
                done += count;
                continue;
            }
            for (int64_t i = 0; i < count; ++i, ++done) {
                const size_t element_at = in_.pos();
                const Label what("element ", done);
                (void)read_int(what);
                int64_t physical = 0;
                for (int64_t k = 0; k < ntags; ++k) {
                    const int64_t tag = read_int(what);
                    if (k == 0) physical = tag;
                }
                std::array<int64_t, 3> corner{};
                for (int k = 0; k < 3; ++k) corner[k] = read_int(what);
                add_triangle(corner, element_at, physical, {});
            }
        }
    }

    // ---- 4.1 ----
    void read_entities() {
        if (binary_) in_.skip_line();
        const size_t at = value_pos();
        int64_t count[4];
        for (int d = 0; d < 4; ++d) count[d] = read_size("the number of entities");
        for (int d = 0; d < 4; ++d) {
            check(count[d], d == 0 ? 10 : 20, d == 0 ? 36 : 68, "entities of dimension " + std::to_string(d), at);
            for (int64_t i = 0; i < count[d]; ++i) {
                const std::string what = "entity " + std::to_string(i) + " of dimension " + std::to_string(d);
                const int64_t tag = read_int(what + ": its tag");
                for (int k = 0; k < (d == 0 ? 3 : 6); ++k) (void)read_double(what + ": its bounding box");
                const size_t physicals_at = value_pos();
                const int64_t physicals = read_size(what + ": its number of physical tags");
                check(physicals, 2, 4, "physical tags", physicals_at);
                int64_t first = 0;
                for (int64_t k = 0; k < physicals; ++k) {
                    const int64_t p = read_int(what + ": a physical tag");
                    if (k == 0) first = p;
                }
                if (physicals > 0) {
                    if (first < std::numeric_limits<int32_t>::min() || first > std::numeric_limits<int32_t>::max()) {
                        fail_at(physicals_at, what + ": physical tag " + std::to_string(first) + " does not fit in 32 bits");
                    }
                    entity_physical_[{d, tag}] = static_cast<int32_t>(first);
                }
                if (d > 0) {
                    const size_t bounding_at = value_pos();
                    const int64_t bounding = read_size(what + ": its number of bounding entities");
                    check(bounding, 2, 4, "bounding entities", bounding_at);
                    for (int64_t k = 0; k < bounding; ++k) {
                        const int64_t b = read_int(what + ": a bounding entity");
                        // A volume's bounding surfaces, by their unsigned tags (see the top).
                        if (d == 3) surface_volumes_[b < 0 ? -b : b].push_back(tag);
                    }
                }
            }
        }
    }

    void read_nodes4() {
        if (binary_) in_.skip_line();
        const size_t at = value_pos();
        const int64_t blocks = read_size("the number of node blocks");
        const int64_t n = read_size("the number of nodes");
        (void)read_size("the smallest node tag");
        (void)read_size("the largest node tag");
        check(n, 8, 32, "nodes", at);
        check(blocks, 8, 20, "node blocks", at);
        vertices_.reserve(static_cast<size_t>(n));
        int64_t done = 0;
        std::vector<int64_t> tags;
        std::vector<size_t> tag_offsets;
        for (int64_t b = 0; b < blocks; ++b) {
            const size_t block_at = value_pos();
            const std::string what = "node block " + std::to_string(b);
            const int64_t dim = read_int(what + ": the entity dimension");
            (void)read_int(what + ": the entity tag");
            const int64_t parametric = read_int(what + ": the parametric flag");
            const int64_t count = read_size(what + ": its number of nodes");
            if (dim < 0 || dim > 3) fail_at(block_at, what + ": entity dimension " + std::to_string(dim) + " is not 0..3");
            if (parametric != 0 && parametric != 1) fail_at(block_at, what + ": parametric flag is not 0 or 1");
            if (count < 0 || count > n - done) {
                fail_at(block_at, what + " holds " + std::to_string(count) + " nodes, but only " +
                                      std::to_string(n - done) + " of the announced nodes are left");
            }
            const int extra = parametric ? static_cast<int>(dim) : 0;
            tags.clear();
            tag_offsets.clear();
            for (int64_t i = 0; i < count; ++i) {
                tag_offsets.push_back(value_pos());
                tags.push_back(read_size(Label("the tag of node ", done + i)));
            }
            for (int64_t i = 0; i < count; ++i) {
                Vec3 p;
                for (int k = 0; k < 3; ++k) p[k] = read_double(Label("node ", done + i, ": a coordinate"));
                for (int k = 0; k < extra; ++k) (void)read_double(Label("node ", done + i, ": a parametric coordinate"));
                add_node(tags[static_cast<size_t>(i)], tag_offsets[static_cast<size_t>(i)], p);
            }
            done += count;
        }
        if (done != n) fail_at(value_pos(), "the node blocks hold " + std::to_string(done) + " nodes, not the announced " + std::to_string(n));
    }

    void read_elements4() {
        if (binary_) in_.skip_line();
        const size_t at = value_pos();
        const int64_t blocks = read_size("the number of element blocks");
        const int64_t n = read_size("the number of elements");
        (void)read_size("the smallest element tag");
        (void)read_size("the largest element tag");
        check(n, 4, 16, "elements", at);
        check(blocks, 8, 20, "element blocks", at);
        int64_t done = 0;
        for (int64_t b = 0; b < blocks; ++b) {
            const size_t block_at = value_pos();
            const std::string what = "element block " + std::to_string(b);
            const int64_t dim = read_int(what + ": the entity dimension");
            const int64_t entity = read_int(what + ": the entity tag");
            const int64_t type = read_int(what + ": the element type");
            const int64_t count = read_size(what + ": its number of elements");
            if (count < 0 || count > n - done) {
                fail_at(block_at, what + " holds " + std::to_string(count) + " elements, but only " +
                                      std::to_string(n - done) + " of the announced elements are left");
            }
            const int nodes = nodes_of_element_type(type);
            if (type != 2) {
                if (nodes == 0 && binary_) {
                    fail_at(block_at, what + ": unknown element type " + std::to_string(type) +
                                          " (cannot be skipped in a binary file)");
                }
                if (binary_) {
                    const size_t record = 8 * static_cast<size_t>(1 + nodes);
                    check(count, 0, static_cast<double>(record), "elements in this block", block_at);
                    in_.seek(in_.pos() + record * static_cast<size_t>(count));
                } else {
                    in_.skip_line();
                    for (int64_t i = 0; i < count; ++i) {
                        if (in_.at_end()) fail_at(in_.pos(), "the file ends inside " + what);
                        in_.skip_line();
                    }
                }
                skipped_ += count;
                done += count;
                continue;
            }
            check(count, 8, 32, "triangles", block_at);
            for (int64_t i = 0; i < count; ++i, ++done) {
                const size_t element_at = value_pos();
                (void)read_size(Label("element ", done, ": its tag"));
                std::array<int64_t, 3> corner{};
                for (int k = 0; k < 3; ++k) corner[k] = read_size(Label("element ", done, ": a node tag"));
                add_triangle(corner, element_at, 0, {static_cast<int>(dim), static_cast<int>(entity)});
                if (!binary_) in_.expect_line_end("after the 3 nodes of a triangle");
            }
        }
        if (done != n) fail_at(value_pos(), "the element blocks hold " + std::to_string(done) + " elements, not the announced " + std::to_string(n));
    }

    void add_triangle(const std::array<int64_t, 3>& corner, size_t at, int64_t physical, std::pair<int, int> entity) {
        if (physical < std::numeric_limits<int32_t>::min() || physical > std::numeric_limits<int32_t>::max()) {
            fail_at(at, "physical tag " + std::to_string(physical) + " does not fit in 32 bits");
        }
        if (raw_triangles_.size() >= static_cast<size_t>(std::numeric_limits<int32_t>::max())) {
            fail_at(at, "too many triangles for bpm (at most 2^31-1)");
        }
        raw_triangles_.push_back(corner);
        triangle_offsets_.push_back(at);
        patches_.push_back(static_cast<int32_t>(physical));
        entities_.push_back(entity);
    }

    ReaderOutput finish() {
        ReaderOutput out;
        Surface& s = out.surface;
        nodes_.build(in_, binary_);
        s.vertices = std::move(vertices_);
        s.triangles.reserve(raw_triangles_.size());
        for (size_t t = 0; t < raw_triangles_.size(); ++t) {
            Tri tri;
            for (int k = 0; k < 3; ++k) {
                const int32_t index = nodes_.find(raw_triangles_[t][k]);
                if (index < 0) {
                    fail_at(triangle_offsets_[t], "triangle " + std::to_string(t) + ": node tag " +
                                                      std::to_string(raw_triangles_[t][k]) + " is not in $Nodes");
                }
                tri[k] = index;
            }
            s.triangles.push_back(tri);
        }
        s.patches = std::move(patches_);
        if (version4_) {
            for (size_t t = 0; t < s.patches.size(); ++t) {
                const auto it = entity_physical_.find(entities_[t]);
                s.patches[t] = it == entity_physical_.end() ? 0 : it->second;
            }
        }
        if (patch_offset_ != 0) {
            for (size_t t = 0; t < s.patches.size(); ++t) {
                if (s.patches[t] < patch_offset_)
                    in_.fail("triangle " + std::to_string(t) + " has physical tag " + std::to_string(s.patches[t]) +
                             ", below the tag of patch 0 (" + std::to_string(patch_offset_) + ") that $BpmPatchIds gives");
                s.patches[t] -= patch_offset_;
            }
        }
        for (const auto& [tag, name] : physical_names_) {
            if (tag < patch_offset_) continue;  // not a patch of this file
            PatchInfo info{tag - patch_offset_, name, {}, {}, true};
            if (const auto pair = materials_from_patch_name(name)) {
                info.front = pair->first;
                info.back = pair->second;
                info.oriented = false;  // a name does not say which side is which
            }
            out.patch_info.push_back(std::move(info));
        }
        materials_from_volumes(s, out);
        out.skipped_elements = skipped_;
        if (skipped_ > 0) {
            out.notes.push_back("skipped " + std::to_string(skipped_) + " MSH element" + (skipped_ == 1 ? "" : "s") +
                                " that are not 3-node triangles");
        }
        return out;
    }

    // The physical volumes on the two sides of each patch (see the top), into
    // out.patch_info; a note when there are physical volumes and they give nothing.
    void materials_from_volumes(const Surface& s, ReaderOutput& out) const {
        if (volume_names_.empty() && surface_volumes_.empty()) return;
        std::string names;
        for (const auto& [tag, name] : volume_names_) names += (names.empty() ? "'" : ", '") + name + "'";
        if (!version4_) {
            if (!names.empty())
                out.notes.push_back("physical volumes " + names + " ignored: MSH 2.2 does not say which surfaces bound "
                                    "a volume (write MSH 4.1, gmsh -format msh41, or name the physical surfaces 'A|B' "
                                    "after the materials on their two sides)");
            return;
        }
        using Pair = std::pair<std::string, std::string>;
        const auto volume_material = [&](int64_t volume) -> std::optional<std::string> {
            const auto physical = entity_physical_.find({3, static_cast<int>(volume)});
            if (physical == entity_physical_.end()) return std::nullopt;
            const auto named = volume_names_.find(physical->second);
            return named != volume_names_.end() ? named->second : "volume_" + std::to_string(physical->second);
        };
        // Per patch: the pair all its surface entities give; nullopt once one gives none or another.
        std::map<int32_t, std::optional<Pair>> by_patch;
        std::set<std::pair<int32_t, int>> seen;  // (patch, surface entity)
        for (size_t t = 0; t < s.patches.size() && t < entities_.size(); ++t) {
            if (entities_[t].first != 2 || !seen.insert({s.patches[t], entities_[t].second}).second) continue;
            std::optional<Pair> pair;
            const auto volumes = surface_volumes_.find(entities_[t].second);
            if (volumes != surface_volumes_.end() && (volumes->second.size() == 1 || volumes->second.size() == 2)) {
                const auto a = volume_material(volumes->second[0]);
                const auto b = volumes->second.size() == 2 ? volume_material(volumes->second[1])
                                                           : std::optional<std::string>(kExteriorMaterial);
                if (a && b && *a != *b) pair = std::minmax(*a, *b);
            }
            const auto [it, fresh] = by_patch.emplace(s.patches[t], pair);
            if (!fresh && it->second != pair) it->second = std::nullopt;
        }
        int64_t given = 0;
        std::string unnamed;
        for (const auto& [patch, pair] : by_patch) {
            PatchInfo* info = find_patch_info(out.patch_info, patch);
            if (info && info->has_materials()) continue;  // its name says them
            if (!pair) {
                unnamed += (unnamed.empty() ? "" : ", ") + std::to_string(patch + patch_offset_);
                continue;
            }
            if (!info) {
                out.patch_info.push_back(PatchInfo{patch, "", {}, {}, true});
                info = &out.patch_info.back();
            }
            info->front = pair->first;
            info->back = pair->second;
            info->oriented = false;
            ++given;
        }
        std::sort(out.patch_info.begin(), out.patch_info.end(),
                  [](const PatchInfo& a, const PatchInfo& b) { return a.patch < b.patch; });
        if (given == 0 && !names.empty())
            out.notes.push_back("physical volumes " + names + " ignored: no physical surface lies between the same "
                                "physical volumes everywhere (its surfaces are not listed as bounding a volume, or "
                                "bound different ones); name the physical surfaces 'A|B' after the materials on "
                                "their two sides");
        else if (!unnamed.empty() && given > 0)
            out.notes.push_back("physical surfaces " + unnamed + ": no materials from the physical volumes (parts of "
                                "them bound different volumes, or none with a physical group)");
    }

    InputCursor in_;
    bool version4_ = false;
    bool binary_ = false;
    bool big_endian_ = false;
    bool have_nodes_ = false;
    bool have_elements_ = false;
    NodeIndex nodes_;
    std::vector<Vec3> vertices_;
    std::vector<std::array<int64_t, 3>> raw_triangles_;
    std::vector<size_t> triangle_offsets_;
    std::vector<int32_t> patches_;
    std::vector<std::pair<int, int>> entities_;
    std::map<std::pair<int, int>, int32_t> entity_physical_;
    std::map<int32_t, std::string> physical_names_;  // dimension 2 only
    std::map<int32_t, std::string> volume_names_;    // dimension 3: physical tag -> name
    std::map<int64_t, std::vector<int64_t>> surface_volumes_;  // 4.1: surface entity -> volume entities it bounds
    int32_t patch_offset_ = 0;                       // $BpmPatchIds: physical tag of patch 0
    int64_t skipped_ = 0;
};

}  // namespace

ReaderOutput read_msh(std::string_view bytes, const std::string& name) { return MshReader(bytes, name).read(); }

}  // namespace bpm::detail
