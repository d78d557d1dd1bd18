#!/usr/bin/python3
"""Writes FILE.off: a solid slab [-2,2]^2 x [-1,0] whose top (a 5 x 5 grid) has a bump,
its centre vertex raised by 0.3, and a cavity under the bump: a small tetrahedron around
(0, 0, 0.1), its normals pointing into it (one file = one material: the cavity is
exterior, its outside the solid). Removing the bump's vertex flattens the top over the
cavity, which touches no new triangle: the intersection test passes, but the cavity would
then lie outside the solid (the island guard refuses it). Used by islands_stay_inside.sh.

    island.py FILE.off
"""
import sys


def slab_with_cavity(h=0.3):
    verts, tris = [], []
    n = 5
    top = lambda i, j: i * n + j
    bottom = lambda i, j: n * n + i * n + j
    for z in (0.0, -1.0):
        for i in range(n):
            for j in range(n):
                raised = z == 0.0 and i == 2 and j == 2
                verts.append((i - 2.0, j - 2.0, h if raised else z))
    for i in range(n - 1):
        for j in range(n - 1):
            a, b, c, d = top(i, j), top(i + 1, j), top(i + 1, j + 1), top(i, j + 1)
            tris += [(a, b, c), (a, c, d)]  # normal +z
            a, b, c, d = bottom(i, j), bottom(i + 1, j), bottom(i + 1, j + 1), bottom(i, j + 1)
            tris += [(a, c, b), (a, d, c)]  # normal -z
    ring = [(i, 0) for i in range(n - 1)] + [(n - 1, j) for j in range(n - 1)] + \
           [(i, n - 1) for i in range(n - 1, 0, -1)] + [(0, j) for j in range(n - 1, 0, -1)]
    for k in range(len(ring)):
        p, q = ring[k], ring[(k + 1) % len(ring)]
        a, b, c, d = top(*p), top(*q), bottom(*q), bottom(*p)
        tris += [(a, d, c), (a, c, b)]  # outward (the ring runs counter-clockwise seen from +z)
    # The cavity: a regular tetrahedron, inward normals.
    s, cz = 0.04, 0.1
    base = len(verts)
    verts += [(s, s, cz + s), (s, -s, cz - s), (-s, s, cz - s), (-s, -s, cz + s)]
    outward = [(0, 1, 2), (0, 3, 1), (0, 2, 3), (1, 3, 2)]
    tris += [(base + a, base + c, base + b) for a, b, c in outward]
    return verts, tris


def check_outward(verts, tris):
    # every slab triangle's normal points away from the slab's centre (0, 0, -0.5)
    for t in tris:
        if max(t) >= 50:
            continue
        p = [verts[i] for i in t]
        u = [p[1][k] - p[0][k] for k in range(3)]
        w = [p[2][k] - p[0][k] for k in range(3)]
        nrm = (u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0])
        c = [sum(q[k] for q in p) / 3 for k in range(3)]
        assert sum(nrm[k] * (c[k] - (0, 0, -0.5)[k]) for k in range(3)) > 0, t


if __name__ == "__main__":
    verts, tris = slab_with_cavity()
    check_outward(verts, tris)
    with open(sys.argv[1], "w") as f:
        f.write("OFF\n%d %d 0\n" % (len(verts), len(tris)))
        for v in verts:
            f.write("%.17g %.17g %.17g\n" % v)
        for t in tris:
            f.write("3 %d %d %d\n" % t)
