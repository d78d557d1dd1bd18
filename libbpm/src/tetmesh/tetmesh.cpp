// Volume meshing of the coarse surface with TetGen (bpm/tetmesh.h).
//
// TetGen runs as an external program (Debian package `tetgen`, 1.5): the coarse surface
// goes out as a .poly file, the mesh comes back as .node/.ele. It runs twice:
//   pass 1  `-pYzA` without quality constraints: a cheap tetrahedralization of the
//           bounded part of R^3 minus S (TetGen carves away the unbounded region). Its
//           tetrahedra, flood-filled across the faces that are not on S, give the regions
//           exactly; the incentre of the fattest tetrahedron of each region is a point
//           strictly inside it.
//   pass 2  `-pYzA -q<quality> [-a<volume>] -o/<max dihedral>` with those points as region attributes.
// The regions of the final mesh are found by the same flood fill (so their ids do not
// depend on TetGen) and compared with TetGen's attributes (a difference is reported, not
// fatal: TetGen locates the seeds in floating point).
//
// Reference: H. Si, TetGen 1.5 user manual (file formats, switches -p -Y -q -a -A -z -o/).

#include "bpm/tetmesh.h"
#include "bpm/tetmesh_smooth.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <numeric>
#include <sstream>

#include "bpm/check.h"
#include "bpm/errors.h"
#include "bpm/predicates.h"
#include "bpm/surface_topology.h"
#include "core/number_text.h"
#include "core/tetrahedron_quality.h"
#include "phi/phi_layout.h"
#include "tetmesh/tet_flips.h"
#include "tetmesh/tet_insert.h"
#include "tetmesh/tet_split.h"
#include "tetmesh/tetgen_poly.h"
#include "tetmesh/tetmesh_internal.h"

namespace bpm {

int32_t TetMesh::num_regions() const {
    int32_t r = 0;
    for (int32_t x : regions) r = std::max(r, x);
    return r;
}

namespace detail {

const int kTetFaces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

FaceKey face_key(int32_t a, int32_t b, int32_t c) {
    FaceKey k{a, b, c};
    std::sort(k.begin(), k.end());
    return k;
}

ProtectedFaces::ProtectedFaces(const std::vector<Tri>& faces) {
    keys_.reserve(faces.size());
    for (const Tri& f : faces) keys_.push_back(face_key(f[0], f[1], f[2]));
    std::sort(keys_.begin(), keys_.end());
}

bool ProtectedFaces::contains(int32_t a, int32_t b, int32_t c) const {
    return std::binary_search(keys_.begin(), keys_.end(), face_key(a, b, c));
}

bool same_cyclic_orientation(const Tri& f, const std::array<int32_t, 3>& g) {
    for (int s = 0; s < 3; ++s)
        if (f[0] == g[s] && f[1] == g[(s + 1) % 3] && f[2] == g[(s + 2) % 3]) return true;
    return false;
}

std::vector<TetFace> enumerate_faces(const std::vector<Tet>& tets) {
    std::vector<TetFace> faces;
    faces.reserve(tets.size() * 4);
    for (size_t t = 0; t < tets.size(); ++t)
        for (int k = 0; k < 4; ++k) {
            const Tet& x = tets[t];
            faces.push_back({face_key(x[kTetFaces[k][0]], x[kTetFaces[k][1]], x[kTetFaces[k][2]]),
                             static_cast<int32_t>(t), k});
        }
    std::sort(faces.begin(), faces.end(), [](const TetFace& a, const TetFace& b) {
        return a.key != b.key ? a.key < b.key : a.tet < b.tet;
    });
    return faces;
}

std::array<int32_t, 3> outward_face(const Tet& t, int k) {
    return {t[kTetFaces[k][0]], t[kTetFaces[k][1]], t[kTetFaces[k][2]]};
}

double signed_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    return dot(b - a, cross(c - a, d - a)) / 6.0;
}

}  // namespace detail

using detail::FaceKey;
using detail::round_trip_text;
using detail::significant_text;
using detail::three_digit_text;

namespace {

std::string num(int64_t v) { return std::to_string(v); }

struct UnionFind {
    std::vector<int32_t> parent;
    explicit UnionFind(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
    int32_t find(int32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    }
    void unite(int32_t a, int32_t b) {
        a = find(a);
        b = find(b);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
};

// ---------------------------------------------------------------------------
// Running TetGen
// ---------------------------------------------------------------------------

std::string find_executable(const std::string& name) {
    if (name.find('/') != std::string::npos) return access(name.c_str(), X_OK) == 0 ? name : std::string();
    const char* path = std::getenv("PATH");
    std::string dirs = path ? path : "/usr/local/bin:/usr/bin:/bin";
    size_t start = 0;
    while (start <= dirs.size()) {
        size_t end = dirs.find(':', start);
        if (end == std::string::npos) end = dirs.size();
        std::string dir = dirs.substr(start, end - start);
        if (dir.empty()) dir = ".";
        const std::string candidate = dir + "/" + name;
        struct stat st{};
        if (stat(candidate.c_str(), &st) == 0 && S_ISREG(st.st_mode) && access(candidate.c_str(), X_OK) == 0)
            return candidate;
        start = end + 1;
    }
    return {};
}

class TempDir {
public:
    explicit TempDir(bool keep) : keep_(keep) {
        std::string pattern = (std::filesystem::temp_directory_path() / "bpm-tetgen-XXXXXX").string();
        std::vector<char> buffer(pattern.begin(), pattern.end());
        buffer.push_back('\0');
        if (!mkdtemp(buffer.data()))
            throw ExternalToolError("cannot create a temporary directory for TetGen in " +
                                    std::filesystem::temp_directory_path().string() + ": " + std::strerror(errno));
        path_ = buffer.data();
    }
    ~TempDir() {
        if (keep_) return;
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    const std::string& path() const { return path_; }

private:
    std::string path_;
    bool keep_;
};

std::string read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

void write_text(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
    if (!out) throw ExternalToolError("cannot write TetGen input " + path);
}

// The last `n` non-empty lines of TetGen's output, which hold its error message.
std::string tail_lines(const std::string& text, size_t n) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);)
        if (line.find_first_not_of(" \t\r") != std::string::npos) lines.push_back(line);
    std::string out;
    for (size_t i = lines.size() > n ? lines.size() - n : 0; i < lines.size(); ++i) out += "\n  " + lines[i];
    return out;
}

// The running TetGen process, in a process group of its own (so that signals reach any
// helper it starts). Whatever ends the wait - normal exit, the time limit, cancellation
// through the progress callback (the tools turn SIGINT/SIGTERM/SIGHUP into that), or an
// exception - the destructor stops the whole group: SIGTERM, then SIGKILL after a grace
// period, and reaps it. If bpm itself is killed outright (SIGKILL), PR_SET_PDEATHSIG
// makes the kernel kill TetGen with it.
class TetgenProcess {
public:
    TetgenProcess(const std::string& exe, const std::vector<std::string>& args, const std::string& dir,
                  const std::string& log) {
        const pid_t parent = getpid();
        pid_ = fork();
        if (pid_ < 0) throw ExternalToolError(std::string("cannot start tetgen: fork failed: ") + std::strerror(errno));
        if (pid_ == 0) {
            setpgid(0, 0);
            // Death signal first, then the check for a parent that died before it was set.
            prctl(PR_SET_PDEATHSIG, SIGKILL);
            if (getppid() != parent) _exit(125);
            // A tool may catch or ignore these (to clean up); TetGen gets the defaults.
            for (const int sig : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) signal(sig, SIG_DFL);
            sigset_t none;
            sigemptyset(&none);
            sigprocmask(SIG_SETMASK, &none, nullptr);
            const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
            if (fd < 0 || chdir(dir.c_str()) != 0) _exit(126);
            dup2(fd, STDOUT_FILENO);
            dup2(fd, STDERR_FILENO);
            const int null = open("/dev/null", O_RDONLY);
            if (null >= 0) dup2(null, STDIN_FILENO);
            std::vector<char*> argv;
            argv.push_back(const_cast<char*>(exe.c_str()));
            for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
            argv.push_back(nullptr);
            execv(exe.c_str(), argv.data());
            _exit(127);
        }
        // Also from the parent, so that the group exists before any kill(-pid) below.
        setpgid(pid_, pid_);
    }
    TetgenProcess(const TetgenProcess&) = delete;
    TetgenProcess& operator=(const TetgenProcess&) = delete;
    ~TetgenProcess() { stop(); }

