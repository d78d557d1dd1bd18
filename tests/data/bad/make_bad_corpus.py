#!/usr/bin/python3
"""Writes the corpus of malformed surface files next to this script.

Every file must make bpm::read_surface() (default options) throw bpm::InputError;
EXPECTED.tsv lists, per file, a piece of text the error message must contain ("*" when
any non-empty message will do, e.g. for random bytes). Deterministic: run it again and
the files come out byte for byte the same.

    /usr/bin/python3 tests/data/bad/make_bad_corpus.py
"""
import os
import random
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
FILES = []  # (name, bytes, expected substring)


def add(name, data, expected):
    if isinstance(data, str):
        data = data.encode()
    FILES.append((name, data, expected))


def garbage(seed, n):
    rng = random.Random(seed)
    return bytes(rng.randrange(256) for _ in range(n))


# A tetrahedron, the good surface most bad files are derived from.
TET_V = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
TET_F = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]


def off(vertices, faces, header=None):
    s = header if header is not None else "OFF\n%d %d 0\n" % (len(vertices), len(faces))
    s += "".join(" ".join(str(c) for c in v) + "\n" for v in vertices)
    s += "".join("%d %s\n" % (len(f), " ".join(str(i) for i in f)) for f in faces)
    return s


# ---- OFF -------------------------------------------------------------------------
add("off_empty.off", "", "empty")
add("off_only_comment.off", "# nothing here\n", "empty")
add("off_no_header.off", off(TET_V, TET_F, header="4 4 0\n"), "expected the keyword 'OFF'")
add("off_binary_claim.off", "OFF BINARY\n4 4 0\n", "binary OFF")
add("off_4d.off", "4OFF\n1 0 0\n0 0 0 0\n", "only 3-D")
add("off_missing_counts.off", "OFF\n4\n", "number of faces")
add("off_truncated_vertices.off", off(TET_V, TET_F)[:22], "announced")
add("off_truncated_faces.off", off(TET_V, TET_F).rsplit("3 ", 2)[0], "truncated, or wrong counts?")
add("off_too_few_announced.off", off(TET_V, TET_F, header="OFF\n4 3 0\n"), "after the last of the 3 announced faces")
add("off_billions.off", "OFF\n4000000000 4 0\n0 0 0\n", "bpm supports at most")
add("off_big_counts.off", "OFF\n2000000000 2000000000 0\n0 0 0\n", "cannot hold that many")
add("off_negative_count.off", "OFF\n-4 4 0\n", "negative number of vertices")
add("off_nan.off", off([(0, 0, 0), (1, "nan", 0), (0, 1, 0), (0, 0, 1)], TET_F), "is not a finite number")
add("off_inf.off", off([(0, 0, 0), (1, 0, 0), ("-inf", 1, 0), (0, 0, 1)], TET_F), "is not a finite number")
add("off_overflow.off", off([(0, 0, 0), (1, 0, 0), (0, "1e999", 0), (0, 0, 1)], TET_F), "is not a finite number")
add("off_garbage_coordinate.off", off([(0, 0, 0), (1, 0, "abc"), (0, 1, 0), (0, 0, 1)], TET_F), "expected coordinate")
add("off_negative_index.off", off(TET_V, TET_F[:3] + [(1, -2, 3)]), "vertex index -2 is out of range")
add("off_index_out_of_range.off", off(TET_V, TET_F[:3] + [(1, 2, 4)]), "vertex index 4 is out of range")
add("off_garbage_index.off", off(TET_V, TET_F[:3] + [(1, "2x", 3)]), "expected a vertex index")
add("off_quad.off", off(TET_V + [(1, 1, 0)], TET_F[:3] + [(1, 4, 2, 3)]), "only triangles are accepted")
add("off_zero_area.off", off(TET_V + [(2, 0, 0)], TET_F + [(0, 1, 4)]), "zero area")
add("off_repeated_corner.off", off(TET_V, TET_F + [(0, 1, 1)]), "are the same vertex")
add("off_duplicate_triangle.off", off(TET_V, TET_F + [(2, 1, 0)]), "same three vertices as triangle 0")
add("off_unreferenced_vertex.off", off(TET_V + [(5, 5, 5)], TET_F), "vertex 4: not used by any triangle")
add("off_duplicate_vertex.off", off(TET_V + [(1, 0, 0)], TET_F[:3] + [(4, 2, 3)]), "vertex 4: same position")
add("off_no_triangles.off", "OFF\n0 0 0\n", "no triangles")
add("off_binary_garbage.off", garbage(1, 300), "*")
add("off_header_then_garbage.off", b"OFF\n4 4 0\n" + garbage(2, 200), "*")

