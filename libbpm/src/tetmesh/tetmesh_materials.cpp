// Materials of the regions of a tetrahedral mesh (bpm/tetmesh_materials.h).
#include "bpm/tetmesh_materials.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <optional>
#include <set>

#include "bpm/errors.h"

namespace bpm {

namespace {

std::string num(int64_t v) { return std::to_string(v); }

// The regions on the front and back of every face on S (0 = the unmeshed outside).
struct Sides {
    int32_t front = 0, back = 0;
};

bool same_cycle(const Tri& a, const Tri& b) {
    for (int r = 0; r < 3; ++r)
        if (a[0] == b[r] && a[1] == b[(r + 1) % 3] && a[2] == b[(r + 2) % 3]) return true;
    return false;
}

std::vector<Sides> face_sides(const TetMesh& m) {
    using Key = std::array<int32_t, 3>;
    std::vector<std::pair<Key, int32_t>> keys(m.faces.size());
    for (size_t f = 0; f < m.faces.size(); ++f) {
        Key k{m.faces[f][0], m.faces[f][1], m.faces[f][2]};
        std::sort(k.begin(), k.end());
        keys[f] = {k, static_cast<int32_t>(f)};
    }
    std::sort(keys.begin(), keys.end());
    // Face opposite corner i of a positively oriented tetrahedron, oriented so that the
    // tetrahedron is on its front: for (0,0,0), e1, e2, e3 the face (0,1,2) has e3 in
    // front (normal e1 x e2).
    static const int kFront[4][3] = {{1, 3, 2}, {0, 2, 3}, {0, 3, 1}, {0, 1, 2}};
    std::vector<Sides> sides(m.faces.size());
    for (size_t t = 0; t < m.tetrahedra.size(); ++t) {
        const Tet& x = m.tetrahedra[t];
        for (const auto& c : kFront) {
            const Tri tri{x[c[0]], x[c[1]], x[c[2]]};
            Key k{tri[0], tri[1], tri[2]};
            std::sort(k.begin(), k.end());
            const auto it = std::lower_bound(keys.begin(), keys.end(), std::make_pair(k, int32_t(-1)));
            if (it == keys.end() || it->first != k) continue;
            Sides& s = sides[size_t(it->second)];
            (same_cycle(tri, m.faces[size_t(it->second)]) ? s.front : s.back) = m.regions[t];
        }
    }
    return sides;
}

bool is_exterior(const std::string& name) {
    const std::string e = kExteriorMaterial;
    if (name.size() != e.size()) return false;
    for (size_t i = 0; i < e.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(name[i])) != e[i]) return false;
    return true;
}

// One patch side pair between two regions: what its PatchInfo says (name indices).
struct Constraint {
    int32_t front = 0, back = 0;  // regions
    int a = 0, b = 0;             // front, back materials (or the unordered pair)
    bool oriented = true;
};

struct Resolution {
    std::vector<std::optional<std::set<int>>> allowed;  // per region 0..R; nullopt = unconstrained
    std::vector<std::set<int>> named;                   // every material a side of the region names
    int64_t conflicts = 0;                              // regions 0..R whose constraints leave nothing
};

Resolution resolve(const std::vector<Constraint>& constraints, int32_t nr, const std::vector<std::string>& names,
                   bool all_unordered) {
    Resolution res;
    res.allowed.resize(size_t(nr) + 1);
    res.named.resize(size_t(nr) + 1);
    auto constrain = [&](int32_t r, const std::set<int>& allowed) {
        auto& a = res.allowed[size_t(r)];
        if (!a) {
            a = allowed;
            return true;
        }
        std::set<int> both;
        std::set_intersection(a->begin(), a->end(), allowed.begin(), allowed.end(), std::inserter(both, both.end()));
        if (both == *a) return false;
        a = std::move(both);
        return true;
    };
    int exterior = -1;
    for (size_t i = 0; i < names.size(); ++i)
        if (is_exterior(names[i])) exterior = static_cast<int>(i);
    // "exterior" on a side of a meshed region (not the unmeshed outside, region 0) says
    // only "outside this file" (the file-per-material convention: every file's outer side
    // is exterior, apply_file_material): a file nested in another has the enclosing
    // file's material there. So it names a region only when nothing else does.
    std::vector<int32_t> weakly_exterior;
    for (const Constraint& c : constraints) {
        if (c.oriented && !all_unordered) {
            for (const auto& [r, m] : {std::pair{c.front, c.a}, std::pair{c.back, c.b}}) {
                res.named[size_t(r)].insert(m);
                if (m == exterior && r != 0) weakly_exterior.push_back(r);
                else constrain(r, {m});
            }
        } else {
            constrain(c.front, {c.a, c.b});
            constrain(c.back, {c.a, c.b});
            for (int32_t r : {c.front, c.back}) res.named[size_t(r)].insert({c.a, c.b});
        }
    }
    for (int32_t r : weakly_exterior)
        if (!res.allowed[size_t(r)]) constrain(r, {exterior});
    for (bool changed = true; changed;) {
        changed = false;
        for (const Constraint& c : constraints) {
            if ((c.oriented && !all_unordered) || c.a == c.b) continue;
            // The two sides of an unordered pair hold different materials.
            for (const auto& [from, to] : {std::pair{c.front, c.back}, std::pair{c.back, c.front}}) {
                const auto& known = res.allowed[size_t(from)];
                if (!known || known->size() != 1) continue;
                const int x = *known->begin();
                if (x == c.a) changed = constrain(to, {c.b}) || changed;
                else if (x == c.b) changed = constrain(to, {c.a}) || changed;
            }
        }
        auto& outside = res.allowed[0];
        if (!changed && exterior >= 0 && outside && outside->size() > 1 && outside->count(exterior)) {
            outside = std::set<int>{exterior};
            changed = true;
        }
    }
    // The outside counts too: with reversed normals the weak exteriors no longer
    // contradict, but the outside is then told to be a file's material.
    for (int32_t r = 0; r <= nr; ++r)
        if (res.allowed[size_t(r)] && res.allowed[size_t(r)]->empty()) ++res.conflicts;
    return res;
}

std::string list(const std::set<int>& ids, const std::vector<std::string>& names) {
    std::string out;
    size_t i = 0;
    for (int id : ids) out += (i++ == 0 ? "" : i == ids.size() ? " and " : ", ") + names[size_t(id)];
    return out;
}

}  // namespace

