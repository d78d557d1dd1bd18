#!/usr/bin/python3
"""Writes the corpus of malformed .bpm files next to this script, and EXPECTED.tsv.

Every file starts from the golden example spec/examples/two_triangles.bpm: either its
content rewritten with h5py (libver latest, no object timestamps, minimal object headers,
without the /VTKHDF view, which bpm readers ignore; about 7 KB a file) with one defect put
in, or its bytes with one defect put in (truncation, a corrupt HDF5 structure).
Deterministic: run it again and the files come out byte for byte the same (h5py 3.7 /
HDF5 1.10.8, Debian 12).

    /usr/bin/python3 tests/data/bad/bpm/make_bad_bpm.py

EXPECTED.tsv, one line per file (tests/cli/bad_input.sh reads it):
    file <TAB> bpm-check exit <TAB> other tools' exit <TAB> text the error message must contain
  * exit 3: unreadable or malformed; every tool that reads .bpm (bpm-check, bpm-smooth,
    bpm-refine, bpm-mesh) must exit 3 with one error line naming the file;
  * exit 1 (bpm-check only): the file reads (its structure is right) but a check fails,
    e.g. an image that is not the point its node names; the other tools then either work
    on it or refuse it (the column lists the allowed exit codes, e.g. "0,5"), but never
    crash, and bpm-check's failing check is named by the text column ("FAIL format").
  * "*" in the text column: any non-empty message.
"""
import collections
import ctypes
import os
import random
import shutil
import struct

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
GOLDEN = os.path.normpath(os.path.join(HERE, "..", "..", "..", "..", "spec", "examples", "two_triangles.bpm"))
ROWS = []  # (file name, check exit, other exits, expected text)


# ---- the model: the golden file as plain data ------------------------------------------


def load_model():
    """{'attrs': root attributes, 'items': path -> None (group) or ndarray, 'group_attrs': path -> {}}"""
    model = {"attrs": collections.OrderedDict(), "items": collections.OrderedDict(), "group_attrs": {}}
    with h5py.File(GOLDEN, "r") as f:
        for k, v in f.attrs.items():
            model["attrs"][k] = v

        def visit(name, obj):
            if name.startswith("VTKHDF"):
                return
            if isinstance(obj, h5py.Group):
                model["items"]["/" + name] = None
            else:
                model["items"]["/" + name] = obj[()]

        f.visititems(visit)
    return model


def copy_model(model):
    return {
        "attrs": collections.OrderedDict(model["attrs"]),
        "items": collections.OrderedDict((k, None if v is None else np.array(v)) for k, v in model["items"].items()),
        "group_attrs": {k: dict(v) for k, v in model["group_attrs"].items()},
    }


def write_model(path, model):
    """Writes the model deterministically (no timestamps, latest object formats)."""
    fcpl = h5py.h5p.create(h5py.h5p.FILE_CREATE)
    fcpl.set_obj_track_times(False)
    fapl = h5py.h5p.create(h5py.h5p.FILE_ACCESS)
    fapl.set_libver_bounds(h5py.h5f.LIBVER_LATEST, h5py.h5f.LIBVER_LATEST)
    fid = h5py.h5f.create(path.encode(), h5py.h5f.ACC_TRUNC, fcpl=fcpl, fapl=fapl)
    # Minimal dataset object headers (h5py does not expose this HDF5 1.10.5 call): files of
    # about 7 KB instead of 10 KB.
    try:
        ctypes.CDLL("libhdf5_serial.so.103").H5Fset_dset_no_attrs_hint(ctypes.c_int64(fid.id), ctypes.c_uint(1))
    except (OSError, AttributeError):
        pass
    with h5py.File(fid) as f:
        for k, v in model["attrs"].items():
            f.attrs[k] = v
        for p, data in model["items"].items():
            parent, name = p.rsplit("/", 1)
            g = f[parent] if parent else f
            if data is None:
                gcpl = h5py.h5p.create(h5py.h5p.GROUP_CREATE)
                gcpl.set_obj_track_times(False)
                h5py.h5g.create(g.id, name.encode(), gcpl=gcpl)
            elif isinstance(data, dict):  # {'shape':, 'dtype':, 'chunks':, 'compression':} without data
                g.create_dataset(name, shape=data["shape"], dtype=data["dtype"], chunks=data.get("chunks"),
                                 compression=data.get("compression"), maxshape=data.get("maxshape"),
                                 track_times=False)
            else:
                g.create_dataset(name, data=data, track_times=False)
        for p, attrs in model["group_attrs"].items():
            for k, v in attrs.items():
                f[p].attrs[k] = v