# ---- OBJ -------------------------------------------------------------------------
OBJ_V = "".join("v %g %g %g\n" % v for v in TET_V)
add("obj_empty.obj", "", "no vertices and no faces")
add("obj_not_obj.obj", "hello world\nthis is text\n", "does not look like an OBJ file")
add("obj_quad.obj", OBJ_V + "v 1 1 0\nf 1 2 3\nf 2 5 3 4\n", "has 4 corners; only triangles")
add("obj_two_corners.obj", OBJ_V + "f 1 2\n", "a triangle needs 3")
add("obj_index_zero.obj", OBJ_V + "f 0 1 2\n", "OBJ indices start at 1")
add("obj_out_of_range.obj", OBJ_V + "f 1 3 2\nf 1 2 9\n", "vertex index 9 is out of range")
add("obj_relative_before_first.obj", OBJ_V + "f -1 -2 -7\n", "points before the first vertex")
add("obj_nan.obj", "v 0 0 0\nv NaN 0 0\nv 0 1 0\nf 1 2 3\n", "is not a finite number")
add("obj_inf.obj", "v 0 0 0\nv 1 0 0\nv 0 infinity 0\nf 1 2 3\n", "is not a finite number")
add("obj_garbage_coordinate.obj", "v 0 0 0\nv 1 0 0\nv 0 1 x\nf 1 2 3\n", "expected a vertex coordinate")
add("obj_missing_coordinate.obj", "v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n", "found the end of the line")
add("obj_bad_corner_form.obj", OBJ_V + "f 1/1/1/1 2 3\n", "a face corner")
add("obj_garbage_index.obj", OBJ_V + "f 1 2 three\n", "expected a vertex index")
add("obj_zero_area.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n", "zero area")
add("obj_duplicate_vertex.obj", OBJ_V + "v 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 5 3\nf 2 3 4\n", "vertex 4: same position")
add("obj_binary_garbage.obj", garbage(3, 300), "*")

# ---- STL -------------------------------------------------------------------------
def stl_binary(tris, header=b"bad corpus", count=None, fmt="<3f"):
    out = header.ljust(80, b" ")[:80] + struct.pack("<I", len(tris) if count is None else count)
    for t in tris:
        out += struct.pack("<3f", 0, 0, 0)
        for p in t:
            out += struct.pack(fmt, *p)
        out += b"\0\0"
    return out


def stl_ascii(tris):
    s = "solid bad\n"
    for t in tris:
        s += "facet normal 0 0 0\nouter loop\n" + "".join("vertex %s %s %s\n" % p for p in t) + "endloop\nendfacet\n"
    return s + "endsolid bad\n"


STL_TRIS = [[TET_V[i] for i in f] for f in TET_F]
add("stl_empty.stl", "", "empty")
add("stl_short.stl", "not an stl", "too short")
add("stl_truncated_binary.stl", stl_binary(STL_TRIS)[:-10], "which needs 284 bytes")
add("stl_billions.stl", stl_binary([], count=0xFFFFFFFF), "4294967295 triangles")
add("stl_binary_extra_bytes.stl", stl_binary(STL_TRIS) + b"\0" * 7, "but the file has")
add("stl_binary_nan.stl", stl_binary(STL_TRIS[:3] + [[(1, 0, 0), (0, float("nan"), 0), (0, 0, 1)]]), "coordinate is NaN")
add("stl_binary_inf.stl", stl_binary(STL_TRIS[:3] + [[(1, 0, 0), (0, 1, 0), (float("inf"), 0, 1)]]), "coordinate is infinite")
add("stl_solid_binary_truncated.stl", stl_binary(STL_TRIS, header=b"solid exported")[:-20], "holds binary data")
add("stl_repeated_corner.stl", stl_binary(STL_TRIS + [[(1, 0, 0), (1, 0, 0), (0, 0, 1)]]), "are the same vertex")
add("stl_zero_area.stl", stl_binary(STL_TRIS + [[(0, 0, 0), (1, 0, 0), (2, 0, 0)]]), "zero area")
add("stl_ascii_truncated.stl", stl_ascii(STL_TRIS)[:150], "expected")
add("stl_ascii_nan.stl", stl_ascii(STL_TRIS).replace("vertex 1 0 0", "vertex 1 nan 0", 1), "is not a finite number")
add("stl_ascii_garbage.stl", stl_ascii(STL_TRIS).replace("normal 0 0 0", "normal a b c", 1), "expected a normal component")
add("stl_ascii_quad.stl", stl_ascii(STL_TRIS).replace("endloop", "vertex 1 1 1\nendloop", 1), "more than 3 vertices")
add("stl_ascii_no_endsolid.stl", stl_ascii(STL_TRIS).replace("endsolid bad\n", ""), "'facet' or 'endsolid'")
add("stl_binary_garbage.stl", garbage(4, 300), "*")

# ---- PLY -------------------------------------------------------------------------
def ply_header(fmt, nv, nf, vertex_type="float", extra="", face_extra="", index_type="int", count_type="uchar"):
    return ("ply\nformat %s 1.0\nelement vertex %d\nproperty %s x\nproperty %s y\nproperty %s z\n%s"
            "element face %d\nproperty list %s %s vertex_indices\n%send_header\n"
            % (fmt, nv, vertex_type, vertex_type, vertex_type, extra, nf, count_type, index_type, face_extra)).encode()


