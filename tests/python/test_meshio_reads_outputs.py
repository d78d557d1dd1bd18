"""meshio (python3-meshio) reads every output format bpm writes: bpm-refine's surfaces
(.off .obj .stl .ply .vtu) and bpm-mesh's volume meshes (.msh .vtu .mesh), with the
vertex and element counts bpm reports. Prevents outputs that solvers' readers choke on:
meshio 5 crashed on bpm's binary PLY ("numpy.int32 has no len()"), and physical tag 0
in .msh is read as "no physical group"."""
import os
import shutil
import subprocess
import sys

from vtk_test_common import parse_args, report, work_dir

TET = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"


def main():
    args = parse_args()
    try:
        import meshio
    except ImportError as e:
        print("test_meshio_reads_outputs: FAILED, cannot import meshio (python3-meshio): %s" % e)
        return 1
    work = work_dir(args, "meshio_reads_outputs")
    tool = lambda name: os.path.join(args.tools, name)
    with open(os.path.join(work, "tet.off"), "w") as f:
        f.write(TET)
    run = lambda *cmd: subprocess.run(cmd, check=True, capture_output=True)
    run(tool("bpm-simplify"), os.path.join(work, "tet.off"), "-o", os.path.join(work, "tet.bpm"), "--vertices", "4", "-q")
    expected = {}  # path -> (points, {cell type: count})
    for ext in ("off", "obj", "stl", "ply", "vtu"):
        path = os.path.join(work, "surface." + ext)
        run(tool("bpm-refine"), os.path.join(work, "tet.bpm"), "--levels", "1", "-o", path, "-q")
        expected[path] = (10 if ext != "stl" else None, {"triangle": 16})
    if shutil.which("tetgen"):
        for ext in ("msh", "vtu", "mesh"):
            path = os.path.join(work, "volume." + ext)
            run(tool("bpm-mesh"), os.path.join(work, "tet.bpm"), "-o", path, "-q")
            expected[path] = (None, {"tetra": None})
    else:
        print("note: tetgen missing, bpm-mesh outputs not checked")

    def check(path):
        points, cells = expected[path]
        try:
            mesh = meshio.read(path)
        except Exception as e:  # the failure this test exists for
            return ["meshio.read failed: %s: %s" % (type(e).__name__, e)]
        problems = []
        # STL repeats a triangle's corners; meshio may or may not merge them.
        if points is not None and len(mesh.points) != points:
            problems.append("%d points, expected %d" % (len(mesh.points), points))
        got = {}
        for block in mesh.cells:
            got[block.type] = got.get(block.type, 0) + len(block.data)
        for kind, count in cells.items():
            if kind not in got:
                problems.append("no %s cells (got %s)" % (kind, got))
            elif count is not None and got[kind] != count:
                problems.append("%d %s cells, expected %d" % (got[kind], kind, count))
        if path.endswith(".msh"):
            for name, (tag, dim) in mesh.field_data.items():
                if tag < 1:
                    problems.append("physical group %s has tag %d (< 1)" % (name, tag))
        return problems

    return 1 if report(sorted(expected), check) else 0


if __name__ == "__main__":
    sys.exit(main())
