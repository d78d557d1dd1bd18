#!/usr/bin/python3
"""A synthetic segmentation for measuring bpm's label image reading: an N^3 uint8 NIfTI-1
image (.nii.gz) of 5 nested labels (ellipsoids 1 > 2 > 3 > 4 > 5 in background 0; off
centre so that no two axes are alike), written slice by slice (memory of one slice).

Usage: make_label_phantom.py N OUT.nii.gz
"""
import gzip
import struct
import sys

import numpy as np


def main():
    n, out = int(sys.argv[1]), sys.argv[2]
    h = bytearray(348)
    struct.pack_into("<i", h, 0, 348)
    struct.pack_into("<8h", h, 40, 3, n, n, n, 1, 1, 1, 1)
    struct.pack_into("<hh", h, 70, 2, 8)  # uint8
    struct.pack_into("<8f", h, 76, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0)
    struct.pack_into("<f", h, 108, 352.0)
    struct.pack_into("<f", h, 112, 1.0)
    h[123] = 2  # mm
    struct.pack_into("<h", h, 254, 1)
    for r in range(3):
        row = [0.0] * 4
        row[r] = 1.0
        row[3] = -n / 2
        struct.pack_into("<4f", h, 280 + 16 * r, *row)
    h[344:348] = b"n+1\0"
    y, x = np.mgrid[0:n, 0:n].astype(np.float64)  # one slice, indexed [j, i]
    c = np.array([0.5, 0.47, 0.52]) * n
    with gzip.open(out, "wb", compresslevel=1) as f:
        f.write(bytes(h) + b"\0\0\0\0")
        for k in range(n):
            s = np.zeros((n, n), np.uint8)
            for label, r in enumerate([0.45, 0.36, 0.27, 0.18, 0.09], start=1):
                d = ((x - c[0]) / (r * n)) ** 2 + ((y - c[1]) / (0.85 * r * n)) ** 2 + ((k - c[2]) / (0.9 * r * n)) ** 2
                s[d < 1] = label
            f.write(s.tobytes())


if __name__ == "__main__":
    main()