    // True (and the wait status in `status`) once TetGen has exited.
    bool finished(int& status) {
        if (reaped_) {
            status = status_;
            return true;
        }
        const pid_t r = waitpid(pid_, &status_, WNOHANG);
        if (r == pid_) {
            reaped_ = true;
            // Anything TetGen left behind in its group goes too.
            kill(-pid_, SIGKILL);
            status = status_;
            return true;
        }
        if (r < 0 && errno != EINTR) throw ExternalToolError(std::string("waiting for tetgen failed: ") + std::strerror(errno));
        return false;
    }

    // Stops the process group (SIGTERM, SIGKILL after 2 s) and reaps TetGen.
    void stop() {
        if (reaped_) return;
        kill(-pid_, SIGTERM);
        const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(2);
        while (!reaped_ && std::chrono::steady_clock::now() < give_up) {
            if (waitpid(pid_, &status_, WNOHANG) == pid_) reaped_ = true;
            else usleep(10000);
        }
        kill(-pid_, SIGKILL);
        while (!reaped_) {
            const pid_t r = waitpid(pid_, &status_, 0);
            if (r == pid_ || (r < 0 && errno != EINTR)) reaped_ = true;
        }
    }

private:
    pid_t pid_ = -1;
    int status_ = 0;
    bool reaped_ = false;
};

std::string seconds_text(double s) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.0f s", s);
    return buffer;
}

// Runs `exe args` in `dir` with stdout and stderr into dir/tetgen.log; returns the log.
// Polls every 50 ms: the progress callback (cancellation), the time limit (0 = none),
// and a log line every 30 s so that a long run is never silent.
std::string run_tetgen(const std::string& exe, const std::vector<std::string>& args, const std::string& dir,
                       std::string& command, const Context& context, double fraction, const std::string& stage,
                       double time_limit_seconds, double& elapsed_before) {
    command = exe;
    for (const auto& a : args) command += " " + a;
    const std::string log = dir + "/tetgen.log";
    using clock = std::chrono::steady_clock;
    const auto start = clock::now();
    TetgenProcess process(exe, args, dir, log);
    int status = 0;
    double next_note = 30;
    while (!process.finished(status)) {
        const double elapsed = std::chrono::duration<double>(clock::now() - start).count();
        const double total = elapsed_before + elapsed;
        if (time_limit_seconds > 0 && total > time_limit_seconds) {
            process.stop();
            throw ExternalToolError("TetGen did not finish within the time limit of " +
                                    seconds_text(time_limit_seconds) + " (" + stage + ", `" + command +
                                    "`); it was stopped. Loosen the quality bounds or allow more time");
        }
        if (elapsed >= next_note) {
            context.info("TetGen still running (" + stage + ", " + seconds_text(elapsed) + ")");
            next_note += 30;
        }
        context.report(fraction, stage + ", " + seconds_text(elapsed));  // throws Cancelled; ~process stops TetGen
        usleep(50000);
    }
    elapsed_before += std::chrono::duration<double>(clock::now() - start).count();
    const std::string output = read_text(log);
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return output;
    std::string how = WIFEXITED(status) ? "exit status " + num(WEXITSTATUS(status))
                                        : "signal " + num(WIFSIGNALED(status) ? WTERMSIG(status) : -1);
    if (WIFEXITED(status) && WEXITSTATUS(status) == 127) how += " (could not execute " + exe + ")";
    throw ExternalToolError("tetgen failed (" + how + ") running `" + command + "` in " + dir +
                            "; its last output lines:" + tail_lines(output, 12));
}

