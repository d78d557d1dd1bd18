"""The Python module bpm (python/), run with pytest (ctest: python.module).

libbpm's phi through the module must agree with the independent spec reader
(tests/python/bpm_spec_reader.py, h5py + numpy only) on random points of real meshes, and
so must inverse phi (the spec reader's phi of the returned parameter points is the
original point); the arrays must be the file's datasets; bad input must raise the
documented exceptions with libbpm's messages; refine must give 4**K triangles per coarse
triangle; repair must move a solver's flat refined boundary onto S0 without inverting.

Environment (set by ctest; defaults for a run from the source tree after a build in build/):
  BPM_TOOLS   the built tools (build/bin)       BPM_MESHES  the real meshes (.data/meshes)
  BPM_WORK    a scratch directory               PYTHONPATH  must find the package (build/python)
"""
import json
import os
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

import bpm

HERE = Path(__file__).resolve().parent
SOURCE = HERE.parents[2]
sys.path.insert(0, str(HERE.parent))
import bpm_spec_reader as spec  # noqa: E402

TOOLS = Path(os.environ.get("BPM_TOOLS", SOURCE / "build" / "bin"))
MESHES = Path(os.environ.get("BPM_MESHES", SOURCE / ".data" / "meshes"))
WORK = Path(os.environ.get("BPM_WORK", SOURCE / "build" / "tests" / "work" / "python_module"))


def simplified(name):
    """The real mesh `name` simplified to 10 % by the built bpm-simplify (made once)."""
    WORK.mkdir(parents=True, exist_ok=True)
    out = WORK / f"{name}.bpm"
    if not out.exists():
        subprocess.run([str(TOOLS / "bpm-simplify"), str(MESHES / f"{name}.off"), "--ratio", "0.1",
                        "--deterministic", "-o", str(out)], check=True, stderr=subprocess.DEVNULL)
    return out


@pytest.fixture(scope="session")
def femur():
    return simplified("femur")


@pytest.fixture(scope="session")
def meshed_elephant():
    """The elephant at 10 % with a /tetmesh group (bpm-mesh, needs TetGen)."""
    out = WORK / "elephant_tet.bpm"
    if not out.exists():
        subprocess.run([str(TOOLS / "bpm-mesh"), str(simplified("elephant")), "-o", str(out)], check=True,
                       stderr=subprocess.DEVNULL)
    return out