def add_model(name, mutate, check_exit, others, text):
    m = copy_model(BASE)
    mutate(m)
    write_model(os.path.join(HERE, name), m)
    ROWS.append((name, check_exit, others, text))


def add_bytes(name, data, check_exit, others, text):
    with open(os.path.join(HERE, name), "wb") as out:
        out.write(data)
    ROWS.append((name, check_exit, others, text))


def setitem(path, value):
    def mutate(m):
        m["items"][path] = value
    return mutate


def delete(path):
    def mutate(m):
        for p in list(m["items"]):
            if p == path or p.startswith(path + "/"):
                del m["items"][p]
    return mutate


def change(path, fn):
    def mutate(m):
        a = np.array(m["items"][path])
        fn(a)
        m["items"][path] = a
    return mutate


def with_attr(name, value):
    def mutate(m):
        if value is None:
            m["attrs"].pop(name, None)
        else:
            m["attrs"][name] = value
    return mutate


def chain(*mutations):
    def mutate(m):
        for f in mutations:
            f(m)
    return mutate


BASE = load_model()
N = BASE["items"]  # shorthand for shapes below

# A structurally valid /tetmesh for the two-triangle surface (coarse vertices plus an
# apex; not a closed volume, which the reader does not check), to derive /tetmesh defects.
_cv = N["/coarse/vertices"]
_ct = N["/coarse/triangles"]


def with_tetmesh(m):
    nvc = len(_cv)
    vertices = np.vstack([_cv, [[0.5, 0.5, 1.0]]])
    m["items"]["/tetmesh"] = None
    m["group_attrs"]["/tetmesh"] = {"level": np.array([0], dtype=np.int32)}
    m["items"]["/tetmesh/vertices"] = vertices
    m["items"]["/tetmesh/tetrahedra"] = np.array([list(t) + [nvc] for t in _ct], dtype=np.int32)
    m["items"]["/tetmesh/regions"] = np.ones(len(_ct), dtype=np.int32)
    m["items"]["/tetmesh/faces"] = np.array(_ct, dtype=np.int32)
    m["items"]["/tetmesh/face_coarse_triangle"] = np.arange(len(_ct), dtype=np.int32)
    m["items"]["/tetmesh/face_patches"] = np.array(N["/coarse/patches"], dtype=np.int32)
    m["items"]["/tetmesh/vertex_coarse_vertex"] = np.array(list(range(nvc)) + [-1], dtype=np.int32)
    tri_of, bary = [], []
    for v in range(nvc):
        t = next(i for i, tri in enumerate(_ct) if v in tri)
        tri_of.append(t)
        bary.append([1.0 if c == v else 0.0 for c in _ct[t]])
    m["items"]["/tetmesh/vertex_parameter_triangle"] = np.array(tri_of + [-1], dtype=np.int32)
    m["items"]["/tetmesh/vertex_parameter_barycentric"] = np.array(bary + [[0.0, 0.0, 0.0]])


def with_steps(m):
    m["items"]["/simplification_steps"] = None
    m["items"]["/simplification_steps/vertex"] = np.array([0], dtype=np.int32)
    m["items"]["/simplification_steps/triangle_offsets"] = np.array([0, 1], dtype=np.int64)
    m["items"]["/simplification_steps/triangles"] = np.array([[1, 2, 3]], dtype=np.int32)
    m["items"]["/simplification_steps/triangle_patches"] = np.array([1], dtype=np.int32)