// Whitespace-separated numbers of a TetGen output file, '#' comments skipped. TetGen
// writes them with printf in the "C" locale (it never calls setlocale), whatever locale
// the program that links libbpm has set; parse_double reads them so.
class Tokens {
public:
    Tokens(std::string text, std::string name) : text_(std::move(text)), name_(std::move(name)) {}
    double next() {
        while (pos_ < text_.size()) {
            const char c = text_[pos_];
            if (c == '#') {
                while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
            } else if (std::isspace(static_cast<unsigned char>(c))) {
                ++pos_;
            } else {
                break;
            }
        }
        if (pos_ >= text_.size()) throw ExternalToolError("TetGen output " + name_ + " ends early");
        double v = 0;
        const char* start = text_.data() + pos_;
        const std::from_chars_result r = detail::parse_double(start, text_.data() + text_.size(), v);
        if (r.ptr == start) throw ExternalToolError("TetGen output " + name_ + ": unexpected text");
        pos_ = static_cast<size_t>(r.ptr - text_.data());
        return v;
    }
    int64_t next_int() {
        const double v = next();
        if (v != std::floor(v) || std::fabs(v) > 2e9) throw ExternalToolError("TetGen output " + name_ + ": bad integer");
        return static_cast<int64_t>(v);
    }

private:
    std::string text_, name_;
    size_t pos_ = 0;
};

struct TetgenMesh {
    std::vector<Vec3> nodes;
    std::vector<Tet> tets;
    std::vector<int32_t> attributes;  // region attribute per tet (0 if none)
};

TetgenMesh read_tetgen_output(const std::string& base) {
    TetgenMesh m;
    if (!std::filesystem::exists(base + ".node") || !std::filesystem::exists(base + ".ele"))
        throw ExternalToolError("tetgen reported success but wrote no " + base + ".node / .ele");
    Tokens node(read_text(base + ".node"), base + ".node");
    const int64_t nn = node.next_int();
    const int64_t dim = node.next_int();
    const int64_t nattr = node.next_int();
    const int64_t nmark = node.next_int();
    if (dim != 3 || nn < 0) throw ExternalToolError("TetGen output " + base + ".node: unexpected header");
    m.nodes.resize(static_cast<size_t>(nn));
    for (int64_t i = 0; i < nn; ++i) {
        const int64_t id = node.next_int();
        if (id != i) throw ExternalToolError("TetGen output " + base + ".node: node numbering is not 0-based");
        for (int c = 0; c < 3; ++c) m.nodes[static_cast<size_t>(i)][c] = node.next();
        for (int64_t a = 0; a < nattr + (nmark ? 1 : 0); ++a) node.next();
    }
    Tokens ele(read_text(base + ".ele"), base + ".ele");
    const int64_t nt = ele.next_int();
    const int64_t corners = ele.next_int();
    const int64_t eattr = ele.next_int();
    if (corners != 4 || nt < 0) throw ExternalToolError("TetGen output " + base + ".ele: unexpected header");
    m.tets.resize(static_cast<size_t>(nt));
    m.attributes.assign(static_cast<size_t>(nt), 0);
    for (int64_t i = 0; i < nt; ++i) {
        ele.next_int();
        for (int c = 0; c < 4; ++c) {
            const int64_t v = ele.next_int();
            if (v < 0 || v >= nn) throw ExternalToolError("TetGen output " + base + ".ele: vertex out of range");
            m.tets[static_cast<size_t>(i)][c] = static_cast<int32_t>(v);
        }
        for (int64_t a = 0; a < eattr; ++a) {
            const double x = ele.next();
            if (a == 0) m.attributes[static_cast<size_t>(i)] = static_cast<int32_t>(std::lround(x));
        }
    }
    return m;
}

// What the flood fill finds in a tetrahedralization of the volume bounded by S.
struct Regions {
    std::vector<int32_t> region;                      // #Tet region id >= 1
    int32_t count = 0;
    std::vector<std::array<int32_t, 2>> sides;        // #S.T region on (front, back), 0 = outside
    std::vector<std::array<int32_t, 2>> side_tets;    // #S.T the tet on (front, back), -1 = none
};

// Orients all tets positively (exactly), then flood-fills regions and checks that S is
// exactly a union of faces of the mesh.
Regions find_regions(const Surface& s, const std::vector<Vec3>& nodes, std::vector<Tet>& tets) {
    for (size_t t = 0; t < tets.size(); ++t) {
        Tet& x = tets[t];
        const int o = orient3d(nodes[x[0]], nodes[x[1]], nodes[x[2]], nodes[x[3]]);
        if (o == 0) throw AlgorithmError("TetGen produced a flat tetrahedron (" + num(t) + ")");
        if (o < 0) std::swap(x[2], x[3]);
    }
    std::map<FaceKey, int32_t> coarse;
    for (int32_t t = 0; t < s.num_triangles(); ++t) {
        const Tri& c = s.triangles[t];
        coarse.emplace(detail::face_key(c[0], c[1], c[2]), t);
    }
    Regions r;
    r.sides.assign(s.triangles.size(), {0, 0});
    r.side_tets.assign(s.triangles.size(), {-1, -1});
    UnionFind uf(tets.size());
    const auto faces = detail::enumerate_faces(tets);
    for (size_t i = 0; i < faces.size();) {
        size_t j = i;
        while (j < faces.size() && faces[j].key == faces[i].key) ++j;
        if (j - i > 2) throw AlgorithmError("TetGen produced a non-manifold tetrahedral mesh (a face in 3 tets)");
        const auto it = coarse.find(faces[i].key);
        if (it != coarse.end()) {
            const int32_t t = it->second;
            for (size_t k = i; k < j; ++k) {
                const auto g = detail::outward_face(tets[faces[k].tet], faces[k].local);
                // The face, oriented out of this tet, agrees with the coarse triangle: the
                // tet is on the back side.
                const int side = detail::same_cyclic_orientation(s.triangles[t], g) ? 1 : 0;
                if (r.side_tets[t][side] >= 0)
                    throw AlgorithmError("TetGen's mesh has two tetrahedra on the same side of coarse triangle " +
                                         num(t));
                r.side_tets[t][side] = faces[k].tet;
            }
        } else if (j - i == 2) {
            uf.unite(faces[i].tet, faces[i + 1].tet);
        } else {
            const auto& k = faces[i].key;
            throw AlgorithmError("TetGen's mesh has a boundary face (" + num(k[0]) + ", " + num(k[1]) + ", " +
                                 num(k[2]) + ") that is not a coarse triangle; is the surface closed?");
        }
        i = j;
    }
    for (int32_t t = 0; t < s.num_triangles(); ++t)
        if (r.side_tets[t][0] < 0 && r.side_tets[t][1] < 0)
            throw AlgorithmError("coarse triangle " + num(t) + " (vertices " + num(s.triangles[t][0]) + ", " +
                                 num(s.triangles[t][1]) + ", " + num(s.triangles[t][2]) +
                                 ") is not a face of TetGen's mesh (TetGen changed the surface)");
    // Number the components by their first bounding side 2t (front) / 2t+1 (back).
    std::map<int32_t, int64_t> first_side;
    for (int32_t t = 0; t < s.num_triangles(); ++t)
        for (int side = 0; side < 2; ++side)
            if (r.side_tets[t][side] >= 0) first_side.emplace(uf.find(r.side_tets[t][side]), 2 * int64_t(t) + side);
    std::vector<std::pair<int64_t, int32_t>> order;
    for (const auto& [root, key] : first_side) order.emplace_back(key, root);
    std::sort(order.begin(), order.end());
    std::map<int32_t, int32_t> id_of_root;
    for (size_t i = 0; i < order.size(); ++i) id_of_root[order[i].second] = static_cast<int32_t>(i + 1);
    r.count = static_cast<int32_t>(order.size());
    r.region.resize(tets.size());
    for (size_t t = 0; t < tets.size(); ++t) {
        const auto it = id_of_root.find(uf.find(static_cast<int32_t>(t)));
        if (it == id_of_root.end())
            throw AlgorithmError("TetGen's mesh has tetrahedra not bounded by the surface (tet " + num(t) + ")");
        r.region[t] = it->second;
    }
    for (int32_t t = 0; t < s.num_triangles(); ++t)
        for (int side = 0; side < 2; ++side)
            r.sides[t][side] = r.side_tets[t][side] >= 0 ? r.region[r.side_tets[t][side]] : 0;
    return r;
}

