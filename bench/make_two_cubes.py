#!/usr/bin/python3
"""The two-cubes fixture of the unit tests as an OBJ file with patch groups.

tests/unit/fixtures_surfaces.cpp: two_cubes(res) = voxel_surface(2, 1, 1, {1, 2}, res):
the unit cubes [0,1]^3 (material 1) and [1,2]x[0,1]^2 (material 2), every face between
cells of different labels (0 = outside) split into res x res quads of two triangles
(diagonal from the quad's first to third corner), normals from the higher label to the
lower one, patch = a * 100 + b for labels a < b: 1 = cube 1 outside, 2 = cube 2 outside,
102 = the shared square. bpm reads OBJ groups `patch_<id>` as patches.

Usage: make_two_cubes.py OUT.obj [RES]   (RES default 4: 4x4 quads per square)
"""
import sys


def two_cubes(res):
    labels = {(0, 0, 0): 1, (1, 0, 0): 2}
    n = (2, 1, 1)

    def label(c):
        return labels.get(tuple(c), 0)

    verts, index, faces = [], {}, []

    def vertex(g):
        if g not in index:
            index[g] = len(verts)
            verts.append(tuple(x / res for x in g))
        return index[g]

    for d in range(3):
        d1, d2 = (d + 1) % 3, (d + 2) % 3
        for cd in range(-1, n[d]):
            for c1 in range(n[d1]):
                for c2 in range(n[d2]):
                    c = [0, 0, 0]
                    c[d], c[d1], c[d2] = cd, c1, c2
                    e = list(c)
                    e[d] += 1
                    la, lb = label(c), label(e)
                    if la == lb:
                        continue
                    patch = min(la, lb) * 100 + max(la, lb)
                    for a in range(res):
                        for b in range(res):
                            q = []
                            for (u, v) in ((a, b), (a + 1, b), (a + 1, b + 1), (a, b + 1)):
                                g = [0, 0, 0]
                                g[d] = (c[d] + 1) * res
                                g[d1] = c[d1] * res + u
                                g[d2] = c[d2] * res + v
                                q.append(vertex(tuple(g)))
                            if la < lb:
                                q[1], q[3] = q[3], q[1]
                            faces.append((patch, (q[0], q[1], q[2])))
                            faces.append((patch, (q[0], q[2], q[3])))
    return verts, faces


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__.strip().splitlines()[-1])
    res = int(sys.argv[2]) if len(sys.argv) == 3 else 4
    verts, faces = two_cubes(res)
    with open(sys.argv[1], "w") as f:
        for v in verts:
            f.write("v %.17g %.17g %.17g\n" % v)
        last = None
        for patch, t in faces:
            if patch != last:
                f.write("g patch_%d\n" % patch)
                last = patch
            f.write("f %d %d %d\n" % tuple(i + 1 for i in t))


if __name__ == "__main__":
    main()