def ply_ascii(vertices, faces, **kw):
    body = "".join(" ".join(str(c) for c in v) + "\n" for v in vertices)
    body += "".join("%d %s\n" % (len(f), " ".join(str(i) for i in f)) for f in faces)
    return ply_header("ascii", len(vertices), len(faces), **kw) + body.encode()


def ply_binary(vertices, faces, endian="<", fmt=None):
    fmt = fmt or ("binary_little_endian" if endian == "<" else "binary_big_endian")
    body = b"".join(struct.pack(endian + "3d", *v) for v in vertices)
    body += b"".join(struct.pack(endian + "B%di" % len(f), len(f), *f) for f in faces)
    return ply_header(fmt, len(vertices), len(faces), vertex_type="double") + body


add("ply_empty.ply", "", "empty")
add("ply_no_magic.ply", "PLY\nformat ascii 1.0\nend_header\n", "the first line must be 'ply'")
add("ply_no_end_header.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n", "no 'end_header'")
add("ply_bad_format.ply", ply_ascii(TET_V, TET_F).replace(b"ascii", b"binary_middle_endian"), "unknown PLY encoding")
add("ply_bad_type.ply", ply_ascii(TET_V, TET_F).replace(b"float y", b"flt y"), "unknown PLY type")
add("ply_no_x.ply", ply_ascii(TET_V, TET_F).replace(b"float x", b"float u"), "no scalar property x")
add("ply_no_format.ply", ply_ascii(TET_V, TET_F).replace(b"format ascii 1.0\n", b""), "no 'format' line")
add("ply_billions_ascii.ply", ply_header("ascii", 4000000000, 4) + b"0 0 0\n", "bpm supports at most")
add("ply_billions_binary.ply", ply_header("binary_little_endian", 100000000, 4) + b"\0" * 100, "cannot hold that many")
add("ply_truncated_binary.ply", ply_binary(TET_V, TET_F)[:-7], "runs past the end of the file")
add("ply_truncated_binary_vertex.ply", ply_binary(TET_V, TET_F)[:-60], "cannot hold that many")
add("ply_truncated_ascii.ply", ply_ascii(TET_V, TET_F)[:-12], "expected")
add("ply_too_few_announced.ply", ply_ascii(TET_V, TET_F).replace(b"face 4", b"face 3"), "after the last element")
add("ply_binary_extra_bytes.ply", ply_binary(TET_V, TET_F) + b"\0\0\0", "bytes after the last element")
add("ply_nan_binary.ply", ply_binary([(0, 0, 0), (float("nan"), 0, 0), (0, 1, 0), (0, 0, 1)], TET_F), "is NaN")
add("ply_inf_binary_be.ply", ply_binary([(0, 0, 0), (1, 0, 0), (0, float("-inf"), 0), (0, 0, 1)], TET_F, ">"), "is infinite")
add("ply_inf_ascii.ply", ply_ascii([(0, 0, 0), (1, 0, 0), (0, "inf", 0), (0, 0, 1)], TET_F), "is not a finite number")
add("ply_negative_index.ply", ply_ascii(TET_V, TET_F[:3] + [(1, -1, 3)]), "vertex index -1 is out of range")
add("ply_index_out_of_range.ply", ply_binary(TET_V, TET_F[:3] + [(1, 2, 17)]), "vertex index 17 is out of range")
add("ply_quad.ply", ply_ascii(TET_V + [(1, 1, 0)], TET_F[:3] + [(1, 4, 2, 3)]), "only triangles are accepted")
add("ply_index_does_not_fit_type.ply", ply_ascii(TET_V, TET_F, index_type="uchar")[:-8] + b"3 1 2 300\n", "does not fit its declared type")
add("ply_garbage_ascii.ply", ply_ascii(TET_V, TET_F).replace(b"\n1 0 0\n", b"\n1 zero 0\n"), "expected")
# Big-endian data under a little-endian header: indices come out as 16777216 and such.
add("ply_wrong_endianness.ply", ply_binary(TET_V, TET_F, ">", fmt="binary_little_endian"), "out of range")
# An unused list whose count claims 4 billion entries.
add("ply_huge_list_count.ply",
    ply_header("binary_little_endian", 4, 1, vertex_type="double",
               face_extra="property list uint int extra\n") +
    b"".join(struct.pack("<3d", *v) for v in TET_V) + struct.pack("<B3iI", 3, 0, 1, 2, 4000000000),
    "runs past the end of the file")
add("ply_point_cloud.ply", ply_ascii(TET_V, []), "no triangles")
add("ply_unreferenced_vertex.ply", ply_binary(TET_V + [(3, 3, 3)], TET_F), "not used by any triangle")
add("ply_binary_garbage.ply", b"ply\nformat binary_little_endian 1.0\nelement vertex 5\nproperty double x\n"
    b"property double y\nproperty double z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n" +
    garbage(5, 150), "*")
add("ply_random_bytes.ply", garbage(6, 300), "*")