def node_images(m):
    """The node images as spec/bpm-format.md §6.2 computes them (not stored since 2.0)."""
    items = m["items"]
    x = items["/original/vertices"]
    s = items["/phi/node_edge_parameter"][:, None]
    u, w = items["/phi/node_original_edge"].T
    return np.where(items["/phi/node_kind"][:, None] == 1, (1 - s) * x[u] + s * x[w],
                    x[items["/phi/node_original_vertex"]])


def as_version_1(m):
    """The same content as a format 1.3 file, which stores /phi/node_image (§6.2.1)."""
    m["attrs"]["format_version"] = np.array([1, 3], dtype=np.int32)
    m["items"]["/phi/node_image"] = node_images(m)


NV0 = len(N["/original/vertices"])
NT0 = len(N["/original/triangles"])
NVC = len(N["/coarse/vertices"])
NN = len(N["/phi/node_kind"])


def set_at(index, value):
    def fn(a):
        a[index] = value
    return fn


# ---- the files -------------------------------------------------------------------------
# Sanity: the rewritten base and the synthetic /tetmesh and /simplification_steps groups are
# valid (bpm-check passes them); every other file has exactly one defect. bpm-mesh refuses
# all three with exit 5: the two-triangle surface is open, TetGen needs a closed one.
add_model("valid_base.bpm", lambda m: None, 0, "0,5", "*")
# Valid for the reader (every /tetmesh rule of spec/tetmesh.md §5 holds), but two tetrahedra
# over an open square do not fill a region: bpm-check's tetmesh check finds the holes.
add_model("valid_with_tetmesh.bpm", with_tetmesh, 1, "0,5", "FAIL tetmesh")
add_model("valid_with_steps.bpm", with_steps, 0, "0,5", "*")
add_model("valid_version_1.bpm", as_version_1, 0, "0,5", "*")

# Identification and version (§2).
def not_bpm(m):
    m["attrs"].clear()
    m["items"].clear()
    m["items"]["/data"] = np.arange(10.0)


add_model("not_bpm_hdf5.bpm", not_bpm, 3, "3", "root attribute 'format': missing (is this a bpm file?)")
add_model("format_not_bpm.bpm", with_attr("format", np.bytes_("vtk")), 3, "3", "expected 'bpm'")
add_model("format_wrong_type.bpm", with_attr("format", np.array([1, 2], dtype=np.int32)), 3, "3",
          "root attribute 'format': wrong datatype")
add_model("version_missing.bpm", with_attr("format_version", None), 3, "3", "root attribute 'format_version': missing")
add_model("version_major_3.bpm", with_attr("format_version", np.array([3, 0], dtype=np.int32)), 3, "3",
          "file has format version 3.0, this reader supports major versions 1 to 2 only; a newer bpm is needed")
add_model("version_major_0.bpm", with_attr("format_version", np.array([0, 9], dtype=np.int32)), 3, "3",
          "file has format version 0.9")
add_model("version_one_int.bpm", with_attr("format_version", np.array([1], dtype=np.int32)), 3, "3",
          "expected 2 integers")
add_model("version_float.bpm", with_attr("format_version", np.array([1.0, 0.0])), 3, "3",
          "root attribute 'format_version': wrong datatype")
add_model("version_negative_minor.bpm", with_attr("format_version", np.array([1, -1], dtype=np.int32)), 3, "3",
          "negative minor version")
add_model("units_not_string.bpm", with_attr("units", np.float64(1.0)), 3, "3", "root attribute 'units': wrong datatype")

