// Patch names and materials from the input (bpm/patch_info.h).
#include "bpm/patch_info.h"

#include <algorithm>
#include <set>

namespace bpm {

namespace {

std::string trim(const std::string& s) {
    size_t b = 0, e = s.size();
    while (b < e && (s[b] == ' ' || s[b] == '\t')) ++b;
    while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\t')) --e;
    return s.substr(b, e - b);
}

void sort_by_patch(std::vector<PatchInfo>& infos) {
    std::stable_sort(infos.begin(), infos.end(), [](const PatchInfo& a, const PatchInfo& b) { return a.patch < b.patch; });
}

}  // namespace

const PatchInfo* find_patch_info(const std::vector<PatchInfo>& infos, int32_t patch) {
    for (const PatchInfo& i : infos)
        if (i.patch == patch) return &i;
    return nullptr;
}

PatchInfo* find_patch_info(std::vector<PatchInfo>& infos, int32_t patch) {
    for (PatchInfo& i : infos)
        if (i.patch == patch) return &i;
    return nullptr;
}

std::optional<std::pair<std::string, std::string>> materials_from_patch_name(const std::string& name) {
    std::string a, b;
    if (const size_t bar = name.find('|'); bar != std::string::npos) {
        if (name.find('|', bar + 1) != std::string::npos) return std::nullopt;
        a = trim(name.substr(0, bar));
        b = trim(name.substr(bar + 1));
    } else {
        std::string rest;
        for (const char* prefix : {"pair_", "interface_"})
            if (name.rfind(prefix, 0) == 0) rest = name.substr(std::string(prefix).size());
        const size_t underscore = rest.find('_');
        // Exactly one '_' left: with more, where one material ends is not known.
        if (underscore == std::string::npos || rest.find('_', underscore + 1) != std::string::npos)
            return std::nullopt;
        a = rest.substr(0, underscore);
        b = rest.substr(underscore + 1);
    }
    if (a.empty() || b.empty() || a == b) return std::nullopt;
    return std::make_pair(a, b);
}

std::string patch_info_problem(const std::vector<PatchInfo>& infos) {
    std::set<int32_t> seen;
    for (const PatchInfo& i : infos) {
        const std::string p = "patch " + std::to_string(i.patch);
        if (!seen.insert(i.patch).second) return p + " is described twice";
        if (!i.oriented && !i.has_materials())
            return p + ": an unordered pair of materials needs both materials";
        for (const std::string* s : {&i.name, &i.front, &i.back})
            if (s->find('\0') != std::string::npos) return p + ": a name holds a NUL byte";
    }
    return {};
}

void apply_file_material(std::vector<PatchInfo>& infos, const Surface& surface, const std::string& material) {
    if (material.empty() || !infos.empty()) return;
    for (int32_t p : std::set<int32_t>(surface.patches.begin(), surface.patches.end()))
        infos.push_back(PatchInfo{p, material + "|" + kExteriorMaterial, kExteriorMaterial, material, true});
}

void add_fused_patch_info(std::vector<PatchInfo>& infos, const std::vector<FusedPatch>& fused) {
    for (const FusedPatch& f : fused) {
        PatchInfo made;
        made.patch = f.patch;
        std::string others;  // the back material all other joined patches agree on; "" if not
        bool agree = true;
        for (int32_t j : f.joins) {
            const PatchInfo* info = find_patch_info(infos, j);
            made.name += (made.name.empty() ? "" : "+") + (info && !info->name.empty() ? info->name : "patch_" + std::to_string(j));
            if (j == f.kept_from) continue;
            const std::string back = info && info->oriented ? info->back : std::string();
            if (back.empty() || (!others.empty() && back != others)) agree = false;
            others = back;
        }
        const PatchInfo* kept = f.kept_from >= 0 ? find_patch_info(infos, f.kept_from) : nullptr;
        if (kept && kept->oriented && !kept->back.empty() && agree && !others.empty()) {
            made.back = kept->back;
            made.front = others;
            made.name = made.back + "|" + made.front;
        }
        if (PatchInfo* existing = find_patch_info(infos, f.patch)) *existing = made;
        else infos.push_back(made);
    }
    sort_by_patch(infos);
}

}  // namespace bpm