// A point strictly inside each region: the incentre of its tet with the largest inradius.
std::vector<Vec3> interior_points(const std::vector<Vec3>& nodes, const std::vector<Tet>& tets, const Regions& r) {
    std::vector<Vec3> points(static_cast<size_t>(r.count));
    std::vector<double> best(static_cast<size_t>(r.count), -1.0);
    for (size_t t = 0; t < tets.size(); ++t) {
        const Tet& x = tets[t];
        double area[4], total = 0;
        for (int k = 0; k < 4; ++k) {
            const auto f = detail::outward_face(x, k);
            area[k] = triangle_area(nodes[f[0]], nodes[f[1]], nodes[f[2]]);
            total += area[k];
        }
        const double vol = detail::signed_volume(nodes[x[0]], nodes[x[1]], nodes[x[2]], nodes[x[3]]);
        const double inradius = total > 0 ? 3 * vol / total : 0;
        const size_t id = static_cast<size_t>(r.region[t] - 1);
        if (inradius > best[id]) {
            best[id] = inradius;
            Vec3 c{0, 0, 0};
            for (int k = 0; k < 4; ++k) c = c + (area[k] / total) * nodes[x[k]];  // face k is opposite vertex k
            points[id] = c;
        }
    }
    return points;
}

// A number for a TetGen switch: short, but exact for the values people type.
std::string format_switch(double v) { return significant_text(v, 12); }

}  // namespace

// ---------------------------------------------------------------------------
// Public functions
// ---------------------------------------------------------------------------

void check_meshable(const Surface& surface, const Context& context) {
    if (surface.triangles.empty()) throw AlgorithmError("cannot mesh an empty surface");
    ValidateOptions vo;
    vo.max_problems = 1;
    const auto problems = validate_surface(surface, vo);
    if (!problems.empty())
        throw AlgorithmError("cannot mesh the coarse surface: " + describe_problem(problems.front(), surface));
    const SurfaceConnectivity c = build_connectivity(surface);
    int64_t boundary = 0;
    int32_t first = -1;
    for (int32_t e = 0; e < c.num_edges(); ++e)
        if (c.edge_degree(e) == 1) {
            if (first < 0) first = e;
            ++boundary;
        }
    if (boundary > 0) {
        // Where, as positions: the vertex numbers of the coarse surface mean nothing to a
        // user looking at the input. The coarse surface has the original's boundary
        // (bpm-check's topology check), so the cause is in the input, e.g. an open seam.
        const auto at = [&](int32_t v) {
            const Vec3& p = surface.vertices[size_t(v)];
            return "(" + round_trip_text(p[0]) + ", " + round_trip_text(p[1]) + ", " + round_trip_text(p[2]) + ")";
        };
        const int32_t a = c.edges[first][0], b = c.edges[first][1];
        const std::string message =
            "the coarse surface has " + num(boundary) + " boundary edge" + (boundary == 1 ? "" : "s") +
            ", first from vertex " + num(a) + " " + at(a) + " to vertex " + num(b) + " " + at(b) +
            ": it does not enclose a volume, and TetGen needs a closed surface. The boundary is the "
            "input surface's (bpm-simplify keeps it): close the input there, e.g. an open seam "
            "whose two sides have vertices at slightly different positions";
        // A seam open by rounding (the coarse surface keeps the input's boundary vertices):
        // say so, and how far apart, so that the tool can name the repair.
        const double diagonal = bounding_box_diagonal(surface.vertices);
        if (const std::optional<OpenSeam> seam = find_open_seam(surface, kOpenSeamMaxGap * diagonal)) {
            const double tolerance = seam_merge_tolerance(surface, *seam, diagonal);
            // Three digits, not the positions' full precision: these are ratios.
            if (tolerance > 0)
                throw OpenSeamError(message + ": here " + num(seam->paired_edges) + " of the " + num(boundary) +
                                        " boundary edges pair up with others within " +
                                        three_digit_text(seam->gap / diagonal) +
                                        " of the diagonal, so it is such a seam, which merging the input's vertices "
                                        "within " + three_digit_text(tolerance) + " of its diagonal closes",
                                    tolerance);
        }
        throw AlgorithmError(message);
    }
    CheckOptions co;
    co.max_problems = 1;
    const CheckResult r = check_intersections(surface, co, context);
    if (!r.passed)
        throw AlgorithmError("surface intersects or touches itself (" + r.summary + "); first: " +
                             (r.problems.empty() ? std::string("?") : r.problems.front().describe()) +
                             " (TetGen needs sheets that meet only in shared vertices and edges)");
}

