"""The unit cube with every face an n x n grid of squares split in two, outward normals,
as triangles of coordinate tuples (vertices shared between faces compare equal). Used by
the CLI tests that build their own cube (feature_lines_mean_one_thing.sh,
open_seam_merged_within_tolerance.sh): import it after putting tests/cli/lib on sys.path.
"""
import itertools


def cube_triangles(n, skip_face=None):
    """skip_face = (axis, side) leaves that face out (an open cube)."""
    tris = []
    for axis in range(3):
        for side in (0, 1):
            if skip_face == (axis, side):
                continue
            for i, j in itertools.product(range(n), range(n)):
                def p(a, b):
                    q = [0.0, 0.0, 0.0]
                    q[axis] = float(side)
                    q[(axis + 1) % 3] = a / n
                    q[(axis + 2) % 3] = b / n
                    return tuple(q)
                quad = [p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1)]
                if side == 0:
                    quad.reverse()
                tris += [(quad[0], quad[1], quad[2]), (quad[0], quad[2], quad[3])]
    return tris
