// bpm-make-example (test-only): writes the fixture parametrizations of
// tests/unit/fixtures_phi.h as .bpm files, for the Python tests and the spec example.
//
//   bpm-make-example two_triangles OUTPUT          the spec example (spec/examples/two_triangles.bpm)
//   bpm-make-example octahedron LEVELS OUTPUT      subdivided bumpy octahedron
//   bpm-make-example height_field N M OUTPUT       height field with edge crossings (N % M == 0)
//   bpm-make-example identity LEVELS OUTPUT        identity phi on the subdivided octahedron
//
// OUTPUT "-" writes to stdout. Exit codes: 0 ok, 2 usage, 4 output error.

#include <cstdio>
#include <string>

#include "bpm/bpm_file.h"
#include "bpm/errors.h"
#include "fixtures_phi.h"

namespace {
int usage() {
    std::fprintf(stderr,
                 "usage: bpm-make-example two_triangles OUTPUT\n"
                 "       bpm-make-example octahedron LEVELS OUTPUT\n"
                 "       bpm-make-example height_field N M OUTPUT\n"
                 "       bpm-make-example identity LEVELS OUTPUT\n");
    return 2;
}

bpm::BpmFile wrap(bpm::Parametrization p, const std::string& args) {
    bpm::BpmFile f;
    f.param = std::move(p);
    f.units = "m";
    f.provenance.push_back({"bpm-make-example", "1", "bpm-make-example " + args, ""});
    return f;
}
}  // namespace

int main(int argc, char** argv) {
    if (argc < 3) return usage();
    const std::string kind = argv[1];
    try {
        bpm::BpmFile f;
        std::string out;
        if (kind == "two_triangles" && argc == 3) {
            f = bpm::test::make_two_triangles_example();
            out = argv[2];
        } else if (kind == "octahedron" && argc == 4) {
            f = wrap(bpm::test::make_subdivided_octahedron(std::stoi(argv[2])), kind + " " + argv[2]);
            out = argv[3];
        } else if (kind == "identity" && argc == 4) {
            f = wrap(bpm::make_identity_parametrization(bpm::test::make_subdivided_octahedron(std::stoi(argv[2])).original),
                     kind + " " + argv[2]);
            out = argv[3];
        } else if (kind == "height_field" && argc == 5) {
            f = wrap(bpm::test::make_height_field(std::stoi(argv[2]), std::stoi(argv[3]), bpm::test::default_height),
                     kind + " " + argv[2] + " " + argv[3]);
            out = argv[4];
        } else {
            return usage();
        }
        bpm::write_bpm(out, f);
    } catch (const bpm::OutputError& e) {
        std::fprintf(stderr, "bpm-make-example: error: %s: %s\n", e.where().c_str(), e.what());
        return 4;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bpm-make-example: error: %s\n", e.what());
        return 2;
    }
    return 0;
}