std::string tetgen_poly(const Surface& s, const std::vector<Vec3>& region_points) {
    std::string out;
    out.reserve(64 * (s.vertices.size() + s.triangles.size()));
    out += "# bpm coarse surface: part 1 nodes (0-based)\n";
    out += num(s.num_vertices()) + " 3 0 0\n";
    for (int32_t v = 0; v < s.num_vertices(); ++v)
        out += num(v) + " " + round_trip_text(s.vertices[v][0]) + " " + round_trip_text(s.vertices[v][1]) + " " +
               round_trip_text(s.vertices[v][2]) + "\n";
    out += "# part 2 facets: one per coarse triangle, boundary marker = patch id\n";
    out += num(s.num_triangles()) + " 1\n";
    for (int32_t t = 0; t < s.num_triangles(); ++t) {
        const Tri& x = s.triangles[t];
        out += "1 0 " + num(s.patches[t]) + "\n3 " + num(x[0]) + " " + num(x[1]) + " " + num(x[2]) + "\n";
    }
    out += "# part 3 holes\n0\n# part 4 regions: index x y z attribute (region id) max-volume (unused)\n";
    out += num(static_cast<int64_t>(region_points.size())) + "\n";
    for (size_t r = 0; r < region_points.size(); ++r)
        out += num(static_cast<int64_t>(r)) + " " + round_trip_text(region_points[r][0]) + " " +
               round_trip_text(region_points[r][1]) + " " + round_trip_text(region_points[r][2]) + " " +
               num(static_cast<int64_t>(r + 1)) + " 0\n";
    return out;
}

