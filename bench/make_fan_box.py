#!/usr/bin/python3
"""A square prism whose two square faces are fans around their centres, as CAD exporters
write them: side 1, height 0.5, M segments per square side (4 M rim vertices), the sides
one band of quads split in two, each square face 4 M triangles around one centre vertex.

Unlike the round caps of tests/cli/lib/fan_cylinder.py, the rims have collinear corners
and removing a centre with up to about 250 corners (M = 250) passes the shape limit, so
VertexRemover's early refusal does not apply: it is planned again each time a rim vertex
goes. Its polygon is put on a circle by the polar map (collinear corners), and such a
polygon of more than 64 corners is cut in O(n log n) (fan_retriangulation.cpp
cut_indexed_ears; it was O(n^2)): M = 250 / 500, 2.62 / 29.9 CPU s before, 1.14 / 7.37
after (fanbox branch, 2026-12-07, bench/results/manual/cad-fans.md), outputs unchanged.
M = 250 (2002 vertices), --ratio 0.1 --threads 1, CPU s, medians of 3 alternated rounds
(fans branch): 5.21 before, 4.91 with the refusal and the coplanar test, 2.83 with the
polar-ear test's quick side rejection (fan_retriangulation.cpp in_closed_triangle; the
exact orient2d of collinear rim corners was 27 % of the run). Outputs unchanged.

Usage: make_fan_box.py OUT.off M
"""
import os
import sys


def fan_box(m, height=0.5):
    verts, index, tris = [], {}, []

    def v(p):
        if p not in index:
            index[p] = len(verts)
            verts.append(p)
        return index[p]

    def rim(z):
        pts = []
        for side in range(4):
            for k in range(m):
                t = k / m
                x, y = [(t, 0), (1, t), (1 - t, 1), (0, 1 - t)][side]
                pts.append((x, y, z))
        return pts

    bottom, top = rim(0.0), rim(height)
    n = len(bottom)
    for i in range(n):
        a, b = v(bottom[i]), v(bottom[(i + 1) % n])
        c, d = v(top[(i + 1) % n]), v(top[i])
        tris += [(a, b, c), (a, c, d)]
    centre_bottom, centre_top = v((0.5, 0.5, 0.0)), v((0.5, 0.5, height))
    for i in range(n):
        tris.append((centre_bottom, v(bottom[(i + 1) % n]), v(bottom[i])))
        tris.append((centre_top, v(top[i]), v(top[(i + 1) % n])))
    return verts, tris


def main():
    verts, tris = fan_box(int(sys.argv[2]))
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "cli", "lib"))
    from fan_cylinder import write_off
    write_off(sys.argv[1], verts, tris)


if __name__ == "__main__":
    main()