MaterialResult assign_materials(TetMesh& mesh, const std::vector<PatchInfo>& patch_info, const MaterialOptions& options) {
    const int32_t nr = mesh.num_regions();
    for (const auto& [r, name] : options.region_names) {
        if (r < 1 || r > nr)
            throw OptionError("material for region " + num(r) + ": the mesh has regions 1 to " + num(nr));
        if (name.empty() || name.find('\0') != std::string::npos)
            throw OptionError("material for region " + num(r) + ": the name must be non-empty text");
    }
    // The distinct (front region, back region, patch) triples, and the names they use.
    std::vector<std::string> names;
    auto name_id = [&](const std::string& n) {
        const auto it = std::find(names.begin(), names.end(), n);
        if (it != names.end()) return static_cast<int>(it - names.begin());
        names.push_back(n);
        return static_cast<int>(names.size() - 1);
    };
    std::vector<Constraint> constraints;
    {
        const std::vector<Sides> sides = face_sides(mesh);
        std::map<int32_t, const PatchInfo*> by_patch;
        for (const PatchInfo& i : patch_info)
            if (!i.front.empty() || !i.back.empty()) by_patch.emplace(i.patch, &i);
        std::set<std::array<int32_t, 3>> seen;
        for (size_t f = 0; f < mesh.faces.size(); ++f) {
            const auto found = by_patch.find(mesh.face_patches[f]);
            if (found == by_patch.end()) continue;
            const PatchInfo* info = found->second;
            if (!seen.insert({sides[f].front, sides[f].back, mesh.face_patches[f]}).second) continue;
            if (info->oriented && (info->front.empty() || info->back.empty())) {
                // One side known: constrain that side only (a pair with itself never conflicts).
                if (!info->front.empty()) {
                    const int a = name_id(info->front);
                    constraints.push_back({sides[f].front, sides[f].front, a, a, true});
                } else {
                    const int b = name_id(info->back);
                    constraints.push_back({sides[f].back, sides[f].back, b, b, true});
                }
                continue;
            }
            constraints.push_back({sides[f].front, sides[f].back, name_id(info->front), name_id(info->back),
                                   info->oriented});
        }
    }
    MaterialResult result;
    Resolution res = resolve(constraints, nr, names, false);
    if (res.conflicts > 0) {
        Resolution unordered = resolve(constraints, nr, names, true);
        if (unordered.conflicts < res.conflicts) {
            res = std::move(unordered);
            result.orientation_ignored = true;
        }
    }
    std::vector<std::string> region_name(size_t(nr) + 1);
    for (int32_t r = 1; r <= nr; ++r) {
        const std::string fallback = "region_" + num(r);
        const auto& allowed = res.allowed[size_t(r)];
        if (const auto user = options.region_names.find(r); user != options.region_names.end()) {
            region_name[size_t(r)] = user->second;
            ++result.regions_from_user;
        } else if (allowed && allowed->size() == 1) {
            region_name[size_t(r)] = names[size_t(*allowed->begin())];
            ++result.regions_from_input;
        } else {
            region_name[size_t(r)] = fallback;
            if (!constraints.empty()) {
                if (!allowed)
                    result.problems.push_back("region " + num(r) + ": no patch with materials bounds it; named " + fallback);
                else if (allowed->empty())
                    result.problems.push_back("region " + num(r) + ": its sides say " + list(res.named[size_t(r)], names) +
                                              " (conflict); named " + fallback);
                else
                    result.problems.push_back("region " + num(r) + ": either " + list(*allowed, names) +
                                              " (ambiguous); named " + fallback);
            }
        }
    }
    mesh.material_names.clear();
    mesh.region_material.assign(size_t(nr), 0);
    for (int32_t r = 1; r <= nr; ++r) {
        const std::string& n = region_name[size_t(r)];
        auto it = std::find(mesh.material_names.begin(), mesh.material_names.end(), n);
        if (it == mesh.material_names.end()) it = mesh.material_names.insert(mesh.material_names.end(), n);
        mesh.region_material[size_t(r - 1)] = static_cast<int32_t>(it - mesh.material_names.begin()) + 1;
    }
    result.materials = static_cast<int64_t>(mesh.material_names.size());
    return result;
}