TetMeshResult generate_tetmesh(const Parametrization& param, const TetMeshOptions& options, const Context& context,
                               TetMesh& out) {
    using clock = std::chrono::steady_clock;
    const auto start = clock::now();
    const Surface& s = param.coarse;
    // TetGen does not terminate for radius-edge bounds at or below 1 (its manual: the
    // bound should be larger than 1; about 1.1 is the practical limit).
    if (!(options.quality > 1.0) || !std::isfinite(options.quality))
        throw OptionError("quality (TetGen's radius-edge ratio bound) must be larger than 1.0 (e.g. 1.414); "
                          "TetGen does not terminate for smaller bounds");
    if (options.max_volume && !(*options.max_volume > 0 && std::isfinite(*options.max_volume)))
        throw OptionError("max volume must be a positive number");
    // TetGen's dihedral-angle refinement (-q1.414/<angle>) has no termination guarantee.
    // Measured with TetGen 1.5 on bpm-simplify --ratio 0.1 surfaces (30 s limit; angles
    // 10 14 16 17 18 19 20 21 22 25 30): every run up to 20 degrees finished in the time
    // of the unbounded run (0.1 s femur ... 3.3 s armadillo); the first angle that did not
    // finish was 21 (armadillo), 22 (femur, femur --ratio 0.5), 25 (fandisk), 30 (elephant).
    // The limit keeps 3 degrees below the smallest; refused up front, as quality <= 1 is.
    if (options.min_dihedral_degrees && !(*options.min_dihedral_degrees >= 0))
        throw OptionError("minimum dihedral angle must be >= 0 degrees");
    if (options.min_dihedral_degrees && !(*options.min_dihedral_degrees <= kMaxTetgenMinDihedralDegrees))
        throw OptionError("minimum dihedral angle " + format_switch(*options.min_dihedral_degrees) +
                          " is above the limit of " + format_switch(kMaxTetgenMinDihedralDegrees) +
                          " degrees: TetGen does not terminate for larger bounds (the elements bpm-mesh makes "
                          "from its output are smoothed afterwards)");
    if (!(options.max_dihedral_degrees == 0 ||
          (options.max_dihedral_degrees >= 90 && options.max_dihedral_degrees < 180)))
        throw OptionError("max_dihedral_degrees must be 0 (TetGen's default) or between 90 and 180 degrees");
    if (!(options.time_limit_seconds >= 0) || !std::isfinite(options.time_limit_seconds))
        throw OptionError("time limit must be a number of seconds >= 0 (0 = no limit)");
    detail::require_coordinates_in_range(param);
    context.report(0.0, "checking the coarse surface");
    check_meshable(s, context);
    // TetGen keeps S exactly (-Y): a needle of S (an original one the simplifier could not
    // remove; femur at 10 % keeps one of R/r 92.8) bounds the dihedral angles of the
    // tetrahedra on it (0.55 degrees there), and nothing after TetGen can fix that.
    {
        int32_t worst = -1;
        double worst_aspect = 0;
        for (int32_t t = 0; t < s.num_triangles(); ++t) {
            const double a = aspect_ratio(s.vertices[s.triangles[t][0]], s.vertices[s.triangles[t][1]],
                                          s.vertices[s.triangles[t][2]]);
            if (!(a <= worst_aspect)) worst_aspect = a, worst = t;
        }
        if (worst >= 0 && !(worst_aspect <= kSliverAspectRatio))
            context.warn("coarse triangle " + num(worst) + " has aspect ratio " + three_digit_text(worst_aspect) +
                         " (above " + format_switch(kSliverAspectRatio) +
                         "): the tetrahedra on it will have small dihedral angles");
    }

    const std::string exe = find_executable(options.tetgen);
    if (exe.empty())
        throw ExternalToolError("'" + options.tetgen +
                                "' not found on PATH: bpm-mesh needs TetGen (install the Debian package 'tetgen': "
                                "apt-get install tetgen)");
    TempDir dir(options.keep_temporary);
    if (options.keep_temporary) context.info("TetGen files are kept in " + dir.path());
    TetMeshResult result;
    double tetgen_seconds = 0;
    auto run = [&](const std::string& name, const std::vector<Vec3>& points, const std::vector<std::string>& switches,
                   double fraction, const std::string& stage) {
        context.debug(stage + ": running TetGen " + [&] {
            std::string line;
            for (const auto& w : switches) line += w + " ";
            return line;
        }() + "...");
        context.report(fraction, stage);
        write_text(dir.path() + "/" + name + ".poly", tetgen_poly(s, points));
        std::vector<std::string> args = switches;
        args.push_back(name + ".poly");
        std::string command;
        const std::string log = run_tetgen(exe, args, dir.path(), command, context, fraction, stage,
                                           options.time_limit_seconds, tetgen_seconds);
        result.tetgen_command = command;
        context.debug("ran " + command);
        TetgenMesh m = read_tetgen_output(dir.path() + "/" + name + ".1");
        // -Y: the input points come back first, unchanged.
        if (m.nodes.size() < s.vertices.size())
            throw AlgorithmError("TetGen dropped input vertices (" + num(int64_t(m.nodes.size())) + " < " +
                                 num(s.num_vertices()) + ")");
        for (int32_t v = 0; v < s.num_vertices(); ++v)
            if (m.nodes[v] != s.vertices[v])
                throw AlgorithmError("TetGen moved coarse vertex " + num(v));
        return m;
    };

    TetgenMesh first = run("regions", {}, {"-pYzA"}, 0.05, "TetGen pass 1 (regions)");
    const Regions r1 = find_regions(s, first.nodes, first.tets);
    const std::vector<Vec3> seeds = interior_points(first.nodes, first.tets, r1);
    context.debug("found " + num(r1.count) + " region(s)");

    std::vector<std::string> switches{"-pYzA", "-q" + format_switch(options.quality) +
                                                (options.min_dihedral_degrees
                                                     ? "/" + format_switch(*options.min_dihedral_degrees)
                                                     : std::string())};
    if (options.max_volume) switches.push_back("-a" + format_switch(*options.max_volume));
    if (options.max_dihedral_degrees > 0) switches.push_back("-o/" + format_switch(options.max_dihedral_degrees));
    TetgenMesh m = run("mesh", seeds, switches, 0.2, "TetGen pass 2 (quality mesh)");
    context.report(0.8, "reading the tetrahedral mesh");
    const Regions r = find_regions(s, m.nodes, m.tets);
    if (r.count != r1.count)
        throw AlgorithmError("TetGen's two passes disagree on the number of regions (" + num(r1.count) + " and " +
                             num(r.count) + ")");
    // TetGen's attributes come from locating each seed in floating point: in a region
    // thinner than its rounding (noisy label images give regions 1e-6 across) the seed
    // can land in a neighbour, whose tetrahedra then carry both regions' attributes. The
    // flood fill is exact and is what the mesh uses; a disagreement is only reported.
    int64_t disagreeing = 0, first_disagreeing = -1;
    for (size_t t = 0; t < m.tets.size(); ++t)
        if (m.attributes[t] != r.region[t] && disagreeing++ == 0) first_disagreeing = int64_t(t);
    if (disagreeing > 0)
        context.debug("TetGen's region attributes differ from the flood fill on " + num(disagreeing) +
                      (disagreeing == 1 ? " tetrahedron" : " tetrahedra") + " (first: tetrahedron " + num(first_disagreeing) + ", attribute " +
                      num(m.attributes[size_t(first_disagreeing)]) + ", region " +
                      num(r.region[size_t(first_disagreeing)]) + "): the flood fill's regions are used");

    out = TetMesh{};
    out.vertices = std::move(m.nodes);
    out.tetrahedra = std::move(m.tets);
    out.regions = r.region;
    out.faces = s.triangles;
    out.face_coarse_triangle.resize(s.triangles.size());
    std::iota(out.face_coarse_triangle.begin(), out.face_coarse_triangle.end(), 0);
    out.face_patches = s.patches;
    const size_t nv = out.vertices.size();
    out.vertex_coarse_vertex.assign(nv, -1);
    out.vertex_parameter_points.assign(nv, SurfacePoint{});
    for (int32_t t = s.num_triangles() - 1; t >= 0; --t)  // the first triangle of each vertex wins
        for (int c = 0; c < 3; ++c) {
            const int32_t v = s.triangles[t][c];
            out.vertex_coarse_vertex[v] = v;
            Vec3 b{0, 0, 0};
            b[c] = 1;
            out.vertex_parameter_points[v] = {t, b};
        }
    out.level = 0;
    // One round of level-0 improvement: flips, a new interior vertex in each sliver no flip
    // improves, and flips again around the new vertices. `when` names the round in the
    // debug lines ("" or " after the splits").
    // Progress: this improvement takes most of the time after TetGen on noisy label images
    // (noisy 32^3 at 20 %: 13 of 16 s; the whole run on 64^3 took 181 s), where "reading the
    // tetrahedral mesh" stood still on the terminal throughout. `at`: the fraction of the round's start.
    const auto flip_and_insert = [&](const detail::TetFlipOptions& flip_options, const std::string& when, double at) {
        const std::string round = when.empty() ? "" : " (round 2)";
        context.report(at, "improving the mesh: flips" + round);
        const detail::TetFlipResult fr = detail::flip_tetrahedra(out.vertices, out.tetrahedra, nullptr, out.regions,
                                                                 nullptr, out.faces, flip_options);
        result.flips += fr.flips_23 + fr.edge_removals;
        result.flip_seconds += fr.seconds;
        context.debug("level-0 flips" + when + ": " + num(fr.flips_23) + " 2-3 flips and " + num(fr.edge_removals) +
                      " edge removals (" + num(fr.visited) + " tetrahedra below 15 degrees, " + num(fr.sweeps) +
                      " sweeps), min dihedral " + detail::three_digit_text(fr.min_dihedral_before_degrees) + " -> " +
                      detail::three_digit_text(fr.min_dihedral_after_degrees) + " degrees, " +
                      detail::three_digit_text(fr.seconds) + " s");
        context.report(at + 0.02, "improving the mesh: vertices in slivers" + round);
        const detail::TetInsertResult ir =
            detail::insert_vertices(out.vertices, out.tetrahedra, out.regions, out.faces, {});
        result.insertions += ir.inserted;
        result.flip_seconds += ir.seconds;
        out.vertex_coarse_vertex.resize(out.vertices.size(), -1);
        out.vertex_parameter_points.resize(out.vertices.size(), SurfacePoint{});
        context.debug("level-0 vertex insertion" + when + ": " + num(ir.inserted) + " vertices inserted (" +
                      num(ir.tried) + " tetrahedra below 15 degrees, " + num(ir.rounds) + " rounds), min dihedral " +
                      detail::three_digit_text(ir.min_dihedral_before_degrees) + " -> " +
                      detail::three_digit_text(ir.min_dihedral_after_degrees) + " degrees, " +
                      detail::three_digit_text(ir.seconds) + " s");
        if (ir.inserted == 0) return;
        context.report(at + 0.04, "improving the mesh: flips at new vertices" + round);
        const detail::TetFlipResult again = detail::flip_tetrahedra(out.vertices, out.tetrahedra, nullptr,
                                                                    out.regions, nullptr, out.faces, flip_options);
        result.flips += again.flips_23 + again.edge_removals;
        result.flip_seconds += again.seconds;
        context.debug("level-0 flips after insertion" + when + ": " + num(again.flips_23) + " 2-3 flips and " +
                      num(again.edge_removals) + " edge removals, min dihedral " +
                      detail::three_digit_text(again.min_dihedral_before_degrees) + " -> " +
                      detail::three_digit_text(again.min_dihedral_after_degrees) + " degrees");
    };
    // Flips first, then smoothing: measured on femur, fandisk, elephant, armadillo at 10 %
    // and at 1000 vertices, the other orders (smooth then flip, smooth-flip-smooth,
    // flip-smooth-flip-smooth) gave the same minimum angles and within one the same counts
    // of tetrahedra below 5 and 10 degrees.
    if (options.flip) flip_and_insert({}, "", 0.82);
    // Surface-corner splits after that round: before the flips they cost femur 10 % 203
    // vertices instead of 111 and gave 6.27 instead of 8.56 degrees after smoothing (the
    // flips and insertions remove some surface corners themselves and had fewer choices).
    // Then a second round, whose flips make no new surface corner (the inserted vertices
    // are interior, so their stars have none either): the halves of a split ring share its
    // angles at the edges opposite the split edge (they add up to the parent's), which
    // smoothing cannot widen; a new vertex in a cavity around them can. Femur 10 % level-0
    // minimum after smoothing 8.56 -> 10.6 degrees with 54 more vertices, armadillo 1000
    // 8.07 -> 14.0 with 32 (12.3 and 8.87 without the splits).
    if (options.split_surface_corners) {
        context.report(0.88, "improving the mesh: splitting surface corners");
        const detail::TetSplitResult sr =
            detail::split_surface_corners(out.vertices, out.tetrahedra, out.regions, out.faces);
        result.surface_corner_splits = sr.edge_splits + sr.centroid_splits;
        out.vertex_coarse_vertex.resize(out.vertices.size(), -1);
        out.vertex_parameter_points.resize(out.vertices.size(), SurfacePoint{});
        context.debug("level-0 surface corners: " + num(sr.found) + " tetrahedra with a corner whose three edges are on S, " +
                      num(sr.edge_splits) + " edges split, " + num(sr.centroid_splits) + " centroid splits, " +
                      num(sr.left) + " left, " + detail::three_digit_text(sr.seconds) + " s");
        if (options.flip) {
            detail::TetFlipOptions keep_corners_out;
            keep_corners_out.keep_surface_corners_out = true;
            flip_and_insert(keep_corners_out, " after the splits", 0.89);
        }
    }
    if (options.smooth) {
        // Its progress as 95-99 % of this call's: only this call's own report reaches 100 %
        // (a tool ends the progress line there).
        const TetSmoothResult sm = detail::smooth_tetmesh_within(out, options.smoothing, context, 0.95, 0.04);
        context.debug("level-0 smoothing: " + num(sm.moved_vertices) + " vertices moved, min dihedral " +
                      detail::three_digit_text(sm.min_dihedral_before_degrees) + " -> " +
                      detail::three_digit_text(sm.min_dihedral_after_degrees) + " degrees");
    }

    result.vertices = out.num_vertices();
    result.tetrahedra = out.num_tetrahedra();
    result.faces = static_cast<int64_t>(out.faces.size());
    result.regions = r.count;
    result.steiner_points = result.vertices - s.num_vertices();
    result.tetgen_seconds = tetgen_seconds;
    result.seconds = std::chrono::duration<double>(clock::now() - start).count();
    context.report(1.0, "tetrahedral mesh done");
    return result;
}

