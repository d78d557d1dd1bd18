#!/usr/bin/python3
"""CAD-like test shapes with sharp creases, as OFF files (outward normals).

Usage: sharp_shapes.py SHAPE OUT.off
  cube10     unit cube, every face 10 x 10 squares of two triangles
  cube-quads unit cube as 6 quads (needs --triangulate-polygons)
  lblock     L-shaped block: three unit cubes (0,0,0), (1,0,0), (0,1,0), 6 x 6 squares per unit face
  cylinder   radius 1, height 2, 48 segments, 8 rings on the side, flat caps of 4 rings
"""
import math
import sys


def voxel_block(cells, res):
    cells = set(cells)
    verts, index, faces = [], {}, []

    def vertex(g):
        if g not in index:
            index[g] = len(verts)
            verts.append(tuple(c / res for c in g))
        return index[g]

    for (i, j, k) in sorted(cells):
        for axis in range(3):
            for side in (0, 1):
                n = [i, j, k]
                n[axis] += 1 if side else -1
                if tuple(n) in cells:
                    continue
                u, v = [a for a in range(3) if a != axis]
                for a in range(res):
                    for b in range(res):
                        def g(da, db):
                            p = [i * res, j * res, k * res]
                            p[axis] += res * side
                            p[u] += a + da
                            p[v] += b + db
                            return vertex(tuple(p))
                        q = [g(0, 0), g(1, 0), g(1, 1), g(0, 1)]
                        # (u, v, axis) right-handed: counter-clockwise seen from +axis.
                        outward = side == 1
                        if (axis == 1):
                            outward = not outward  # (u, v) = (x, z): x cross z = -y
                        if not outward:
                            q.reverse()
                        faces.append((q[0], q[1], q[2]))
                        faces.append((q[0], q[2], q[3]))
    return verts, faces


def cylinder(segments=48, rings=8, cap_rings=4, r=1.0, h=2.0):
    verts, faces = [], []
    side = []
    for l in range(rings + 1):
        z = h * l / rings
        side.append([len(verts) + s for s in range(segments)])
        for s in range(segments):
            a = 2 * math.pi * s / segments
            verts.append((r * math.cos(a), r * math.sin(a), z))
    for l in range(rings):
        for s in range(segments):
            a, b = side[l][s], side[l][(s + 1) % segments]
            c, d = side[l + 1][(s + 1) % segments], side[l + 1][s]
            faces += [(a, b, c), (a, c, d)]
    for top in (False, True):
        z = h if top else 0.0
        ring = side[-1] if top else side[0]
        for k in range(cap_rings - 1, 0, -1):
            inner = [len(verts) + s for s in range(segments)]
            for s in range(segments):
                a = 2 * math.pi * (s + 0.5 * (cap_rings - k)) / segments
                verts.append((r * k / cap_rings * math.cos(a), r * k / cap_rings * math.sin(a), z))
            for s in range(segments):
                a, b = ring[s], ring[(s + 1) % segments]
                c, d = inner[(s + 1) % segments], inner[s]
                for t in ((a, b, c), (a, c, d)):
                    faces.append(t if top else t[::-1])
            ring = inner
        centre = len(verts)
        verts.append((0.0, 0.0, z))
        for s in range(segments):
            t = (ring[s], ring[(s + 1) % segments], centre)
            faces.append(t if top else t[::-1])
    return verts, faces


def write_off(path, verts, faces):
    with open(path, "w") as f:
        f.write(f"OFF\n{len(verts)} {len(faces)} 0\n")
        for v in verts:
            f.write("%.17g %.17g %.17g\n" % v)
        for t in faces:
            f.write(f"{len(t)} " + " ".join(map(str, t)) + "\n")


def main():
    shape, out = sys.argv[1], sys.argv[2]
    if shape == "cube10":
        write_off(out, *voxel_block([(0, 0, 0)], 10))
    elif shape == "lblock":
        write_off(out, *voxel_block([(0, 0, 0), (1, 0, 0), (0, 1, 0)], 6))
    elif shape == "cylinder":
        write_off(out, *cylinder())
    elif shape == "cube-quads":
        v = [(x, y, z) for z in (0, 1) for y in (0, 1) for x in (0, 1)]
        q = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
        write_off(out, v, q)
    else:
        sys.exit("unknown shape " + shape)


if __name__ == "__main__":
    main()