# Missing datasets and groups (§4).
add_model("missing_original_vertices.bpm", delete("/original/vertices"), 3, "3", "/original/vertices: missing dataset")
add_model("missing_coarse_group.bpm", delete("/coarse"), 3, "3", "/coarse/vertices: missing dataset")
add_model("missing_phi_pieces.bpm", delete("/phi/pieces"), 3, "3", "/phi/pieces: missing dataset")
add_model("missing_provenance_tool.bpm", delete("/provenance/tool"), 3, "3", "/provenance/tool: missing dataset")
add_model("group_instead_of_dataset.bpm", chain(delete("/phi/node_kind"), setitem("/phi/node_kind", None)), 3, "3",
          "/phi/node_kind: is not a dataset")

# Wrong datatypes.
add_model("vertices_integer.bpm", setitem("/original/vertices", np.zeros((NV0, 3), dtype=np.int32)), 3, "3",
          "/original/vertices: wrong datatype, expected a floating-point type")
add_model("triangles_float.bpm", setitem("/coarse/triangles", N["/coarse/triangles"].astype(np.float64)), 3, "3",
          "/coarse/triangles: wrong datatype, expected an integer type")
add_model("node_kind_string.bpm", setitem("/phi/node_kind", np.array([b"x"] * NN)), 3, "3",
          "/phi/node_kind: wrong datatype")
add_model("provenance_not_strings.bpm", setitem("/provenance/tool", np.array([7], dtype=np.int32)), 3, "3",
          "/provenance/tool: wrong datatype, expected a string type")

# Wrong shapes.
add_model("vertices_two_columns.bpm", setitem("/original/vertices", N["/original/vertices"][:, :2].copy()), 3, "3",
          "/original/vertices: expected shape (#V, 3), found shape (4, 2)")
add_model("triangles_one_dimensional.bpm", setitem("/original/triangles", N["/original/triangles"].reshape(-1)), 3,
          "3", "/original/triangles: expected shape (#T, 3)")
add_model("patches_two_dimensional.bpm", setitem("/coarse/patches", N["/coarse/patches"].reshape(-1, 1)), 3, "3",
          "/coarse/patches: expected shape (#T,)")
add_model("scalar_dataset.bpm", setitem("/phi/node_offsets", np.int64(0)), 3, "3", "/phi/node_offsets: expected shape")
add_model("patches_too_few.bpm", setitem("/original/patches", N["/original/patches"][:1].copy()), 3, "3",
          "/original/patches: has 1 rows, expected 2")
add_model("node_image_too_few_rows.bpm",
          chain(as_version_1, lambda m: m["items"].__setitem__("/phi/node_image", m["items"]["/phi/node_image"][:-1])),
          3, "3", "/phi/node_image: has %d rows, expected %d" % (NN - 1, NN))
add_model("version_1_without_node_image.bpm", with_attr("format_version", np.array([1, 3], dtype=np.int32)), 3, "3",
          "/phi/node_image: missing dataset")

# Indices out of range, negative, beyond int32 (§11.4).
add_model("triangle_index_out_of_range.bpm", change("/original/triangles", set_at((1, 2), NV0)), 3, "3",
          "/original/triangles: entry [1, 2] = %d is out of range [0, %d)" % (NV0, NV0))
add_model("triangle_index_negative.bpm", change("/coarse/triangles", set_at((0, 0), -1)), 3, "3",
          "/coarse/triangles: entry [0, 0] = -1 is out of range")
add_model("vertex_origin_out_of_range.bpm", change("/coarse/vertex_origin", set_at(2, 1000)), 3, "3",
          "/coarse/vertex_origin: entry 2 = 1000 is out of range")
add_model("node_original_vertex_negative.bpm", change("/phi/node_original_vertex", set_at(0, -7)), 3, "3",
          "/phi/node_original_vertex: entry 0 = -7 is out of range")
add_model("piece_local_index_out_of_range.bpm", change("/phi/pieces", set_at((0, 1), 99)), 3, "3",
          "/phi/pieces: entry [0, 1] = 99 is out of range")