def random_points(rng, num_triangles, count):
    """Random parameter points; a tenth on coarse edges and some at corners (where the
    pieces of neighbouring triangles meet)."""
    t = rng.integers(0, num_triangles, count).astype(np.int32)
    a, b = rng.random(count), rng.random(count)
    flip = a + b > 1
    a[flip], b[flip] = 1 - a[flip], 1 - b[flip]
    bary = np.stack([1 - a - b, a, b], axis=1)
    for i in range(count // 10):
        j, s = rng.integers(0, 3), rng.random()
        bary[i] = 0
        bary[i, j], bary[i, (j + 1) % 3] = 1 - s, s
    for i in range(count // 10, count // 10 + 10):
        bary[i] = 0
        bary[i, rng.integers(0, 3)] = 1
    return t, bary


def test_readme_example(femur):
    # README-BEGIN
    import numpy as np
    import bpm

    f = bpm.read(femur)                      # a .bpm file (bpm-simplify's output)
    print(f.coarse_vertices.shape, f.coarse_triangles.shape, f.original_vertices.shape)

    # phi at the centroid of every coarse triangle, on 2 threads
    t = np.arange(len(f.coarse_triangles), dtype=np.int32)
    b = np.full((len(t), 3), 1.0 / 3)
    x = f.phi(t, b, threads=2)               # (k, 3) points on the original surface
    s = f.phi_samples(t, b)                  # + normals, original triangle and barycentric
    t2, b2 = f.phi_inverse(s["original_triangles"], s["original_barycentrics"])  # back to S
    v, tri = f.refine(levels=2)              # the coarse surface refined onto S0
    # README-END
    assert x.shape == (len(t), 3) and np.isfinite(x).all()
    lo, hi = f.original_vertices.min(axis=0), f.original_vertices.max(axis=0)
    assert (x >= lo - 1e-9).all() and (x <= hi + 1e-9).all()
    assert np.array_equal(s["positions"], x)
    assert np.abs(f.phi(t2, b2) - x).max() <= 1e-9
    assert len(tri) == 16 * len(f.coarse_triangles)


@pytest.mark.parametrize("name", ["femur", "elephant"])
def test_phi_agrees_with_the_spec_reader(name):
    path = simplified(name)
    f = bpm.read(path)
    d = spec.read(path)
    rng = np.random.default_rng(17)
    t, b = random_points(rng, len(d["coarse/triangles"]), 3000)
    pos, otri, obary, normal = spec.evaluate(d, t, b)
    scale = float(np.linalg.norm(d["original/vertices"].max(axis=0) - d["original/vertices"].min(axis=0)))
    tol = 1e-12 * max(1.0, scale)

    x = f.phi(t, b)
    assert np.abs(x - pos).max() <= tol
    s = f.phi_samples(t, b, threads=2)
    assert np.array_equal(s["positions"], x)  # the two calls, and 1 or 2 threads, agree exactly
    same = s["original_triangles"] == otri
    # On a piece boundary the two may pick different, equally right original triangles.
    assert same.mean() > 0.95
    assert np.abs(s["original_barycentrics"][same] - obary[same]).max() <= 1e-9
    assert np.abs(s["normals"][same] - normal[same]).max() <= 1e-9
    # Every answer reproduces its point from its own original triangle.
    X, T0 = d["original/vertices"], d["original/triangles"]
    rebuilt = np.einsum("qk,qkd->qd", s["original_barycentrics"], X[T0[s["original_triangles"]]])
    assert np.abs(rebuilt - x).max() <= 1e-9 * max(1.0, scale)


def test_arrays_are_the_file_datasets(femur):
    f = bpm.read(str(femur))
    d = spec.read(femur)
    for attr, key, dtype in [("coarse_vertices", "coarse/vertices", np.float64),
                             ("coarse_triangles", "coarse/triangles", np.int32),
                             ("original_vertices", "original/vertices", np.float64),
                             ("original_triangles", "original/triangles", np.int32),
                             ("patches", "coarse/patches", np.int32),
                             ("coarse_patches", "coarse/patches", np.int32),
                             ("original_patches", "original/patches", np.int32),
                             ("coarse_vertex_origin", "coarse/vertex_origin", np.int32)]:
        a = getattr(f, attr)
        assert a.dtype == dtype, attr
        assert np.array_equal(a, d[key]), attr
        assert not a.flags.writeable, attr
    assert not f.has_tetmesh
    for attr in ("tet_vertices", "tet_tetrahedra", "tet_regions", "tet_faces", "tet_face_coarse_triangle",
                 "tet_vertex_parameter_triangle", "tet_vertex_parameter_barycentric"):
        assert getattr(f, attr) is None, attr


def test_tetmesh_arrays_are_the_file_datasets(meshed_elephant):
    f = bpm.read(meshed_elephant)
    assert f.has_tetmesh
    with h5py.File(meshed_elephant, "r") as h:
        for attr, name in [("tet_vertices", "vertices"), ("tet_tetrahedra", "tetrahedra"),
                           ("tet_regions", "regions"), ("tet_faces", "faces"),
                           ("tet_face_coarse_triangle", "face_coarse_triangle"),
                           ("tet_vertex_parameter_triangle", "vertex_parameter_triangle"),
                           ("tet_vertex_parameter_barycentric", "vertex_parameter_barycentric")]:
            assert np.array_equal(getattr(f, attr), h["tetmesh/" + name][()]), attr
    # The boundary vertices' parameter points, through phi, are where the tet mesh has them
    # (level 0: the coarse vertices themselves, which phi keeps fixed).
    on_s = f.tet_vertex_parameter_triangle >= 0
    x = f.phi(f.tet_vertex_parameter_triangle[on_s], f.tet_vertex_parameter_barycentric[on_s])
    assert np.abs(x - f.tet_vertices[on_s]).max() <= 1e-9


@pytest.mark.parametrize("name", ["femur", "elephant"])
def test_inverse_phi_agrees_with_the_spec_reader(name):
    path = simplified(name)
    f = bpm.read(path)
    d = spec.read(path)
    X, T0 = d["original/vertices"], d["original/triangles"]
    scale = max(1.0, float(np.linalg.norm(X.max(axis=0) - X.min(axis=0))))
    rng = np.random.default_rng(23)
    # Random points of S0 as (original triangle, barycentric), corners and edges included.
    ot, ob = random_points(rng, len(T0), 3000)
    target = np.einsum("qk,qkd->qd", ob, X[T0[ot]])
    t, b = f.phi_inverse(ot, ob, threads=2)
    assert t.dtype == np.int32 and t.shape == (3000,) and b.shape == (3000, 3)
    assert (t >= 0).all() and (t < len(d["coarse/triangles"])).all()
    assert np.abs(b.sum(axis=1) - 1).max() <= 1e-12 and (b >= -1e-12).all()
    pos, _, _, _ = spec.evaluate(d, t, b)  # phi of the answer, by the independent reader
    assert np.abs(pos - target).max() <= 1e-9 * scale
    # Positions: points of S0 pushed off along the normal come back to their foot point,
    # except where another part of S0 is nearer (concave edges): never farther than that.
    s = f.phi_samples(*random_points(rng, len(d["coarse/triangles"]), 500))
    offset = 1e-4 * scale
    r = f.phi_inverse_positions(s["positions"] + offset * s["normals"])
    assert (r["distances"] <= offset * (1 + 1e-9)).all()
    back = np.linalg.norm(r["feet"] - s["positions"], axis=1) <= 1e-6 * offset
    assert back.mean() > 0.9
    assert np.abs(r["distances"][back] - offset).max() <= 1e-6 * offset
    pos, _, _, _ = spec.evaluate(d, r["triangles"], r["barycentrics"])
    assert np.abs(pos - r["feet"]).max() <= 1e-9 * scale


def test_inverse_phi_errors(femur):
    f = bpm.read(femur)
    n0 = len(f.original_triangles)
    b = np.full((1, 3), 1.0 / 3)
    with pytest.raises(ValueError, match=r"original_triangles\[0\] = %d is not an original triangle" % n0):
        f.phi_inverse([n0], b)
    with pytest.raises(ValueError, match=r"original_barycentrics must have shape \(1, 3\)"):
        f.phi_inverse([0], np.ones((1, 2)))
    with pytest.raises(ValueError, match="not finite"):
        f.phi_inverse_positions([[0.0, np.inf, 0.0]])
    # Squared distances from here overflow: this crashed (segfault) instead of raising.
    with pytest.raises(ValueError, match="too far from the original surface"):
        f.phi_inverse_positions([[1e300, 0.0, 0.0]])
    far = f.phi_inverse_positions([[1e100, 0.0, 0.0]])
    assert 0 <= far["triangles"][0] < len(f.coarse_triangles)
    assert 0 <= far["original_triangles"][0] < n0


def test_repair_moves_a_flat_refined_boundary_onto_the_original_surface():
    """bpm-mesh --refine 1 --no-smooth gives a level-1 mesh with every vertex's parameter
    point; putting its new boundary vertices back on the flat coarse surface (where a
    solver's red refinement leaves them) and calling repair must bring them to phi or hold
    them back on their segment, with no tetrahedron inverted."""
    out = WORK / "elephant_tet1.bpm"
    if not out.exists():
        subprocess.run([str(TOOLS / "bpm-mesh"), str(simplified("elephant")), "--refine", "1", "--no-smooth",
                        "-o", str(out)], check=True, stderr=subprocess.DEVNULL)
    f = bpm.read(out)
    pt, pb = f.tet_vertex_parameter_triangle, f.tet_vertex_parameter_barycentric
    with h5py.File(out, "r") as h:
        coarse_vertex = h["tetmesh/vertex_coarse_vertex"][()]
    new_on_s = (pt >= 0) & (coarse_vertex < 0)
    assert new_on_s.sum() > 100
    flat = f.tet_vertices.copy()
    C, T = f.coarse_vertices, f.coarse_triangles
    flat[new_on_s] = np.einsum("qk,qkd->qd", pb[new_on_s], C[T[pt[new_on_s]]])
    at_phi = f.phi(pt[new_on_s], pb[new_on_s])

    x, r = f.repair(flat, f.tet_tetrahedra, pt, pb)
    assert r["boundary_vertices"] == (pt >= 0).sum()
    assert r["at_phi"] + r["held_back"] == r["boundary_vertices"]
    assert r["inverted_before"] == 0 and r["inverted_after"] == 0
    assert r["at_phi"] > r["at_phi_before"]
    before = np.linalg.norm(flat[new_on_s] - at_phi, axis=1)
    after = np.linalg.norm(x[new_on_s] - at_phi, axis=1)
    assert (after <= before + 1e-12).all() and after.sum() < 0.5 * before.sum()
    assert np.isclose(after.max(), r["max_distance"])
    d = np.linalg.det(np.stack([x[f.tet_tetrahedra[:, k]] - x[f.tet_tetrahedra[:, 0]] for k in (1, 2, 3)], axis=1))
    assert (d > 0).all()
    # Without the widening pass (bpm/boundary_repair.h step 4) nothing inverts either, and
    # the smallest angle is no larger than with it.
    x2, r2 = f.repair(flat, f.tet_tetrahedra, pt, pb, widen=False)
    assert r2["inverted_after"] == 0 and r2["min_dihedral_degrees"] <= r["min_dihedral_degrees"] + 1e-12
    assert r2["widened"] == 0 and 0 <= r["widened"] <= r["boundary_vertices"]

    with pytest.raises(ValueError, match=r"tetrahedra\[0, 2\] = %d is not a vertex" % len(x)):
        bad = f.tet_tetrahedra.copy()
        bad[0, 2] = len(x)
        f.repair(flat, bad, pt, pb)
    with pytest.raises(ValueError, match="one entry per vertex"):
        f.repair(flat, f.tet_tetrahedra, pt[:-1], pb[:-1])
    with pytest.raises(bpm.OptionError):
        f.repair(flat, f.tet_tetrahedra, pt, pb, boundary_steps=0)


def test_repair_slides_and_returns_the_new_parameter_points():
    """repair slides (bpm/boundary_repair.h step 6, slide=True by default): a boundary vertex
    next to a tetrahedron below min_dihedral_degrees moves along S0, to phi of a new parameter
    point in the same coarse triangle with the same zero coordinates, where that widens the
    worst tetrahedron around it. The dict returns the points after the slide (before, repair
    did not slide: a caller could not have kept the new points)."""
    out = WORK / "elephant_tet1.bpm"
    if not out.exists():
        subprocess.run([str(TOOLS / "bpm-mesh"), str(simplified("elephant")), "--refine", "1", "--no-smooth",
                        "-o", str(out)], check=True, stderr=subprocess.DEVNULL)
    f = bpm.read(out)
    pt, pb = f.tet_vertex_parameter_triangle, f.tet_vertex_parameter_barycentric
    with h5py.File(out, "r") as h:
        coarse_vertex = h["tetmesh/vertex_coarse_vertex"][()]
    new_on_s = (pt >= 0) & (coarse_vertex < 0)
    flat = f.tet_vertices.copy()
    C, T = f.coarse_vertices, f.coarse_triangles
    flat[new_on_s] = np.einsum("qk,qkd->qd", pb[new_on_s], C[T[pt[new_on_s]]])
    tets = f.tet_tetrahedra
    bound = 15.0  # many tetrahedra next to S0 are thinner

    x0, r0 = f.repair(flat, tets, pt, pb, min_dihedral_degrees=bound, slide=False)
    x1, r1 = f.repair(flat, tets, pt, pb, min_dihedral_degrees=bound)
    assert r0["slid"] == 0
    assert np.array_equal(r0["parameter_triangles"], pt) and np.array_equal(r0["parameter_barycentrics"], pb)
    assert r1["slid"] > 0
    assert r1["inverted_after"] == 0
    assert r1["min_dihedral_degrees"] >= r0["min_dihedral_degrees"]
    t1, b1 = r1["parameter_triangles"], r1["parameter_barycentrics"]
    assert t1.shape == pt.shape and b1.shape == pb.shape
    changed = np.flatnonzero(np.any(b1 != pb, axis=1) | (t1 != pt))
    assert len(changed) == r1["slid"]
    # Same coarse triangle, same zero coordinates (a vertex on a coarse edge stays on it),
    # coarse vertices and interior vertices keep theirs, barycentrics sum to 1.
    assert np.array_equal(t1, pt)
    assert np.array_equal(b1[changed] == 0, pb[changed] == 0)
    assert (coarse_vertex[changed] < 0).all() and (pt[changed] >= 0).all()
    assert np.allclose(b1.sum(axis=1)[pt >= 0], 1.0, atol=1e-12) and (b1 >= 0).all()
    # A slid vertex at phi is at phi of its new point.
    at_phi = np.linalg.norm(x1[changed] - f.phi(t1[changed], b1[changed]), axis=1) < 1e-12
    assert at_phi.any()
    d = np.linalg.det(np.stack([x1[tets[:, k]] - x1[tets[:, 0]] for k in (1, 2, 3)], axis=1))
    assert (d > 0).all()


def test_repair_with_plain_positions_retreats_towards_them():
    """repair(..., plain_positions) adds the retreat (bpm/boundary_repair.h step 5): a
    boundary vertex next to a tetrahedron below min_dihedral_degrees moves back from phi
    towards where the solver's plain refinement put it (here the flat level-1 mesh of the
    test above) where that widens the worst tetrahedron around it. It never lowers the
    smallest angle, inverts nothing, and without plain positions (or with retreat=False)
    nothing retreats."""
    out = WORK / "elephant_tet1.bpm"
    if not out.exists():
        subprocess.run([str(TOOLS / "bpm-mesh"), str(simplified("elephant")), "--refine", "1", "--no-smooth",
                        "-o", str(out)], check=True, stderr=subprocess.DEVNULL)
    f = bpm.read(out)
    pt, pb = f.tet_vertex_parameter_triangle, f.tet_vertex_parameter_barycentric
    with h5py.File(out, "r") as h:
        coarse_vertex = h["tetmesh/vertex_coarse_vertex"][()]
    new_on_s = (pt >= 0) & (coarse_vertex < 0)
    flat = f.tet_vertices.copy()
    C, T = f.coarse_vertices, f.coarse_triangles
    flat[new_on_s] = np.einsum("qk,qkd->qd", pb[new_on_s], C[T[pt[new_on_s]]])
    tets = f.tet_tetrahedra
    bound = 15.0  # many tetrahedra next to S0 are thinner

    # Without the slide (step 6), which would start from different places on the two paths
    # and may end lower on either: the retreat's own guarantee is what is tested here.
    x0, r0 = f.repair(flat, tets, pt, pb, min_dihedral_degrees=bound, slide=False)
    x1, r1 = f.repair(flat, tets, pt, pb, flat, min_dihedral_degrees=bound, slide=False)
    assert r0["retreated"] == 0
    assert r1["retreated"] > 0
    assert r1["inverted_after"] == 0
    assert r1["min_dihedral_degrees"] >= r0["min_dihedral_degrees"]
    assert r1["held_back"] >= r0["held_back"]
    assert r1["at_phi"] + r1["held_back"] == r1["boundary_vertices"]
    # Retreated vertices lie between where steps 1-4 left them (x0) and their plain
    # positions: closer to the latter.
    moved = np.flatnonzero((pt >= 0) & np.any(x1 != x0, axis=1))
    assert len(moved) >= r1["retreated"]
    closer = np.linalg.norm(x1[moved] - flat[moved], axis=1) < np.linalg.norm(x0[moved] - flat[moved], axis=1)
    assert closer.sum() >= r1["retreated"]
    d = np.linalg.det(np.stack([x1[tets[:, k]] - x1[tets[:, 0]] for k in (1, 2, 3)], axis=1))
    assert (d > 0).all()
    # The same as a keyword; None and retreat=False are the repair without it.
    x2, r2 = f.repair(flat, tets, pt, pb, plain_positions=flat, min_dihedral_degrees=bound, slide=False)
    assert np.array_equal(x2, x1) and r2["retreated"] == r1["retreated"]
    x3, r3 = f.repair(flat, tets, pt, pb, plain_positions=None, min_dihedral_degrees=bound, slide=False)
    assert np.array_equal(x3, x0)
    x4, r4 = f.repair(flat, tets, pt, pb, flat, min_dihedral_degrees=bound, retreat=False, slide=False)
    assert np.array_equal(x4, x0) and r4["retreated"] == 0

    with pytest.raises(ValueError, match=r"plain_positions must have shape \(%d, 3\)" % len(flat)):
        f.repair(flat, tets, pt, pb, flat[:-1])
    bad = flat.copy()
    bad[3, 1] = np.nan
    with pytest.raises(ValueError, match=r"plain_positions\[3\] is not finite"):
        f.repair(flat, tets, pt, pb, bad)


@pytest.mark.parametrize("levels", [0, 1, 2])
def test_refine_counts(femur, levels):
    f = bpm.read(femur)
    v, t = f.refine(levels=levels)
    m, n = len(f.coarse_triangles), len(f.coarse_vertices)
    assert t.shape == (m * 4 ** levels, 3) and t.dtype == np.int32
    # A closed surface keeps its Euler characteristic: V - E + F with E = 3F/2.
    assert len(v) - 3 * len(t) // 2 + len(t) == n - 3 * m // 2 + m
    assert t.min() == 0 and t.max() == len(v) - 1
    if levels == 0:
        assert np.array_equal(v, f.coarse_vertices)


def test_missing_file_is_an_input_error_naming_it(tmp_path):
    path = str(tmp_path / "missing.bpm")
    with pytest.raises(bpm.InputError) as e:
        bpm.read(path)
    assert isinstance(e.value, OSError) and isinstance(e.value, bpm.Error)
    assert str(e.value).startswith(path + ": ")


def test_file_that_is_not_hdf5_is_an_input_error(tmp_path):
    path = tmp_path / "not.bpm"
    path.write_text("OFF\n0 0 0\n")
    with pytest.raises(bpm.InputError, match="not.bpm"):
        bpm.read(str(path))


def test_bad_queries_are_value_errors(femur):
    f = bpm.read(femur)
    m = len(f.coarse_triangles)
    b = np.full((2, 3), 1.0 / 3)
    with pytest.raises(ValueError, match=r"triangles\[1\] = %d is not a coarse triangle" % m):
        f.phi(np.array([0, m]), b)
    with pytest.raises(ValueError, match="is not a coarse triangle"):
        f.phi_samples(np.array([-1, 0]), b)
    with pytest.raises(ValueError, match=r"shape \(2, 3\)"):
        f.phi(np.array([0, 1]), np.ones((3, 3)) / 3)
    with pytest.raises(ValueError, match="1-D"):
        f.phi(np.zeros((2, 1), dtype=np.int32), b)
    with pytest.raises(ValueError, match="integers"):
        f.phi(np.array([0.0, 1.5]), b)
    with pytest.raises(ValueError, match="not finite"):
        f.phi(np.array([0, 1]), np.array([[np.nan, 0, 1], [1, 0, 0]]))
    with pytest.raises(ValueError, match="threads"):
        f.phi(np.array([0, 1]), b, threads=-1)
    # Coordinates that are not a point of the triangle: phi extrapolated them to points off
    # the surface ((0.2, 0.2, 0.2) did not sum to 1; (0.5, 0.6, -0.1) is outside).
    with pytest.raises(ValueError, match=r"barycentrics\[1\] = \(0.2, 0.2, 0.2.*is not a point of the triangle"):
        f.phi(np.array([0, 1]), np.array([[1.0, 0, 0], [0.2, 0.2, 0.2]]))
    with pytest.raises(ValueError, match="is not a point of the triangle"):
        f.phi_samples(np.array([0]), np.array([[0.5, 0.6, -0.1]]))
    with pytest.raises(ValueError, match=r"original_barycentrics\[0\] = .* is not a point of the triangle"):
        f.phi_inverse(np.array([0]), np.array([[2.0, 2.0, 2.0]]))
    # Rounding is fine: a caller's 1 - a - b may be a few ulps off.
    assert f.phi(np.array([0]), np.array([[1 + 1e-12, -1e-12, 0.0]])).shape == (1, 3)
    assert f.phi(np.zeros(0, dtype=np.int32), np.zeros((0, 3))).shape == (0, 3)
    # Lists are arrays too.
    assert np.array_equal(f.phi([0, 1], b.tolist()), f.phi(np.array([0, 1]), b))


def test_refine_options_are_option_errors_with_libbpm_messages(femur):
    f = bpm.read(femur)
    with pytest.raises(bpm.OptionError) as e:
        f.refine()  # neither levels nor tolerance
    assert isinstance(e.value, ValueError)
    with pytest.raises(bpm.OptionError):
        f.refine(levels=11)
    # Both kinds at once: the tolerance was dropped silently (uniform refinement won);
    # bpm-refine refuses --levels with --max-error or --max-level.
    with pytest.raises(bpm.OptionError, match=r"give levels \(uniform\) or tolerance \(adaptive\), not both; "
                                              r"got levels 2 and tolerance 0.001$"):
        f.refine(levels=2, tolerance=1e-3)
    with pytest.raises(bpm.OptionError, match=r"give levels or max_level, not both; got levels 1 and max_level 3$"):
        f.refine(levels=1, max_level=3)
    v, t = f.refine(tolerance=3e-3, max_level=2)
    assert len(t) > 0


def read_off(path):
    """Vertices (n, 3) and triangles (m, 3) of an OFF file of triangles."""
    t = Path(path).read_text().split()
    nv, nt = int(t[1]), int(t[2])
    v = np.array(t[4:4 + 3 * nv], dtype=float).reshape(-1, 3)
    f = np.array(t[4 + 3 * nv:4 + 3 * nv + 4 * nt], dtype=np.int64).reshape(-1, 4)
    assert (f[:, 0] == 3).all()
    return v, f[:, 1:]


@pytest.mark.parametrize("name", ["femur", "fandisk"])
def test_simplify_from_arrays_is_the_tools_result(name, tmp_path):
    """bpm.simplify on the arrays of a real mesh gives bpm-simplify's coarse surface and phi,
    on any thread count; File.write writes it; the report says what was reached."""
    vertices, triangles = read_off(MESHES / f"{name}.off")
    made = bpm.simplify(vertices, triangles, ratio=0.1, threads=1)
    tool = bpm.read(simplified(name))
    for key in ("coarse_vertices", "coarse_triangles", "coarse_patches", "coarse_vertex_origin",
                "original_vertices", "original_triangles"):
        assert np.array_equal(getattr(made, key), getattr(tool, key)), key
    rng = np.random.default_rng(7)
    t, b = random_points(rng, len(made.coarse_triangles), 500)
    assert np.array_equal(made.phi(t, b), tool.phi(t, b))
    assert np.array_equal(bpm.simplify(vertices, triangles, ratio=0.1, threads=2).coarse_vertices, made.coarse_vertices)
    report = made.simplify_report
    assert report["input_vertices"] == len(vertices) and report["output_vertices"] == len(made.coarse_vertices)
    assert report["target_reached"] and 0 < report["max_error"] < 0.05
    assert tool.simplify_report is None
    out = tmp_path / "made.bpm"
    made.write(out)
    assert made.path == str(out)
    back = bpm.read(out)
    assert np.array_equal(back.coarse_triangles, made.coarse_triangles)
    with h5py.File(out, "r") as f:
        assert f["provenance/tool"][0].decode() == "bpm (Python)"
        assert "ratio=0.10000000000000001" in f["provenance/arguments"][0].decode()


def test_repair_self_intersections_then_simplify():
    """bull.off crosses itself in 3 places: bpm.simplify refuses it, bpm.repair_self_intersections
    repairs it as bpm-simplify --repair-self-intersections does (kept vertices and triangles
    first, unchanged), and the repaired arrays simplify; a clean surface comes back as it was;
    max_change refuses a repair that moves the surface too far."""
    vertices, triangles = read_off(MESHES / "bull.off")
    with pytest.raises(bpm.AlgorithmError, match="repair_self_intersections"):
        bpm.simplify(vertices, triangles, ratio=0.1)
    v, t, p, report = bpm.repair_self_intersections(vertices, triangles)
    assert report["intersecting_pairs"] == 3 and report["remaining_pairs"] == 0 and report["refused"] == ""
    assert report["removed_triangles"] == 4 and len(t) == len(triangles) - 4 + report["added_triangles"]
    assert 0 < report["largest_change"] < 0.01 and report["topology_change"] == ""
    kept = len(v) - report["added_vertices"]
    assert np.array_equal(v[:kept], vertices[:kept]) and (p == 0).all()
    made = bpm.simplify(v, t, p, ratio=0.1)
    assert np.array_equal(made.original_triangles, t)
    clean_v, clean_t = read_off(MESHES / "femur.off")
    v2, t2, _, report2 = bpm.repair_self_intersections(clean_v, clean_t)
    assert report2["intersecting_pairs"] == 0 and np.array_equal(v2, clean_v) and np.array_equal(t2, clean_t)
    _, t3, _, report3 = bpm.repair_self_intersections(vertices, triangles, max_change=1e-5)
    assert "max_change" in report3["refused"] and np.array_equal(t3, triangles)
    with pytest.raises(ValueError, match="max_change"):
        bpm.repair_self_intersections(vertices, triangles, max_change=0)


def test_simplify_keeps_patches_and_targets():
    """Patches given per triangle stay the original's and the coarse surface's; a vertex
    target is met."""
    vertices, triangles = read_off(MESHES / "femur.off")
    patches = (vertices[triangles].mean(axis=1)[:, 2] > np.median(vertices[:, 2])).astype(np.int32) + 4
    made = bpm.simplify(vertices, triangles, patches, target_vertices=1000)
    assert np.array_equal(made.original_patches, patches)
    assert set(np.unique(made.coarse_patches)) == {4, 5}
    assert len(made.coarse_vertices) == 1000


def test_simplify_refuses_bad_arrays_and_surfaces():
    """Bad shapes, indices and surfaces bpm-simplify would refuse are ValueErrors that say
    what is wrong; a surface that intersects itself is an AlgorithmError."""
    vertices, triangles = read_off(MESHES / "elephant.off")
    with pytest.raises(ValueError, match=r"vertices must have shape \(n, 3\)"):
        bpm.simplify(vertices[:, :2], triangles, ratio=0.1)
    with pytest.raises(ValueError, match=r"triangles\[0, 1\] = %d is not a vertex" % len(vertices)):
        bad = triangles.copy()
        bad[0, 1] = len(vertices)
        bpm.simplify(vertices, bad, ratio=0.1)
    with pytest.raises(ValueError, match="give a target"):
        bpm.simplify(vertices, triangles)
    with pytest.raises(ValueError, match="patches must have one entry per triangle"):
        bpm.simplify(vertices, triangles, np.zeros(3, dtype=np.int32), ratio=0.1)
    with pytest.raises(ValueError, match="zero area"):
        flat = vertices.copy()
        a, b, c = triangles[0]
        flat[a], flat[b], flat[c] = (0.0, 0.0, 0.0), (2.0, 2.0, 2.0), (1.0, 1.0, 1.0)  # exactly collinear
        bpm.simplify(flat, triangles, ratio=0.1)
    with pytest.raises(ValueError, match="not used by any triangle"):
        bpm.simplify(np.vstack([vertices, [[9.0, 9.0, 9.0]]]), triangles, ratio=0.1)
    shifted = vertices + np.array([0.3 * np.ptp(vertices[:, 0]), 0.0, 0.0])
    both_v = np.vstack([vertices, shifted])
    both_t = np.vstack([triangles, triangles + len(vertices)])
    with pytest.raises(bpm.AlgorithmError, match="intersects itself"):
        bpm.simplify(both_v, both_t, ratio=0.1)


def test_write_to_a_missing_directory_is_an_output_error(tmp_path):
    vertices, triangles = read_off(MESHES / "elephant.off")
    made = bpm.simplify(vertices, triangles, target_vertices=500)
    with pytest.raises(bpm.OutputError, match="no-such-dir"):
        made.write(tmp_path / "no-such-dir" / "x.bpm")
    assert made.path == "<memory>"
    # An HDF5 file named coarse.off (written silently before) is refused; other names pass.
    for name in ("coarse.off", "coarse.STL", "mesh.vtu"):
        with pytest.raises(bpm.OptionError, match=r"File.write writes .bpm \(HDF5\) files"):
            made.write(tmp_path / name)
        assert not (tmp_path / name).exists()
    made.write(tmp_path / "coarse.h5")
    assert bpm.read(tmp_path / "coarse.h5").coarse_triangles.shape == made.coarse_triangles.shape


def test_simplify_reports_progress_and_stops_on_request():
    """progress(fraction, stage) sees increasing fractions up to 1; an exception raised there,
    a False returned and Ctrl-C (a pending KeyboardInterrupt, set by _thread.interrupt_main)
    each stop the run at the next report, not after it."""
    import _thread
    femur_v, femur_t = read_off(MESHES / "femur.off")
    seen = []
    bpm.simplify(femur_v, femur_t, ratio=0.1, progress=lambda f, stage: seen.append(f))
    assert seen == sorted(seen) and seen[-1] == 1.0 and len(seen) > 5
    vertices, triangles = read_off(MESHES / "elephant.off")

    class Stop(Exception):
        pass

    def stop_at(fraction, action):
        calls = []

        def progress(f, stage):
            calls.append(f)
            if f >= fraction:
                return action()
        return calls, progress

    def raise_stop():
        raise Stop()

    for action, expected in ((raise_stop, Stop), (lambda: False, bpm.Error),
                             (lambda: _thread.interrupt_main(), KeyboardInterrupt)):
        calls, progress = stop_at(0.3, action)
        with pytest.raises(expected):
            bpm.simplify(vertices, triangles, target_vertices=500, progress=progress)
        stopped = [f for f in calls if f >= 0.3]
        # The run ends at the report that asked (Ctrl-C: at the one after it).
        assert len(stopped) <= (2 if expected is KeyboardInterrupt else 1), (action, calls)
        assert calls[-1] < 1.0
    assert len(bpm.simplify(vertices, triangles, target_vertices=500).coarse_vertices) == 500
    # A stop asked for at the very first report, inside the first ranking's round of the
    # planning pool on 2 threads (whose caller goes on taking tasks after one failed): the
    # callback is not called again, and its own exception is raised.
    for action, expected in ((raise_stop, Stop), (lambda: False, bpm.Error)):
        stages = []

        def progress(f, stage):
            stages.append(stage)
            if stage.startswith("evaluating vertices"):
                return action()
        with pytest.raises(expected):
            bpm.simplify(vertices, triangles, target_vertices=500, threads=2, progress=progress)
        assert sum(stage.startswith("evaluating vertices") for stage in stages) == 1, stages

    def not_a_truth(f, stage):
        return np.zeros(3)  # its truth value raises ValueError
    with pytest.raises(ValueError, match="truth value"):
        bpm.simplify(vertices, triangles, target_vertices=500, progress=not_a_truth)


def test_warnings_are_python_warnings_and_patch_ids_any_int32():
    """bpm-mesh's warning about a thin coarse triangle is a UserWarning from File.mesh; the
    largest int32 is a patch id."""
    femur_v, femur_t = read_off(MESHES / "femur.off")
    thin = bpm.simplify(femur_v, femur_t, ratio=0.1, max_aspect=500)  # worst R/r 92.8
    assert thin.simplify_report["worst_aspect_ratio"] > 30
    with pytest.warns(UserWarning, match="has aspect ratio"):
        thin.mesh()
    vertices, triangles = read_off(MESHES / "elephant.off")
    patches = np.full(len(triangles), 2**31 - 1, dtype=np.int64)
    assert (bpm.simplify(vertices, triangles, patches, target_vertices=500).coarse_patches == 2**31 - 1).all()
    with pytest.raises(ValueError, match="is not a patch id"):
        bpm.simplify(vertices, triangles, patches + 1, target_vertices=500)
    with pytest.raises(ValueError, match="0 = as bpm-simplify chooses"):
        bpm.simplify(vertices, triangles, target_vertices=500, threads=-1)


def test_mesh_is_the_tools_mesh(femur, tmp_path):
    """File.mesh gives bpm-mesh's tet mesh of the same file, with the materials its patches
    name; a file made by bpm.simplify meshes too; progress and a stop work as in simplify."""
    out = tmp_path / "femur_tet.bpm"
    subprocess.run([str(TOOLS / "bpm-mesh"), str(femur), "-o", str(out)], check=True, stderr=subprocess.DEVNULL)
    tool = bpm.read(out)
    seen = []
    meshed = bpm.read(femur).mesh(progress=lambda f, stage: seen.append(f))
    assert seen and seen[-1] <= 1.0
    for key in ("tet_vertices", "tet_tetrahedra", "tet_regions", "tet_faces", "tet_face_coarse_triangle",
                "tet_vertex_parameter_triangle", "tet_vertex_parameter_barycentric", "tet_region_material"):
        assert np.array_equal(getattr(meshed, key), getattr(tool, key)), key
    assert meshed.material_names == tool.material_names == ["femur"]
    assert bpm.read(femur).material_names == [] and bpm.read(femur).tet_region_material is None
    meshed.write(tmp_path / "again.bpm")
    assert np.array_equal(bpm.read(tmp_path / "again.bpm").tet_tetrahedra, tool.tet_tetrahedra)
    vertices, triangles = read_off(MESHES / "elephant.off")
    made = bpm.simplify(vertices, triangles, ratio=0.1).mesh()
    assert made.has_tetmesh and len(made.tet_tetrahedra) > 0 and made.material_names == ["region_1"]

    def stop(f, stage):
        return False
    with pytest.raises(bpm.Error, match="cancelled"):
        bpm.read(femur).mesh(progress=stop)


def test_refine_mesh_is_the_tools_refinement(femur, tmp_path):
    """File.refine_mesh(1) gives bpm-mesh --existing --refine 1's tet mesh of the same file;
    a file without a tet mesh and bad levels are ValueErrors."""
    meshed = tmp_path / "femur_tet.bpm"
    refined = tmp_path / "femur_tet1.bpm"
    subprocess.run([str(TOOLS / "bpm-mesh"), str(femur), "-o", str(meshed)], check=True, stderr=subprocess.DEVNULL)
    subprocess.run([str(TOOLS / "bpm-mesh"), str(meshed), "--existing", "--refine", "1", "-o", str(refined)],
                   check=True, stderr=subprocess.DEVNULL)
    tool = bpm.read(refined)
    mine = bpm.read(meshed).refine_mesh(1)
    assert len(mine.tet_tetrahedra) >= 8 * len(bpm.read(meshed).tet_tetrahedra)  # + insertions into slivers
    for key in ("tet_vertices", "tet_tetrahedra", "tet_regions", "tet_faces", "tet_vertex_parameter_triangle",
                "tet_vertex_parameter_barycentric", "tet_region_material"):
        assert np.array_equal(getattr(mine, key), getattr(tool, key)), key
    flat = bpm.read(meshed).refine_mesh(1, flat=True)
    assert not np.array_equal(flat.tet_vertices, mine.tet_vertices)
    with pytest.raises(ValueError, match="no tet mesh"):
        bpm.read(femur).refine_mesh(1)
    with pytest.raises(ValueError, match="levels must be in 0..8"):
        bpm.read(meshed).refine_mesh(9)


def test_smooth_is_the_tools_smoothing(femur, tmp_path):
    """File.smooth gives bpm-smooth's phi of the same file (the datasets of /phi equal), the
    same coarse surface; bad options are OptionErrors."""
    out = tmp_path / "femur_smooth.bpm"
    subprocess.run([str(TOOLS / "bpm-smooth"), str(femur), "-o", str(out), "-q"], check=True)
    mine = tmp_path / "mine.bpm"
    smoothed = bpm.read(femur).smooth()
    smoothed.write(mine)
    with h5py.File(out, "r") as a, h5py.File(mine, "r") as b:
        for name in a["phi"]:
            assert np.array_equal(a["phi"][name][()], b["phi"][name][()], equal_nan=True), name
    assert np.array_equal(smoothed.coarse_vertices, bpm.read(femur).coarse_vertices)
    rng = np.random.default_rng(3)
    t, b = random_points(rng, len(smoothed.coarse_triangles), 300)
    assert not np.array_equal(smoothed.phi(t, b), bpm.read(femur).phi(t, b))  # phi moved
    with pytest.raises(bpm.OptionError, match="iterations"):
        bpm.read(femur).smooth(iterations=-1)


def test_check_is_the_tools_report(femur, tmp_path):
    """File.check reports what bpm-check --json reports for the same file (the same checks,
    verdicts and counts); a file made in memory is checked before it is written; a
    distance gate too tight fails the distance check."""
    tool = json.loads(subprocess.run([str(TOOLS / "bpm-check"), "--json", str(femur)], check=True,
                                     capture_output=True, text=True).stdout)
    mine = bpm.read(femur).check()
    assert mine["passed"] and tool["passed"]
    assert [(c["name"], c["passed"], c.get("counts")) for c in mine["checks"]] == \
        [(c["name"], c["passed"], c.get("counts")) for c in tool["checks"]]
    vertices, triangles = read_off(MESHES / "elephant.off")
    made = bpm.simplify(vertices, triangles, target_vertices=500)
    assert made.check()["passed"]
    tight = made.check(max_distance=1e-6)
    assert not tight["passed"]
    assert [c["name"] for c in tight["checks"] if not c["passed"]] == ["distance"]


def test_option_errors_name_the_python_keywords(femur):
    """An option out of range names the keyword the caller wrote and the value given:
    simplify's errors named libbpm's fields (max_aspect_ratio, feature_angle_degrees) or
    lumped the three targets into one message; check() took a negative max_distance, a
    max_aspect below 2 or a min_angle above 60 and reported every triangle as failing,
    where bpm-check refuses the option."""
    vertices, triangles = read_off(MESHES / "elephant.off")
    for kwargs, message in [
            (dict(ratio=2.0), r"ratio must be in \[0, 1\] .*got 2$"),
            (dict(ratio=float("nan")), r"ratio must be in \[0, 1\] .*got nan$"),
            (dict(target_vertices=-5), r"target_vertices must be >= 0, got -5$"),
            (dict(max_error=-1.0), r"max_error must be >= 0 .*got -1$"),
            (dict(ratio=0.1, max_aspect=1.0), r"^max_aspect must be at least 2 .*got 1$"),
            (dict(ratio=0.1, feature_angle=500.0), r"^feature_angle must be between 0 and 180 .*got 500$")]:
        with pytest.raises(ValueError, match=message):
            bpm.simplify(vertices, triangles, **kwargs)
    f = bpm.read(femur)
    with pytest.raises(bpm.OptionError, match=r"^feature_angle must be between 0 and 180"):
        f.smooth(feature_angle=-1.0)
    for kwargs, message in [(dict(max_distance=-1.0), r"^max_distance must be a number >= 0"),
                            (dict(max_distance=float("inf")), r"^max_distance must be a number >= 0"),
                            (dict(max_aspect=0.5), r"^max_aspect must be at least 2"),
                            (dict(min_angle=100.0), r"^min_angle must be between 0 and 60")]:
        with pytest.raises(bpm.OptionError, match=message):
            f.check(**kwargs)
