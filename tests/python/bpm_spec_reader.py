"""An independent reader and phi evaluator for bpm files, written from
spec/bpm-format.md using only h5py and numpy (no libbpm). Shared by the Python tests.
"""
import h5py
import numpy as np

SUPPORTED_MAJORS = (1, 2)  # 2.0 dropped /phi/node_image: the reader recomputes it (spec 6.2)


class SpecError(Exception):
    pass


def _string(value):
    if isinstance(value, bytes):
        return value.decode("utf-8")
    if isinstance(value, np.ndarray):
        return _string(value[()])
    return str(value)


def read(path):
    """Reads a bpm file into a dict of numpy arrays, checking identification and shapes."""
    with h5py.File(path, "r") as f:
        if _string(f.attrs.get("format", b"")) != "bpm":
            raise SpecError("root attribute 'format' is not 'bpm'")
        version = [int(v) for v in f.attrs["format_version"]]
        if version[0] not in SUPPORTED_MAJORS:
            raise SpecError("unsupported major version %d" % version[0])
        d = {"format_version": version, "units": _string(f.attrs.get("units", b""))}
        for group in ("original", "coarse"):
            d[group + "/vertices"] = f[group + "/vertices"][()].astype(np.float64)
            d[group + "/triangles"] = f[group + "/triangles"][()].astype(np.int64)
            d[group + "/patches"] = f[group + "/patches"][()].astype(np.int64)
        d["coarse/vertex_origin"] = f["coarse/vertex_origin"][()].astype(np.int64)
        # Optional since 1.2 (spec 5.1): per-vertex data of S0, one (#V0, k) dataset per array.
        d["original/point_data"] = {}
        if "original/point_data" in f:
            for name, ds in f["original/point_data"].items():
                a = ds[()].astype(np.float64)
                if a.ndim != 2 or a.shape[0] != len(d["original/vertices"]) or a.shape[1] < 1:
                    raise SpecError("/original/point_data/%s has shape %s" % (name, a.shape))
                d["original/point_data"][name] = a
        for name in ("node_offsets", "node_kind", "node_original_vertex", "node_original_edge",
                     "piece_offsets", "pieces", "piece_original_triangle"):
            d["phi/" + name] = f["phi/" + name][()].astype(np.int64)
        for name in ("node_barycentric", "node_edge_parameter"):
            d["phi/" + name] = f["phi/" + name][()].astype(np.float64)
        if version[0] == 1:  # stored in 1.x (and equal to the recomputation); kept for comparing
            d["phi/stored_node_image"] = f["phi/node_image"][()].astype(np.float64)
        # Optional since 1.3 (spec 5.2): per patch a name and the materials on its two sides.
        d["patch_info"] = {}
        if "patch_info" in f:
            g = f["patch_info"]
            rows = zip(g["patch"][()], g["name"][()], g["front_material"][()], g["back_material"][()], g["oriented"][()])
            for patch, name, front, back, oriented in rows:
                if int(oriented) not in (0, 1) or int(patch) in d["patch_info"]:
                    raise SpecError("/patch_info: bad row for patch %d" % int(patch))
                d["patch_info"][int(patch)] = {"name": _string(name), "front": _string(front),
                                               "back": _string(back), "oriented": bool(oriented)}
        d["provenance"] = [
            tuple(_string(x) for x in row)
            for row in zip(*(f["provenance/" + k][()] for k in ("tool", "version", "arguments", "timestamp")))
        ]
    tc = len(d["coarse/triangles"])
    for name in ("node_offsets", "piece_offsets"):
        off = d["phi/" + name]
        if off.shape != (tc + 1,) or off[0] != 0 or np.any(np.diff(off) < 0):
            raise SpecError("bad CSR offsets in /phi/" + name)
    if d["phi/node_offsets"][-1] != len(d["phi/node_kind"]) or d["phi/piece_offsets"][-1] != len(d["phi/pieces"]):
        raise SpecError("CSR offsets do not end at the dataset length")
    d["phi/node_image"] = node_images(d)
    return d


