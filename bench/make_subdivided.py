#!/usr/bin/python3
"""Loop subdivision of a triangulated OFF surface (bench/README.md, scaling benchmark).

    make_subdivided.py INPUT.off LEVELS OUTPUT.off

Each level splits every triangle into four (Loop 1987, "Smooth subdivision surfaces based
on triangles"): a new vertex on every edge at 3/8 (a + b) + 1/8 (c + d) (c, d the opposite
vertices of the two triangles at edge ab), or at the midpoint on a boundary edge; every old
vertex of valence n moves to (1 - n beta) v + beta * sum(neighbours) with Loop's
beta = (5/8 - (3/8 + 1/4 cos(2 pi / n))^2) / n, or to 3/4 v + 1/8 (two boundary
neighbours) on the boundary. Orientation is kept. Edges with more than two triangles are
refused (Loop subdivision is defined for manifolds). Needs numpy only.
"""
import sys

import numpy as np


def read_off(path):
    with open(path) as f:
        tokens = []
        for line in f:
            line = line.split("#", 1)[0]
            tokens.extend(line.split())
    if not tokens or tokens[0] != "OFF":
        raise ValueError(f"{path}: not an OFF file")
    nv, nf = int(tokens[1]), int(tokens[2])
    at = 4
    vertices = np.array(tokens[at:at + 3 * nv], dtype=np.float64).reshape(nv, 3)
    at += 3 * nv
    faces = np.empty((nf, 3), dtype=np.int64)
    for i in range(nf):
        if tokens[at] != "3":
            raise ValueError(f"{path}: face {i} is not a triangle")
        faces[i] = tokens[at + 1:at + 4]
        at += 4
    return vertices, faces


def write_off(path, vertices, faces):
    with open(path, "w") as f:
        f.write(f"OFF\n{len(vertices)} {len(faces)} 0\n")
        np.savetxt(f, vertices, fmt="%.17g")
        np.savetxt(f, np.hstack([np.full((len(faces), 1), 3), faces]), fmt="%d")


def loop_subdivide(vertices, faces):
    nv = len(vertices)
    # Half-edge k of face f runs from corner k to corner k+1; its opposite corner is k+2.
    start = faces.reshape(-1)
    end = faces[:, [1, 2, 0]].reshape(-1)
    opposite = faces[:, [2, 0, 1]].reshape(-1)
    lo, hi = np.minimum(start, end), np.maximum(start, end)
    edges, half_to_edge, edge_faces = np.unique(lo * nv + hi, return_inverse=True, return_counts=True)
    half_to_edge = half_to_edge.reshape(-1)
    if np.any(edge_faces > 2):
        raise ValueError("non-manifold edge (more than two triangles): Loop subdivision is undefined")
    ea, eb = edges // nv, edges % nv
    ne = len(edges)
    boundary = edge_faces == 1

    # Odd (edge) vertices.
    opposite_sum = np.zeros((ne, 3))
    np.add.at(opposite_sum, half_to_edge, vertices[opposite])
    odd = 0.375 * (vertices[ea] + vertices[eb]) + 0.125 * opposite_sum
    odd[boundary] = 0.5 * (vertices[ea[boundary]] + vertices[eb[boundary]])

    # Even (old) vertices: neighbours through unique edges.
    valence = np.bincount(ea, minlength=nv) + np.bincount(eb, minlength=nv)
    neighbour_sum = np.zeros((nv, 3))
    np.add.at(neighbour_sum, ea, vertices[eb])
    np.add.at(neighbour_sum, eb, vertices[ea])
    n = np.maximum(valence, 1).astype(np.float64)
    beta = (0.625 - (0.375 + 0.25 * np.cos(2.0 * np.pi / n)) ** 2) / n
    even = (1.0 - n * beta)[:, None] * vertices + beta[:, None] * neighbour_sum
    unused = valence == 0
    even[unused] = vertices[unused]
    # Boundary vertices: 3/4 v + 1/8 of their two boundary neighbours.
    bvalence = np.bincount(ea[boundary], minlength=nv) + np.bincount(eb[boundary], minlength=nv)
    bsum = np.zeros((nv, 3))
    np.add.at(bsum, ea[boundary], vertices[eb[boundary]])
    np.add.at(bsum, eb[boundary], vertices[ea[boundary]])
    on_boundary = bvalence > 0
    if np.any(bvalence[on_boundary] != 2):
        raise ValueError("a boundary vertex with other than two boundary edges")
    even[on_boundary] = 0.75 * vertices[on_boundary] + 0.125 * bsum[on_boundary]

    # Four triangles per triangle, same orientation.
    m = (nv + half_to_edge).reshape(-1, 3)  # m[:, k] = new vertex on edge k (corner k -> k+1)
    a, b, c = faces[:, 0], faces[:, 1], faces[:, 2]
    mab, mbc, mca = m[:, 0], m[:, 1], m[:, 2]
    new_faces = np.concatenate([
        np.stack([a, mab, mca], axis=1),
        np.stack([b, mbc, mab], axis=1),
        np.stack([c, mca, mbc], axis=1),
        np.stack([mab, mbc, mca], axis=1),
    ])
    return np.vstack([even, odd]), new_faces


def main(argv):
    if len(argv) != 4:
        sys.stderr.write(__doc__)
        return 2
    vertices, faces = read_off(argv[1])
    for _ in range(int(argv[2])):
        vertices, faces = loop_subdivide(vertices, faces)
    write_off(argv[3], vertices, faces)
    sys.stderr.write(f"make_subdivided.py: {argv[3]}: {len(vertices)} vertices, {len(faces)} triangles\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