add_model("piece_original_triangle_negative.bpm", change("/phi/piece_original_triangle", set_at(0, -1)), 3, "3",
          "/phi/piece_original_triangle: entry 0 = -1 is out of range")
add_model("index_beyond_int32.bpm",
          setitem("/original/triangles", np.where(np.arange(3 * NT0).reshape(-1, 3) == 4, 1 << 40,
                                                  N["/original/triangles"]).astype(np.int64)),
          3, "3", "does not fit in int32")
add_model("node_kind_invalid.bpm", change("/phi/node_kind", set_at(1, 3)), 3, "3",
          "/phi/node_kind: entry 1 = 3 is not a valid node kind")

# CSR offsets (§11.5).
add_model("node_offsets_not_monotone.bpm",
          change("/phi/node_offsets", lambda a: a.__setitem__(1, a[2] + 1)), 3, "3",
          "/phi/node_offsets: entry 2")
add_model("node_offsets_not_from_zero.bpm", change("/phi/node_offsets", set_at(0, 1)), 3, "3",
          "/phi/node_offsets: entry 0 is 1, must be 0")
add_model("node_offsets_incomplete.bpm", change("/phi/node_offsets", set_at(-1, NN - 1)), 3, "3",
          "/phi/node_offsets: last entry is %d but /phi/node_kind has %d rows" % (NN - 1, NN))
add_model("piece_offsets_wrong_length.bpm",
          setitem("/phi/piece_offsets", N["/phi/piece_offsets"][:-1].copy()), 3, "3",
          "/phi/piece_offsets: has 2 rows, expected 3")
add_model("piece_offsets_negative.bpm", change("/phi/piece_offsets", set_at(1, -2)), 3, "3",
          "/phi/piece_offsets: entry")

# Non-finite and out-of-range values (§11.7).
add_model("vertices_nan.bpm", change("/original/vertices", set_at((2, 1), np.nan)), 3, "3",
          "/original/vertices: entry [2, 1] is not finite (nan)")
add_model("coarse_vertices_inf.bpm", change("/coarse/vertices", set_at((0, 0), -np.inf)), 3, "3",
          "/coarse/vertices: entry [0, 0] is not finite (-inf)")
add_model("node_image_inf.bpm", chain(as_version_1, change("/phi/node_image", set_at((3, 2), np.inf))), 3, "3",
          "/phi/node_image: entry [3, 2] is not finite")
add_model("barycentric_nan.bpm", change("/phi/node_barycentric", set_at((0, 0), np.nan)), 3, "3",
          "/phi/node_barycentric: entry [0, 0] is not finite")
add_model("barycentric_sum_not_one.bpm", change("/phi/node_barycentric", set_at((1, 0), 0.75)), 3, "3",
          "/phi/node_barycentric: row 1 sums to")

# Extents that claim more than the file can hold (memory must stay bounded).
add_model("huge_extent_contiguous.bpm",
          setitem("/original/vertices", {"shape": (1 << 40, 3), "dtype": "f8"}), 3, "3",
          "more than a")
add_model("huge_extent_compressed.bpm",
          setitem("/phi/node_kind", {"shape": (1 << 36,), "dtype": "u1", "chunks": (1 << 20,), "compression": "gzip"}),
          3, "3", "more than a")
add_model("huge_extent_unlimited.bpm",
          setitem("/original/triangles", {"shape": (1 << 38, 3), "dtype": "i4", "chunks": (1024, 3),
                                          "maxshape": (None, 3)}),
          3, "3", "more than a")

# Provenance (§8).
add_model("provenance_rows_disagree.bpm", setitem("/provenance/version", np.array([b"1", b"2"])), 3, "3",
          "/provenance/version: has 2 rows, expected 1")

# Optional groups: /tetmesh (spec/tetmesh.md) and /simplification_steps (§10.1).
add_model("tetmesh_level_missing.bpm", chain(with_tetmesh, lambda m: m["group_attrs"].pop("/tetmesh")), 3, "3",
          "/tetmesh: attribute 'level': missing")
