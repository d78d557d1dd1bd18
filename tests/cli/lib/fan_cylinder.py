#!/usr/bin/python3
"""A closed cylinder as CAD exporters write it: radius 1, height 1, N segments, RINGS rings
of N vertices on the side (RINGS - 1 bands of quads split in two), and each disc cap a fan
of N triangles around one centre vertex (valence N). Outward normals. Written as OFF.

N = 3000 with 5 rings gives 15002 vertices and 30000 triangles. Used by
tests/cli/fan_caps_simplified.sh and to measure bpm-simplify on huge fan centres.

Usage: fan_cylinder.py OUT.off N [RINGS]   (RINGS default 5)
"""
import math
import sys


def fan_cylinder(n, rings):
    verts = []
    for r in range(rings):
        z = r / (rings - 1)
        for k in range(n):
            a = 2.0 * math.pi * k / n
            verts.append((math.cos(a), math.sin(a), z))
    bottom, top = len(verts), len(verts) + 1
    verts += [(0.0, 0.0, 0.0), (0.0, 0.0, 1.0)]

    def v(r, k):
        return r * n + k % n

    tris = []
    for r in range(rings - 1):
        for k in range(n):
            a, b, c, d = v(r, k), v(r, k + 1), v(r + 1, k + 1), v(r + 1, k)
            tris += [(a, b, c), (a, c, d)]
    for k in range(n):
        tris.append((bottom, v(0, k + 1), v(0, k)))
        tris.append((top, v(rings - 1, k), v(rings - 1, k + 1)))
    return verts, tris


def write_off(path, verts, tris):
    """verts: (x, y, z) tuples, tris: (a, b, c) 0-based; also bench/make_fan_box.py's writer."""
    with open(path, "w") as f:
        f.write("OFF\n%d %d 0\n" % (len(verts), len(tris)))
        for p in verts:
            f.write("%.17g %.17g %.17g\n" % p)
        for t in tris:
            f.write("3 %d %d %d\n" % t)


def main():
    out, n = sys.argv[1], int(sys.argv[2])
    rings = int(sys.argv[3]) if len(sys.argv) > 3 else 5
    write_off(out, *fan_cylinder(n, rings))


if __name__ == "__main__":
    main()
