#!/usr/bin/python3
"""Two nested icospheres as OFF files: a multi-material fixture with a curved interface.

make_nested_spheres.py OUTER.off INNER.off [SUBDIVISIONS]   (default 4: 2562 vertices each)

OUTER has radius 1, INNER radius 0.5, same centre, both oriented outwards.
`bpm-simplify OUTER.off INNER.off --ratio R` gives two regions: the ball inside INNER and
the shell between them (one input file per material). The torsion problem -Δu = 1 in the
unit ball, u = 0 on its boundary, has J = ∫u = 4π/45 for the exact sphere; the reference
for the icosphere is computed like the other meshes' (bench/dune_torsion.py).
"""
import math
import sys


def icosphere(subdivisions):
    t = (1 + math.sqrt(5)) / 2
    verts = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
             (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    verts = [tuple(c / math.sqrt(sum(x * x for x in v)) for c in v) for v in verts]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(subdivisions):
        mid = {}

        def midpoint(a, b):
            key = (min(a, b), max(a, b))
            if key not in mid:
                m = [(verts[a][k] + verts[b][k]) / 2 for k in range(3)]
                n = math.sqrt(sum(x * x for x in m))
                mid[key] = len(verts)
                verts.append(tuple(x / n for x in m))
            return mid[key]

        new = []
        for a, b, c in faces:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            new += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = new
    return verts, faces


def write_off(path, verts, faces, radius):
    with open(path, "w") as f:
        f.write(f"OFF\n{len(verts)} {len(faces)} 0\n")
        for v in verts:
            f.write(" ".join(repr(radius * x) for x in v) + "\n")
        for a, b, c in faces:
            f.write(f"3 {a} {b} {c}\n")


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    n = int(sys.argv[3]) if len(sys.argv) > 3 else 4
    v, f = icosphere(n)
    write_off(sys.argv[1], v, f, 1.0)
    write_off(sys.argv[2], v, f, 0.5)
