// The simplifier against the checker's oracle: every output must be a valid
// parametrization (format, bijectivity, topology, no intersections).
#include <catch2/catch.hpp>

#include <filesystem>

#include "bpm/check.h"
#include "bpm/simplify.h"
#include "bpm/surface_io.h"
#include "fixtures_surfaces.h"

using namespace bpm;

namespace {

void require_valid(const Parametrization& p, const std::string& label) {
    INFO(label);
    CheckOptions options;
    const CheckResult format = check_format(p, options);
    INFO(check_report_to_text(CheckReport{label, {format}}));
    REQUIRE(format.passed);
    const CheckResult bijective = check_bijectivity(p, options);
    INFO(check_report_to_text(CheckReport{label, {bijective}}));
    CHECK(bijective.passed);
    const CheckResult topology = check_topology(p, options);
    INFO(check_report_to_text(CheckReport{label, {topology}}));
    CHECK(topology.passed);
    const CheckResult intersections = check_intersections(p.coarse, options);
    INFO(check_report_to_text(CheckReport{label, {intersections}}));
    CHECK(intersections.passed);
}

Parametrization run(const Surface& s, SimplifyOptions options, SimplifyResult* out_result = nullptr) {
    Parametrization p;
    const SimplifyResult r = simplify(s, options, Context{}, p);
    if (out_result) *out_result = r;
    return p;
}

}  // namespace

TEST_CASE("simplify keeps a valid parametrization on synthetic surfaces", "[simplify]") {
    struct Case {
        std::string name;
        Surface surface;
    };
    std::vector<Case> cases = {
        {"torus", fixtures::torus(24, 16)},
        {"double torus", fixtures::double_torus(4)},
        {"disk", fixtures::disk(12)},
        {"cube", fixtures::cube(6)},
        {"two cubes", fixtures::two_cubes(5)},
        {"cylinder wedges", fixtures::cylinder_wedges(24, 6)},
        {"octants", fixtures::octants(4)},
        {"hourglass", fixtures::hourglass(24)},
    };
    for (auto& c : cases) {
        INFO("fixture: " << c.name);
        SimplifyOptions options;
        options.target_ratio = 0.1;
        options.self_check = true;
        SimplifyResult result;
        const Parametrization p = run(c.surface, options, &result);
        INFO(c.name << ": " << result.input_vertices << " -> " << result.output_vertices);
        require_valid(p, c.name);
    }
}

TEST_CASE("simplify keeps a valid parametrization on real meshes", "[simplify][real]") {
    const std::string dir = BPM_MESH_DIR;
    for (const std::string name : {"femur", "fandisk", "elephant", "mech-holes-shark"}) {
        const std::string path = dir + "/" + name + ".off";
        if (!std::filesystem::exists(path)) {
            WARN("missing " << path);
            continue;
        }
        const Surface s = read_surface(path);
        SimplifyOptions options;
        options.target_ratio = 0.1;
        SimplifyResult result;
        const Parametrization p = run(s, options, &result);
        INFO(name << ": " << result.input_vertices << " -> " << result.output_vertices << " error " << result.max_error);
        require_valid(p, name);
    }
}