def node_images(d):
    """phi(node) for every node, from what the node is (spec 6.2): x_v for an original vertex
    or coarse corner, (1-s)*x_u + s*x_w for an edge crossing, computed with exactly that
    expression in float64."""
    x = d["original/vertices"]
    kind = d["phi/node_kind"]
    crossing = kind == 1
    image = np.empty((len(kind), 3))
    image[~crossing] = x[d["phi/node_original_vertex"][~crossing]]
    e = d["phi/node_original_edge"][crossing]
    s = d["phi/node_edge_parameter"][crossing][:, None]
    image[crossing] = (1 - s) * x[e[:, 0]] + s * x[e[:, 1]]
    return image


def node_in_original(d, node, tri):
    """Barycentric coordinates of a node in original triangle `tri` (3 vertex ids),
    derived from the node's kind as the spec prescribes."""
    beta = np.zeros(3)
    kind = d["phi/node_kind"][node]
    if kind == 1:  # EdgeCrossing on original edge (u, w) at parameter s
        u, w = d["phi/node_original_edge"][node]
        s = d["phi/node_edge_parameter"][node]
        beta[list(tri).index(u)] = 1 - s
        beta[list(tri).index(w)] = s
    else:  # OriginalVertex (0) or CoarseCorner (2)
        beta[list(tri).index(d["phi/node_original_vertex"][node])] = 1
    return beta


def data_at(d, name, otri, obary):
    """The value of point data array `name` at points given by original triangle and
    barycentric coordinates in it (from evaluate): linear interpolation, spec 5.1."""
    values = d["original/point_data"][name]
    corners = d["original/triangles"][otri]                         # (q, 3)
    return np.einsum("qk,qkc->qc", obary, values[corners])


def evaluate(d, triangles, barycentrics):
    """phi at (coarse triangle, barycentric) queries, following "Evaluating phi" of the spec:
    the piece whose barycentric coordinates of the query have the largest minimum,
    then linear interpolation. Returns position, original triangle, original barycentric,
    normal."""
    q = len(triangles)
    pos = np.zeros((q, 3))
    otri = np.zeros(q, dtype=np.int64)
    obary = np.zeros((q, 3))
    normal = np.zeros((q, 3))
    X = d["original/vertices"]
    T0 = d["original/triangles"]
    noff, poff = d["phi/node_offsets"], d["phi/piece_offsets"]
    for t in np.unique(triangles):
        idx = np.nonzero(triangles == t)[0]
        B = barycentrics[idx]
        P = d["phi/pieces"][poff[t]:poff[t + 1]] + noff[t]           # (p, 3) global node ids
        corners = d["phi/node_barycentric"][P]                      # (p, corner, coordinate)
        inv = np.linalg.inv(np.transpose(corners, (0, 2, 1)))       # columns = corners
        lam = np.einsum("pij,qj->qpi", inv, B)                      # (q, p, 3)
        best = lam.min(axis=2).argmax(axis=1)
        L = lam[np.arange(len(idx)), best]
        neg = L.min(axis=1) < 0
        if np.any(neg):
            Ln = np.maximum(L[neg], 0)
            L[neg] = Ln / Ln.sum(axis=1, keepdims=True)
        nodes = P[best]                                             # (q, 3)
        pos[idx] = np.einsum("qk,qkd->qd", L, d["phi/node_image"][nodes])
        ot = d["phi/piece_original_triangle"][poff[t] + best]
        otri[idx] = ot
        for r, i in enumerate(idx):
            tri = T0[ot[r]]
            obary[i] = sum(L[r, k] * node_in_original(d, nodes[r, k], tri) for k in range(3))
            n = np.cross(X[tri[1]] - X[tri[0]], X[tri[2]] - X[tri[0]])
            normal[i] = n / np.linalg.norm(n)
    return pos, otri, obary, normal