# ---- MSH -------------------------------------------------------------------------
def msh22_ascii(nodes, elements, fmt="2.2 0 8"):
    s = "$MeshFormat\n%s\n$EndMeshFormat\n$Nodes\n%d\n" % (fmt, len(nodes))
    s += "".join("%d %s %s %s\n" % ((i + 1,) + tuple(p)) for i, p in enumerate(nodes))
    s += "$EndNodes\n$Elements\n%d\n" % len(elements)
    s += "".join("%d %s\n" % (i + 1, " ".join(str(x) for x in e)) for i, e in enumerate(elements))
    return s + "$EndElements\n"


TRI22 = [(2, 2, 7, 1, f[0] + 1, f[1] + 1, f[2] + 1) for f in TET_F]


def msh22_binary(nodes, tris, marker=1, endian="<"):
    out = b"$MeshFormat\n2.2 1 8\n" + struct.pack(endian + "i", marker) + b"\n$EndMeshFormat\n"
    out += b"$Nodes\n%d\n" % len(nodes)
    out += b"".join(struct.pack(endian + "i3d", i + 1, *p) for i, p in enumerate(nodes))
    out += b"\n$EndNodes\n$Elements\n%d\n" % len(tris)
    out += struct.pack(endian + "3i", 2, len(tris), 2)
    out += b"".join(struct.pack(endian + "6i", i + 1, 7, 1, *[v + 1 for v in f]) for i, f in enumerate(tris))
    return out + b"\n$EndElements\n"


def msh41_ascii(nodes, tris, blocks_header=None):
    s = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n0 0 1 0\n1 0 0 0 1 1 1 1 5 0\n$EndEntities\n"
    s += "$Nodes\n1 %d 1 %d\n2 1 0 %d\n" % (len(nodes), len(nodes), len(nodes))
    s += "".join("%d\n" % (i + 1) for i in range(len(nodes)))
    s += "".join("%s %s %s\n" % tuple(p) for p in nodes)
    s += "$EndNodes\n$Elements\n"
    s += blocks_header if blocks_header is not None else "1 %d 1 %d\n2 1 2 %d\n" % (len(tris), len(tris), len(tris))
    s += "".join("%d %d %d %d\n" % ((i + 1,) + tuple(v + 1 for v in f)) for i, f in enumerate(tris))
    return s + "$EndElements\n"


def msh41_binary(nodes, tris, element_type=2):
    q = lambda *v: struct.pack("<%dQ" % len(v), *v)
    i = lambda *v: struct.pack("<%di" % len(v), *v)
    out = b"$MeshFormat\n4.1 1 8\n" + i(1) + b"\n$EndMeshFormat\n"
    out += b"$Entities\n" + q(0, 0, 1, 0) + i(1) + struct.pack("<6d", 0, 0, 0, 1, 1, 1) + q(1) + i(5) + q(0)
    out += b"\n$EndEntities\n$Nodes\n" + q(1, len(nodes), 1, len(nodes)) + i(2, 1, 0) + q(len(nodes))
    out += q(*range(1, len(nodes) + 1)) + b"".join(struct.pack("<3d", *p) for p in nodes)
    out += b"\n$EndNodes\n$Elements\n" + q(1, len(tris), 1, len(tris)) + i(2, 1, element_type) + q(len(tris))
    out += b"".join(q(k + 1, *[v + 1 for v in f]) for k, f in enumerate(tris))
    return out + b"\n$EndElements\n"


