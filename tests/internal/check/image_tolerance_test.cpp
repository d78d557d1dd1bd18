// write_bpm refuses exactly the node images bpm-check's format check fails: both hold them
// to check/image_tolerance.h, on either side of it.
#include <catch2/catch.hpp>

#include "bpm/bpm_file.h"
#include "bpm/check.h"
#include "bpm/errors.h"
#include "check/image_tolerance.h"

using namespace bpm;

TEST_CASE("writer and format check draw the image line at the same distance", "[format]") {
    Surface s;
    s.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0.5}, {0, 1, 0.25}};
    s.triangles = {{0, 1, 2}, {0, 2, 3}};
    s.patches = {3, 7};
    const double tolerance = detail::kImageToleranceRelativeToDiagonal * bounding_box_diagonal(s);
    for (const double times : {0.5, 2.0}) {
        BpmFile f;
        f.param = make_identity_parametrization(s);
        f.provenance.push_back({"test", "0", "test", ""});
        f.param.node_image[4] = node_image_from_kind(f.param, 4) + Vec3{0, times * tolerance, 0};
        const bool within = times < 1;
        INFO("image " << times << " x the tolerance from its node's point");
        CHECK(check_format(f.param).passed == within);
        if (within) CHECK_NOTHROW(write_bpm_to_memory(f));
        else CHECK_THROWS_AS(write_bpm_to_memory(f), OutputError);
    }
}