add_model("tetmesh_index_out_of_range.bpm",
          chain(with_tetmesh, change("/tetmesh/tetrahedra", set_at((1, 3), 50))), 3, "3",
          "/tetmesh/tetrahedra: entry [1, 3] = 50 is out of range")
add_model("tetmesh_region_zero.bpm", chain(with_tetmesh, change("/tetmesh/regions", set_at(0, 0))), 3, "3",
          "/tetmesh/regions: entry 0 = 0 is not a region id")
add_model("steps_vertex_out_of_range.bpm",
          chain(with_steps, change("/simplification_steps/vertex", set_at(0, NV0 + 5))), 3, "3",
          "/simplification_steps/vertex: entry 0 = %d is out of range" % (NV0 + 5))

# Readable but invalid: the structure is right, a check of bpm-check fails (exit 1).
add_model("image_off_the_original.bpm",
          chain(as_version_1, change("/phi/node_image", lambda a: a.__setitem__((4, 2), a[4, 2] + 0.5))),
          1, "0,5", "FAIL format")
add_model("coarse_vertex_moved.bpm", change("/coarse/vertices", lambda a: a.__setitem__((1, 0), a[1, 0] + 0.25)),
          1, "0,5", "FAIL format")
add_model("piece_flipped.bpm", change("/phi/pieces", lambda a: a.__setitem__(0, a[0][[0, 2, 1]])), 1, "0,5",
          "FAIL bijectivity")

# Byte-level damage to the golden file itself.
golden = open(GOLDEN, "rb").read()
add_bytes("empty.bpm", b"", 3, "3", "empty input, not a bpm file")
add_bytes("truncated_4k.bpm", golden[:4096], 3, "3", "cannot open as HDF5, file truncated or damaged")
add_bytes("truncated_half.bpm", golden[: len(golden) // 2], 3, "3", "*")
add_bytes("garbage.bpm", bytes(random.Random(7).randrange(256) for _ in range(2048)), 3, "3",
          "not an HDF5 file (no HDF5 signature)")
add_bytes("signature_then_garbage.bpm",
          golden[:8] + bytes(random.Random(8).randrange(256) for _ in range(2040)), 3, "3", "*")
add_bytes("text_file.bpm", b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", 3, "3", "no HDF5 signature")
# The first local heap (group names) announces 2^64-1 bytes: HDF5 1.10.8 then copies with
# size -1 and corrupts its heap (SIGSEGV or a glibc abort; found by tests/fuzz/fuzz_read_bpm).
# The tools parse in a child process first and report the crash (bpm_file.h,
# set_hdf5_isolation).
heap = golden.index(b"HEAP")
add_bytes("hdf5_crash_local_heap_size.bpm",
          golden[: heap + 8] + struct.pack("<Q", 0xFFFFFFFFFFFFFFFF) + golden[heap + 16:], 3, "3",
          "the HDF5 library crashed reading it")

# A directory where a file is expected (git keeps it through the file inside).
directory = os.path.join(HERE, "directory.bpm")
shutil.rmtree(directory, ignore_errors=True)
os.makedirs(directory)
with open(os.path.join(directory, "README"), "w") as out:
    out.write("A directory named like a .bpm file: the tools must refuse it as input (exit 3).\n")
ROWS.append(("directory.bpm", 3, "3", "is a directory, not a file"))

with open(os.path.join(HERE, "EXPECTED.tsv"), "w") as out:
    out.write("# file\tbpm-check exit\tother tools' exit(s)\ttext the error message (exit 3) or report (exit 1) must "
              "contain; * = anything (make_bad_bpm.py explains)\n")
    for row in ROWS:
        out.write("%s\t%d\t%s\t%s\n" % row)
print("wrote %d files to %s" % (len(ROWS), HERE))