std::string find_tetmesh_inconsistency(const TetMesh& m, const Surface& coarse) {
    const int64_t nv = m.num_vertices(), nt = m.num_tetrahedra(), nf = static_cast<int64_t>(m.faces.size());
    const int64_t nvc = coarse.num_vertices(), ntc = coarse.num_triangles();
    auto sizes = [](size_t got, int64_t want, const char* name, const char* what) -> std::string {
        if (static_cast<int64_t>(got) != want)
            return std::string("/tetmesh/") + name + ": has " + num(int64_t(got)) + " rows, expected " + num(want) +
                   " (" + what + ")";
        return {};
    };
    for (auto e : {sizes(m.regions.size(), nt, "regions", "one per tetrahedron"),
                   sizes(m.face_coarse_triangle.size(), nf, "face_coarse_triangle", "one per face"),
                   sizes(m.face_patches.size(), nf, "face_patches", "one per face"),
                   sizes(m.vertex_coarse_vertex.size(), nv, "vertex_coarse_vertex", "one per vertex"),
                   sizes(m.vertex_parameter_points.size(), nv, "vertex_parameter_triangle", "one per vertex")})
        if (!e.empty()) return e;
    if (!m.tet_ancestor.empty())
        if (auto e = sizes(m.tet_ancestor.size(), nt, "tet_ancestor", "one per tetrahedron, or absent"); !e.empty())
            return e;
    if (m.level < 0) return "/tetmesh: attribute 'level' is negative (" + num(m.level) + ")";
    for (int64_t v = 0; v < nv; ++v)
        for (int c = 0; c < 3; ++c)
            if (!std::isfinite(m.vertices[v][c]))
                return "/tetmesh/vertices: entry [" + num(v) + ", " + num(c) + "] is not finite";
    for (int64_t t = 0; t < nt; ++t) {
        for (int c = 0; c < 4; ++c)
            if (m.tetrahedra[t][c] < 0 || m.tetrahedra[t][c] >= nv)
                return "/tetmesh/tetrahedra: entry [" + num(t) + ", " + num(c) + "] = " + num(m.tetrahedra[t][c]) +
                       " is out of range [0, " + num(nv) + ") (rows of /tetmesh/vertices)";
        if (m.regions[t] < 1)
            return "/tetmesh/regions: entry " + num(t) + " = " + num(m.regions[t]) + " is not a region id (>= 1)";
        if (!m.tet_ancestor.empty() && m.tet_ancestor[t] < 0)
            return "/tetmesh/tet_ancestor: entry " + num(t) + " = " + num(m.tet_ancestor[t]) + " is negative";
    }
    for (int64_t f = 0; f < nf; ++f) {
        for (int c = 0; c < 3; ++c)
            if (m.faces[f][c] < 0 || m.faces[f][c] >= nv)
                return "/tetmesh/faces: entry [" + num(f) + ", " + num(c) + "] = " + num(m.faces[f][c]) +
                       " is out of range [0, " + num(nv) + ") (rows of /tetmesh/vertices)";
        const int32_t t = m.face_coarse_triangle[f];
        if (t < 0 || t >= ntc)
            return "/tetmesh/face_coarse_triangle: entry " + num(f) + " = " + num(t) + " is out of range [0, " +
                   num(ntc) + ") (rows of /coarse/triangles)";
        if (m.face_patches[f] != coarse.patches[t])
            return "/tetmesh/face_patches: entry " + num(f) + " = " + num(m.face_patches[f]) +
                   " differs from the patch " + num(coarse.patches[t]) + " of its coarse triangle " + num(t);
    }
    for (int64_t v = 0; v < nv; ++v) {
        const int32_t cv = m.vertex_coarse_vertex[v];
        if (cv < -1 || cv >= nvc)
            return "/tetmesh/vertex_coarse_vertex: entry " + num(v) + " = " + num(cv) + " is out of range [-1, " +
                   num(nvc) + ")";
        const int32_t t = m.vertex_parameter_points[v].triangle;
        if (t < -1 || t >= ntc)
            return "/tetmesh/vertex_parameter_triangle: entry " + num(v) + " = " + num(t) + " is out of range [-1, " +
                   num(ntc) + ")";
        if (cv >= 0 && t < 0)
            return "/tetmesh/vertex_parameter_triangle: entry " + num(v) + " is -1 but the vertex is coarse vertex " +
                   num(cv);
        const Vec3& b = m.vertex_parameter_points[v].barycentric;
        for (int c = 0; c < 3; ++c)
            if (!std::isfinite(b[c]) || (t >= 0 && b[c] < 0))
                return "/tetmesh/vertex_parameter_barycentric: entry [" + num(v) + ", " + num(c) +
                       "] is negative or not finite";
        if (t >= 0 && std::fabs(b[0] + b[1] + b[2] - 1) > 1e-9)
            return "/tetmesh/vertex_parameter_barycentric: row " + num(v) + " does not sum to 1";
        if (cv >= 0) {
            int corner = -1;
            for (int c = 0; c < 3; ++c)
                if (coarse.triangles[t][c] == cv && b[c] == 1) corner = c;
            if (corner < 0)
                return "/tetmesh/vertex_parameter_barycentric: row " + num(v) + " is not the corner of coarse triangle " +
                       num(t) + " that is coarse vertex " + num(cv);
        }
    }
    return {};
}