add("msh_empty.msh", "", "empty")
add("msh_no_format.msh", msh22_ascii(TET_V, TRI22).replace("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n", ""), "'$MeshFormat'")
add("msh_version1.msh", "$NOD\n0\n$ENDNOD\n", "MSH version 1 is not supported")
add("msh_version3.msh", msh22_ascii(TET_V, TRI22, fmt="3.0 0 8"), "is not supported")
add("msh_version40.msh", msh22_ascii(TET_V, TRI22, fmt="4 0 8"), "is not supported")
add("msh_data_size4.msh", msh22_ascii(TET_V, TRI22, fmt="2.2 0 4"), "data size 4")
add("msh22_truncated.msh", msh22_ascii(TET_V, TRI22)[:-40], "expected")
add("msh22_billions_nodes.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4000000000\n1 0 0 0\n", "bpm supports at most")
add("msh22_too_many_nodes.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n90000000\n1 0 0 0\n", "cannot hold that many")
add("msh22_nan.msh", msh22_ascii([(0, 0, 0), (1, 0, 0), (0, "nan", 0), (0, 0, 1)], TRI22), "is not a finite number")
add("msh22_missing_node.msh", msh22_ascii(TET_V, TRI22[:3] + [(2, 2, 7, 1, 2, 3, 99)]), "node tag 99 is not in $Nodes")
add("msh22_duplicate_node_tag.msh", msh22_ascii(TET_V, TRI22).replace("\n4 0 0 1\n", "\n3 0 0 1\n"), "used by two nodes")
add("msh22_wrong_count.msh", msh22_ascii(TET_V, TRI22).replace("$Elements\n4\n", "$Elements\n5\n"), "expected")
add("msh22_no_end.msh", msh22_ascii(TET_V, TRI22).replace("$EndNodes\n", ""), "'$EndNodes'")
add("msh22_only_lines.msh", msh22_ascii(TET_V, [(1, 2, 7, 1, 1, 2), (1, 2, 7, 1, 2, 3)]), "no triangles")
add("msh22_binary_bad_endian_marker.msh", msh22_binary(TET_V, TET_F, marker=2), "endianness marker is 2")
add("msh22_binary_truncated.msh", msh22_binary(TET_V, TET_F)[:-50], "cannot hold that many")
add("msh22_binary_nan.msh", msh22_binary([(0, 0, 0), (1, 0, 0), (0, 1, float("nan")), (0, 0, 1)], TET_F), "is NaN")
add("msh41_truncated.msh", msh41_ascii(TET_V, TET_F)[:-60], "expected")
add("msh41_block_count_mismatch.msh", msh41_ascii(TET_V, TET_F, blocks_header="1 4 1 4\n2 1 2 9\n"), "of the announced elements are left")
add("msh41_billions_elements.msh", msh41_ascii(TET_V, TET_F, blocks_header="1 4000000000 1 4\n2 1 2 4\n"), "bpm supports at most")
add("msh41_no_end.msh", msh41_ascii(TET_V, TET_F).replace("$EndElements\n", ""), "'$EndElements'")
add("msh41_binary_nan.msh", msh41_binary([(0, 0, 0), (float("nan"), 0, 0), (0, 1, 0), (0, 0, 1)], TET_F), "is NaN")
add("msh41_binary_unknown_type.msh", msh41_binary(TET_V, TET_F, element_type=77), "unknown element type 77")
add("msh41_binary_truncated.msh", msh41_binary(TET_V, TET_F)[:-30], "cannot hold that many")
add("msh41_binary_truncated_last.msh", msh41_binary(TET_V, TET_F)[:-20], "cannot hold that many")
add("msh41_binary_truncated_block.msh", msh41_binary(TET_V, TET_F)[:-141], "cannot hold that many")
add("msh41_unreferenced_node.msh", msh41_ascii(TET_V + [(4, 4, 4)], TET_F), "not used by any triangle")
add("msh_binary_garbage.msh", b"$MeshFormat\n4.1 1 8\n" + struct.pack("<i", 1) + b"\n$EndMeshFormat\n$Nodes\n" + garbage(7, 200), "*")
add("msh_random_bytes.msh", garbage(8, 300), "*")

# ---- VTK (legacy) ----------------------------------------------------------------
def vtk_ascii(vertices, faces, version="4.2", body_extra=""):
    s = "# vtk DataFile Version %s\nbad corpus\nASCII\nDATASET POLYDATA\nPOINTS %d double\n" % (version, len(vertices))
    s += "".join(" ".join(str(c) for c in v) + "\n" for v in vertices)
    s += "POLYGONS %d %d\n" % (len(faces), sum(len(f) + 1 for f in faces))
    s += "".join("%d %s\n" % (len(f), " ".join(str(i) for i in f)) for f in faces)
    return s + body_extra


def vtk_binary(vertices, faces, cells_line=None):
    out = b"# vtk DataFile Version 4.2\nbad corpus\nBINARY\nDATASET POLYDATA\nPOINTS %d double\n" % len(vertices)
    out += b"".join(struct.pack(">3d", *v) for v in vertices) + b"\n"
    out += cells_line if cells_line is not None else b"POLYGONS %d %d\n" % (len(faces), sum(len(f) + 1 for f in faces))
    out += b"".join(struct.pack(">%di" % (len(f) + 1), len(f), *f) for f in faces)
    return out + b"\n"


add("vtk_empty.vtk", "", "empty")
add("vtk_no_header.vtk", vtk_ascii(TET_V, TET_F).replace("# vtk DataFile Version 4.2\n", ""), "not a legacy VTK file")
add("vtk_version9.vtk", vtk_ascii(TET_V, TET_F, version="9.0"), "unsupported VTK file version")
add("vtk_no_encoding.vtk", vtk_ascii(TET_V, TET_F).replace("ASCII\n", "TEXT\n"), "expected ASCII or BINARY")
add("vtk_structured_points.vtk", "# vtk DataFile Version 3.0\nimage\nASCII\nDATASET STRUCTURED_POINTS\n"
    "DIMENSIONS 2 2 2\nORIGIN 0 0 0\nSPACING 1 1 1\n", "is a grid, not a surface")
