// bpm-bench-write: the cost of bpm's mesh output encodings (bpm/mesh_encoding.h) on one
// surface: writes it as MSH 4.1 (ASCII, binary), MSH 2.2 and VTU (ASCII, binary, zlib),
// the formats taking turns for --repeat rounds, and prints a Markdown table of the file
// size and the median CPU seconds (process CPU time, so other load on the machine counts
// less than in wall time) of one write. Usage:
//   bpm-bench-write SURFACE DIR [--repeat 3]
// SURFACE is any surface bpm reads (e.g. a level-6 refinement written with bpm-refine
// --binary); the files go to DIR and are removed.
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bpm/surface_io.h"
#include "bpm/write_vtu.h"

namespace {

double cpu_seconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

struct Case {
    const char* name;
    const char* file;
    bool vtu;
    bpm::SurfaceFormat format;
    bpm::MeshEncoding encoding;
    std::vector<double> seconds;
    uintmax_t bytes = 0;
};

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Size and CPU seconds of writing one surface in bpm's MSH and VTU encodings"};
    std::string input, dir;
    int repeat = 3;
    app.add_option("SURFACE", input, "Surface to write (any format bpm reads)")->required();
    app.add_option("DIR", dir, "Directory for the files (removed after)")->required();
    app.add_option("--repeat", repeat, "Rounds; the median is reported (default 3)")->check(CLI::Range(1, 100));
    CLI11_PARSE(app, argc, argv);

    bpm::SurfaceReadOptions options;
    options.drop_unreferenced_vertices = true;
    const bpm::Surface s = bpm::read_surface(input, options);
    using E = bpm::MeshEncoding;
    using F = bpm::SurfaceFormat;
    std::vector<Case> cases = {
        {"VTU ASCII", "a.vtu", true, F::Vtu, E::Ascii, {}},
        {"VTU --binary", "b.vtu", true, F::Vtu, E::Binary, {}},
        {"VTU --compress (zlib)", "z.vtu", true, F::Vtu, E::BinaryZlib, {}},
        {"MSH 4.1 ASCII", "a.msh", false, F::Msh, E::Ascii, {}},
        {"MSH 4.1 --binary", "b.msh", false, F::Msh, E::Binary, {}},
        {"MSH 2.2 (msh22)", "c.msh", false, F::Msh22, E::Ascii, {}},
    };
    std::filesystem::create_directories(dir);
    for (int round = 0; round < repeat; ++round) {
        for (Case& c : cases) {
            const std::string path = dir + "/" + c.file;
            const double t0 = cpu_seconds();
            if (c.vtu)
                bpm::write_surface_vtu(path, s, {}, {}, c.encoding);
            else
                bpm::write_surface(path, s, c.format, c.encoding);
            c.seconds.push_back(cpu_seconds() - t0);
            c.bytes = std::filesystem::file_size(path);
            std::filesystem::remove(path);
        }
    }
    std::printf("%lld vertices, %lld triangles; median of %d writes, formats alternated\n\n",
                (long long)s.num_vertices(), (long long)s.num_triangles(), repeat);
    std::printf("| output | size (MB) | write CPU s | size vs ASCII | CPU vs ASCII |\n|---|---:|---:|---:|---:|\n");
    double ascii_seconds = 0, ascii_bytes = 0;
    for (Case& c : cases) {
        std::sort(c.seconds.begin(), c.seconds.end());
        const double median = c.seconds[c.seconds.size() / 2];
        if (c.encoding == E::Ascii && c.format != F::Msh22) ascii_seconds = median, ascii_bytes = double(c.bytes);
        std::printf("| %s | %.1f | %.2f | %.2f | %.2f |\n", c.name, double(c.bytes) / 1e6, median,
                    double(c.bytes) / ascii_bytes, median / ascii_seconds);
    }
    return 0;
}