TetMeshStats tetmesh_stats(const TetMesh& m) {
    TetMeshStats st;
    constexpr double kPi = 3.14159265358979323846;
    st.region_volumes.assign(static_cast<size_t>(m.num_regions()), 0.0);
    double min_angle = 180, max_angle = 0;
    for (int32_t t = 0; t < m.num_tetrahedra(); ++t) {
        const Tet& x = m.tetrahedra[t];
        const Vec3 p[4] = {m.vertices[x[0]], m.vertices[x[1]], m.vertices[x[2]], m.vertices[x[3]]};
        if (orient3d(p[0], p[1], p[2], p[3]) != 1) ++st.inverted;
        if (m.regions[t] >= 1) st.region_volumes[m.regions[t] - 1] += detail::signed_volume(p[0], p[1], p[2], p[3]);
        // Unsigned angles: an inverted tetrahedron is counted in `inverted`, its shape here.
        double angles[6];
        detail::dihedral_angles(p[0], p[1], p[2], p[3], angles);
        double tet_min = 180;
        for (double a : angles) {
            const double angle = std::abs(a) * 180 / kPi;  // as min_dihedral_degrees
            tet_min = std::min(tet_min, angle);
            max_angle = std::max(max_angle, angle);
        }
        min_angle = std::min(min_angle, tet_min);
        st.below_1_degree += tet_min < 1;
        st.below_5_degrees += tet_min < 5;
        st.below_10_degrees += tet_min < 10;
    }
    st.min_dihedral_degrees = m.tetrahedra.empty() ? 0 : min_angle;
    st.max_dihedral_degrees = m.tetrahedra.empty() ? 0 : max_angle;
    return st;
}

std::vector<double> region_volumes_on_original(const Parametrization& param, const TetMesh& m) {
    const Surface& s = param.coarse;
    // Region on the front (0) and back (1) of every coarse triangle, from the mesh's faces
    // and the (combinatorial) orientation of the tets on them.
    std::vector<std::array<int32_t, 2>> sides(s.triangles.size(), {0, 0});
    std::map<FaceKey, int32_t> face_index;
    for (size_t f = 0; f < m.faces.size(); ++f)
        face_index.emplace(detail::face_key(m.faces[f][0], m.faces[f][1], m.faces[f][2]), static_cast<int32_t>(f));
    for (int32_t t = 0; t < m.num_tetrahedra(); ++t)
        for (int k = 0; k < 4; ++k) {
            const auto g = detail::outward_face(m.tetrahedra[t], k);
            const auto it = face_index.find(detail::face_key(g[0], g[1], g[2]));
            if (it == face_index.end()) continue;
            const int32_t f = it->second;
            const int side = detail::same_cyclic_orientation(m.faces[f], g) ? 1 : 0;
            sides[m.face_coarse_triangle[f]][side] = m.regions[t];
        }
    Vec3 origin{0, 0, 0};
    if (!param.original.vertices.empty()) origin = param.original.vertices.front();
    std::vector<double> volumes(static_cast<size_t>(m.num_regions()), 0.0);
    for (int32_t t = 0; t < s.num_triangles(); ++t) {
        double cone = 0;
        const int64_t base = param.node_offsets[t];
        for (int64_t q = param.piece_offsets[t]; q < param.piece_offsets[t + 1]; ++q) {
            const Tri& pc = param.pieces[q];
            cone += detail::signed_volume(origin, param.node_image[base + pc[0]], param.node_image[base + pc[1]],
                                          param.node_image[base + pc[2]]);
        }
        if (sides[t][1] > 0) volumes[sides[t][1] - 1] += cone;  // region behind the triangle
        if (sides[t][0] > 0) volumes[sides[t][0] - 1] -= cone;  // region in front
    }
    return volumes;
}

}  // namespace bpm