add("vtk_unknown_keyword.vtk", vtk_ascii(TET_V, TET_F).replace("POLYGONS", "POLYGON"), "unknown keyword 'POLYGON'")
add("vtk_unknown_type.vtk", vtk_ascii(TET_V, TET_F).replace("POINTS 4 double", "POINTS 4 real"), "unknown VTK data type 'real'")
add("vtk_nan.vtk", vtk_ascii([(0, 0, 0), (1, "nan", 0), (0, 1, 0), (0, 0, 1)], TET_F), "is not a finite number")
add("vtk_index_out_of_range.vtk", vtk_ascii(TET_V, TET_F[:3] + [(1, 2, 4)]), "point index 4 is out of range")
add("vtk_billions.vtk", "# vtk DataFile Version 4.2\nx\nASCII\nDATASET POLYDATA\nPOINTS 4000000000 float\n0 0 0\n",
    "bpm supports at most")
add("vtk_big_counts.vtk", vtk_ascii(TET_V, TET_F).replace("POLYGONS 4 16", "POLYGONS 100000000 400000000"),
    "cannot hold that many")
add("vtk_wrong_size.vtk", vtk_ascii(TET_V, TET_F).replace("POLYGONS 4 16", "POLYGONS 3 16"), "3 cells use 12 integers, but 16 were announced")
add("vtk_quad.vtk", vtk_ascii(TET_V + [(1, 1, 0)], TET_F[:3] + [(1, 4, 2, 3)]), "the repair it needs: triangulate polygons")
add("vtk_cells_before_points.vtk", "# vtk DataFile Version 4.2\nx\nASCII\nDATASET POLYDATA\nPOLYGONS 1 4\n3 0 1 2\n",
    "before POINTS")
add("vtk_point_data_count.vtk", vtk_ascii(TET_V, TET_F, body_extra="POINT_DATA 5\nSCALARS s float\nLOOKUP_TABLE default\n"
    "1 2 3 4 5\n"), "POINT_DATA 5, but the file has 4 points")
add("vtk_only_lines.vtk", vtk_ascii(TET_V, []).replace("POLYGONS 0 0\n", "LINES 2 6\n2 0 1\n2 1 2\n"), "2 line cells skipped")
add("vtk_tetrahedra.vtk", "# vtk DataFile Version 4.2\nx\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 float\n"
    "0 0 0 1 0 0 0 1 0 0 0 1\nCELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n10\n", "is a tetrahedron (VTK type 10)")
add("vtk_51_bad_offsets.vtk", "# vtk DataFile Version 5.1\nx\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n"
    "0 0 0 1 0 0 0 1 0\nPOLYGONS 2 3\nOFFSETS vtktypeint64\n0 4\nCONNECTIVITY vtktypeint64\n0 1 2\n",
    "offset 1 is 4; expected a value from 0 to 3")
add("vtk_unreferenced_vertex.vtk", vtk_ascii(TET_V + [(3, 3, 3)], TET_F), "not used by any triangle")
add("vtk_binary_truncated.vtk", vtk_binary(TET_V, TET_F)[:-30], "cannot hold that many")
add("vtk_binary_nan.vtk", vtk_binary([(0, 0, 0), (1, 0, 0), (0, float("nan"), 0), (0, 0, 1)], TET_F), "is NaN")
add("vtk_binary_index_out_of_range.vtk", vtk_binary(TET_V, TET_F[:3] + [(1, 2, 99)]), "point index 99 is out of range")
# Little-endian data under a format that is big endian by definition: counts come out huge.
add("vtk_binary_little_endian.vtk", vtk_binary(TET_V, TET_F).replace(
    b"".join(struct.pack(">4i", 3, *f) for f in TET_F), b"".join(struct.pack("<4i", 3, *f) for f in TET_F)), "cell 0 has")
add("vtk_binary_garbage.vtk", b"# vtk DataFile Version 4.2\nx\nBINARY\nDATASET POLYDATA\nPOINTS 5 float\n" +
    garbage(9, 150), "*")
add("vtk_random_bytes.vtk", garbage(10, 300), "*")


# ---- VTK XML (.vtp, .vtu) ----
def vtk_array(name, typ, values, fmt="ascii", comps=1, appended=None, zlib_data=False, header=None):
    """A DataArray element; binary data goes inline (base64) or into `appended` (a bytearray)."""
    import base64
    import zlib
    code = {"Float64": "d", "Float32": "f", "Int32": "i", "Int64": "q", "UInt8": "B"}[typ]
    attrs = '<DataArray type="%s" Name="%s" NumberOfComponents="%d" format="%s"' % (typ, name, comps, fmt)
    if fmt == "ascii":
        return attrs + ">\n" + " ".join(repr(v) if typ.startswith("Float") else str(v) for v in values) + "\n</DataArray>\n"
    data = struct.pack("<%d%s" % (len(values), code), *values)
    if zlib_data:
        block = zlib.compress(data)
        head = struct.pack("<4I", 1, 32768, len(data), len(block)) if header is None else header
        payload = (head, block)
    else:
        payload = ((struct.pack("<I", len(data)) if header is None else header) + data,)
    if fmt == "binary":
        return attrs + ">\n" + "".join(base64.b64encode(x).decode() for x in payload) + "\n</DataArray>\n"
    offset = len(appended)
    appended += b"".join(payload)
    return attrs + ' offset="%d"/>\n' % offset