int64_t name_patches_after_regions(const TetMesh& mesh, std::vector<PatchInfo>& patch_info) {
    if (mesh.region_material.empty() || find_material_inconsistency(mesh) != "") return 0;
    // Per patch: the material on the front and on the back of its faces (0 = the unmeshed
    // outside), -1 where its faces disagree.
    const std::vector<Sides> sides = face_sides(mesh);
    const auto material = [&](int32_t region) {
        return region >= 1 && region <= int32_t(mesh.region_material.size()) ? mesh.region_material[size_t(region - 1)] : 0;
    };
    std::map<int32_t, std::pair<int32_t, int32_t>> by_patch;
    for (size_t f = 0; f < mesh.faces.size() && f < mesh.face_patches.size(); ++f) {
        const std::pair<int32_t, int32_t> m{material(sides[f].front), material(sides[f].back)};
        const auto [it, fresh] = by_patch.emplace(mesh.face_patches[f], m);
        if (fresh) continue;
        if (it->second.first != m.first) it->second.first = -1;
        if (it->second.second != m.second) it->second.second = -1;
    }
    int64_t changed = 0;
    for (PatchInfo& info : patch_info) {
        const auto found = by_patch.find(info.patch);
        if (!info.oriented || found == by_patch.end()) continue;
        const std::string generated = info.back + "|" + info.front;
        bool now = false;
        for (auto [side, m] : {std::pair{&info.front, found->second.first}, std::pair{&info.back, found->second.second}}) {
            if (m < 1 || !is_exterior(*side)) continue;
            const std::string& there = mesh.material_names[size_t(m - 1)];
            if (is_exterior(there)) continue;
            *side = there;
            now = true;
        }
        if (!now) continue;
        ++changed;
        if (info.name == generated) info.name = info.back + "|" + info.front;
    }
    return changed;
}

std::vector<int32_t> tet_materials(const TetMesh& mesh) {
    if (mesh.region_material.empty()) return {};
    std::vector<int32_t> out(mesh.regions.size());
    for (size_t t = 0; t < out.size(); ++t) out[t] = mesh.region_material[size_t(mesh.regions[t] - 1)];
    return out;
}

std::string find_material_inconsistency(const TetMesh& mesh) {
    if (mesh.region_material.empty() && mesh.material_names.empty()) return {};
    const int64_t nr = mesh.num_regions(), nm = static_cast<int64_t>(mesh.material_names.size());
    if (static_cast<int64_t>(mesh.region_material.size()) != nr)
        return "/tetmesh/region_material: has " + num(int64_t(mesh.region_material.size())) + " entries, expected " +
               num(nr) + " (one per region id 1.." + num(nr) + ")";
    for (int64_t r = 0; r < nr; ++r) {
        const int32_t id = mesh.region_material[size_t(r)];
        if (id < 1 || id > nm)
            return "/tetmesh/region_material: entry " + num(r) + " = " + num(id) + " is out of range [1, " + num(nm) +
                   "] (entries of /tetmesh/material_names)";
    }
    std::set<std::string> seen;
    for (int64_t i = 0; i < nm; ++i) {
        const std::string& n = mesh.material_names[size_t(i)];
        if (n.empty() || n.find('\0') != std::string::npos)
            return "/tetmesh/material_names: entry " + num(i) + " is empty or holds a NUL byte";
        if (!seen.insert(n).second) return "/tetmesh/material_names: entry " + num(i) + " ('" + n + "') is repeated";
    }
    return {};
}

}  // namespace bpm
