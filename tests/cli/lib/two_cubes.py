#!/usr/bin/python3
"""Writes DIR/left.off = [0,1]^3 and DIR/right.off = [1,2]x[0,1]^2, outward normals: two
materials touching along the square x = 1, which is in both files, triangulated alike, in
opposite orientations (bpm-simplify fuses it with --merge-duplicate-vertices
--merge-duplicate-triangles). Used by the CLI tests (materials.sh, check_tetmesh.sh).
The same two cubes also as one OBJ each way a single file can hold two materials:
DIR/named.obj, groups `exterior|left`, `left|right` (the shared square, once) and
`exterior|right`; DIR/labels.obj, one closed surface per label, groups `patch_1` and
`patch_2` (the shared square in both).

    two_cubes.py DIR
"""
import sys


def cube(work, x0, name):
    v = [(x0 + i, j, k) for k in (0, 1) for j in (0, 1) for i in (0, 1)]
    idx = lambda i, j, k: i + 2 * j + 4 * k
    quads = [  # outward, counter-clockwise seen from outside
        (idx(0,0,0), idx(0,1,0), idx(1,1,0), idx(1,0,0)),  # z = 0
        (idx(0,0,1), idx(1,0,1), idx(1,1,1), idx(0,1,1)),  # z = 1
        (idx(0,0,0), idx(1,0,0), idx(1,0,1), idx(0,0,1)),  # y = 0
        (idx(0,1,0), idx(0,1,1), idx(1,1,1), idx(1,1,0)),  # y = 1
        (idx(0,0,0), idx(0,0,1), idx(0,1,1), idx(0,1,0)),  # x = x0
        (idx(1,0,0), idx(1,1,0), idx(1,1,1), idx(1,0,1)),  # x = x0 + 1
    ]
    tris = []
    for q in quads:
        # split every square along the diagonal from its smallest to its largest corner
        # position, so that the shared square is split alike in both files
        pos = [v[c] for c in q]
        s = min(range(4), key=lambda i: pos[i])
        q = q[s:] + q[:s]
        tris += [(q[0], q[1], q[2]), (q[0], q[2], q[3])]
    with open(f"{work}/{name}.off", "w") as f:
        f.write(f"OFF\n{len(v)} {len(tris)} 0\n")
        for p in v: f.write("%g %g %g\n" % p)
        for t in tris: f.write("3 %d %d %d\n" % t)
    return v, tris


def write_obj(path, groups):
    """groups: (name, [triangles as corner positions]); vertices shared by position."""
    ids, verts = {}, []
    with open(path, "w") as f:
        lines = []
        for name, triangles in groups:
            lines.append("g %s\n" % name)
            for t in triangles:
                for p in t:
                    if p not in ids:
                        ids[p] = len(verts) + 1
                        verts.append(p)
                lines.append("f %d %d %d\n" % tuple(ids[p] for p in t))
        f.writelines("v %g %g %g\n" % p for p in verts)
        f.writelines(lines)


if __name__ == "__main__":
    work = sys.argv[1]
    left = [tuple(p for p in (lv[c] for c in t)) for lv, ts in [cube(work, 0, "left")] for t in ts]
    right = [tuple(p for p in (rv[c] for c in t)) for rv, ts in [cube(work, 1, "right")] for t in ts]
    shared = {frozenset(t) for t in left} & {frozenset(t) for t in right}
    write_obj(f"{work}/named.obj", [("exterior|left", [t for t in left if frozenset(t) not in shared]),
                                    ("left|right", [t for t in left if frozenset(t) in shared]),
                                    ("exterior|right", [t for t in right if frozenset(t) not in shared])])
    write_obj(f"{work}/labels.obj", [("patch_1", left), ("patch_2", right)])