def vtp(fmt="ascii", vertices=TET_V, faces=TET_F, zlib_data=False, offsets=None, extra="", header_of=None):
    appended = bytearray()
    def arr(name, typ, values, comps=1):
        return vtk_array(name, typ, values, fmt, comps, appended, zlib_data, header_of.get(name) if header_of else None)
    flat = [c for v in vertices for c in v]
    conn = [i for f in faces for i in f]
    offs = offsets if offsets is not None else [3 * (i + 1) for i in range(len(faces))]
    s = '<?xml version="1.0"?>\n<VTKFile type="PolyData" version="1.0" byte_order="LittleEndian" header_type="UInt32"%s>\n' % (
        ' compressor="vtkZLibDataCompressor"' if zlib_data else "")
    s += '<PolyData>\n<Piece NumberOfPoints="%d" NumberOfPolys="%d">\n' % (len(vertices), len(offs))
    s += "<PointData>\n" + arr("temperature", "Float64", [float(i) for i in range(len(vertices))]) + "</PointData>\n" + extra
    s += "<Points>\n" + arr("Points", "Float64", [float(c) for c in flat], 3) + "</Points>\n"
    s += "<Polys>\n" + arr("connectivity", "Int64", conn) + arr("offsets", "Int64", offs) + "</Polys>\n"
    s += "</Piece>\n</PolyData>\n"
    data = s.encode()
    if fmt == "appended":
        data += b'<AppendedData encoding="raw">\n_' + bytes(appended) + b"\n</AppendedData>\n"
    return data + b"</VTKFile>\n"


def vtu_cells(types, conn, offs):
    flat = [float(c) for v in TET_V for c in v]
    s = '<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian">\n<UnstructuredGrid>\n'
    s += '<Piece NumberOfPoints="4" NumberOfCells="%d">\n' % len(types)
    s += "<Points>\n" + vtk_array("Points", "Float64", flat, comps=3) + "</Points>\n<Cells>\n"
    s += vtk_array("connectivity", "Int64", conn) + vtk_array("offsets", "Int64", offs) + vtk_array("types", "UInt8", types)
    return s + "</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n"


add("vtp_empty.vtp", "", "empty")
add("vtp_not_xml.vtp", "OFF\n3 1 0\n", "not an XML file")
add("vtp_image_data.vtp", vtp().replace(b'type="PolyData"', b'type="ImageData"'), "VTKFile type 'ImageData' is not supported")
add("vtp_unknown_element.vtp", vtp().replace(b"<Points>", b"<Pointz/>\n<Points>"), "line 10: unknown element <Pointz> in <Piece>")
add("vtp_not_closed.vtp", vtp()[:-40], "the file ends inside a tag (truncated?)")
add("vtp_truncated_in_data.vtp", vtp()[:vtp().rindex(b"</DataArray>")], "<DataArray> is never closed")
add("vtp_mismatched_tag.vtp", vtp().replace(b"</Points>", b"</Polys>"), "</Polys> does not close <Points>")
add("vtp_bad_base64.vtp", vtp("binary").replace(b"AAAAAAAA", b"AAA*AAAA", 1), "invalid base64 character '*'")
add("vtp_offsets_decreasing.vtp", vtp(offsets=[3, 9, 6, 12]), "offsets must not decrease")
add("vtp_offsets_past_end.vtp", vtp(offsets=[3, 6, 9, 13]), "holds 12 values, 13 expected")
add("vtp_index_out_of_range.vtp", vtp(faces=[(0, 2, 1), (0, 1, 4), (0, 3, 2), (1, 2, 3)]), "is out of range (the piece has 4 points)")
add("vtp_nan.vtp", vtp(vertices=[(0, 0, 0), (1, 0, float("nan")), (0, 1, 0), (0, 0, 1)]), "is not a finite number")
add("vtp_quad.vtp", vtp(faces=[(0, 2, 1, 3)], offsets=[4]), "face 0 (4 corners) cannot be triangulated")
add("vtp_appended_truncated.vtp", vtp("appended")[:-60], "(truncated?)")
add("vtp_appended_bad_offset.vtp", vtp("appended").replace(b'offset="0"', b'offset="99999"'), "beyond the end of the appended data")
add("vtp_appended_no_section.vtp", vtp("appended").split(b"<AppendedData")[0] + b"</VTKFile>\n", "the file has no <AppendedData>")
add("vtp_zlib_absurd_size.vtp", vtp("binary", zlib_data=True, header_of={"temperature": struct.pack("<4I", 1, 4000000000, 0, 20)}),
    "absurd decompressed size")
add("vtp_zlib_corrupt.vtp", vtp("appended", zlib_data=True).replace(b"x\x9c", b"x\x9d", 1), "cannot be decompressed")
add("vtp_lz4.vtp", vtp("binary").replace(b'header_type="UInt32"', b'header_type="UInt32" compressor="vtkLZ4DataCompressor"'),
    "is not supported (only vtkZLibDataCompressor)")
add("vtu_only_tetrahedra.vtu", vtu_cells([10], [0, 1, 2, 3], [4]), "extract the boundary first")
add("vtu_triangle_with_four_points.vtu", vtu_cells([5], [0, 1, 2, 3], [4]), "triangle cell 0 has 4 points, 3 expected")

# ---- Amira HyperSurface (.surf) ---------------------------------------------------
def surf(vertices=TET_V, patches=(("A", "Exterior", TET_F),), binary=False):
    out = b"# HyperSurface 0.1 %s\n\n" % (b"BINARY" if binary else b"ASCII")
    out += b'Parameters {\n    Materials {\n        Exterior { Id 0 }\n        A { Color 1 0 0, Id 1 }\n    }\n'
    out += b'    Units { Coordinates "mm" }\n}\n'
    out += b"Vertices %d\n" % len(vertices)
    for v in vertices:
        out += struct.pack(">3f", *(float(c) for c in v)) if binary else (" ".join(str(c) for c in v) + "\n").encode()
    if binary:
        out += b"\n"
    out += b"NBranchingPoints 0\nNVerticesOnCurves 0\nBoundaryCurves 0\nPatches %d\n" % len(patches)
    for inner, outer, faces in patches:
        out += ("{\nInnerRegion %s\nOuterRegion %s\nBoundaryID 0\nBranchingPoints 0\n\nTriangles %d\n"
                % (inner, outer, len(faces))).encode()
        for f in faces:  # one-based in the file
            g = tuple(i + 1 for i in f)
            out += struct.pack(">3i", *g) if binary else ("%d %d %d\n" % g).encode()
        if binary:
            out += b"\n"
        out += b"}\n"
    return out


add("surf_empty.surf", "", "empty")
add("surf_amira_mesh.surf", "# AmiraMesh BINARY-LITTLE-ENDIAN 2.1\ndefine Nodes 4\n", "an AmiraMesh file, not a HyperSurface")
add("surf_version.surf", surf().replace(b"0.1 ASCII", b"0.2 ASCII"), "HyperSurface version '0.2' is not supported")
add("surf_index_zero.surf", surf(patches=(("A", "Exterior", TET_F[:3] + [(1, -1, 3)]),)), "vertex index 0 is out of range")
add("surf_index_out_of_range.surf", surf(patches=(("A", "Exterior", TET_F[:3] + [(1, 2, 4)]),)),
    "vertex index 5 is out of range (the file has 4 vertices, numbered from 1)")
add("surf_nan.surf", surf([(0, 0, 0), (1, "nan", 0), (0, 1, 0), (0, 0, 1)]), "is not a finite number")
add("surf_missing_triangle_count.surf", surf().replace(b"Triangles 4\n", b"Triangles\n"),
    "expected a count after 'Triangles', found the end of the line")
add("surf_unbalanced_braces.surf", surf().replace(b'"mm" }\n}\n', b'"mm" }\n'), "is never closed (unbalanced braces")
add("surf_patch_not_closed.surf", surf()[:-2], "the '{' of patch 0 is never closed")
add("surf_too_few_patches.surf", surf().replace(b"Patches 1", b"Patches 2"), "expected '{' opening patch 1")
add("surf_no_patches.surf", surf().split(b"Patches")[0], "no Patches section")
add("surf_interface_twice.surf", surf(patches=(("A", "Exterior", TET_F), ("A", "B", TET_F[:1]))),
    "the repair it needs: merge duplicate triangles")
add("surf_binary_truncated.surf", surf(binary=True)[:-30], "cannot hold that many")
add("surf_binary_nan.surf", surf([(0, 0, 0), (1, 0, 0), (0, float("nan"), 0), (0, 0, 1)], binary=True), "coordinate y is NaN")
add("surf_binary_index_out_of_range.surf", surf(patches=(("A", "Exterior", TET_F[:3] + [(1, 2, 98)]),), binary=True),
    "vertex index 99 is out of range")
add("surf_binary_unknown_key.surf", surf(binary=True).replace(b"BoundaryID 0\n", b"BoundaryID 0\nColour 1 0 0\n"),
    "cannot be skipped safely")
add("surf_random_bytes.surf", b"# HyperSurface 0.1 BINARY\n" + garbage(11, 300), "*")



def main():
    names = [f[0] for f in FILES]
    assert len(names) == len(set(names)), "duplicate file names"
    for old in os.listdir(HERE):
        if old.split(".")[-1] in ("off", "obj", "stl", "ply", "msh", "vtk", "vtp", "vtu", "surf"):
            os.remove(os.path.join(HERE, old))
    for name, data, _ in FILES:
        with open(os.path.join(HERE, name), "wb") as f:
            f.write(data)
    with open(os.path.join(HERE, "EXPECTED.tsv"), "w") as f:
        f.write("# file\tthe error message must contain (* = any non-empty message)\n")
        for name, _, expected in FILES:
            f.write("%s\t%s\n" % (name, expected))
    print("wrote %d files to %s" % (len(FILES), HERE))


if __name__ == "__main__":
    main()
