#!/usr/bin/python3
"""Label images for the tests of bpm's NIfTI reader and surface nets, written with numpy
alone (the NIfTI-1 header by hand, so that no nibabel is needed).

Usage: label_images.py OUTDIR
Writes
  spheres.nii.gz   two touching balls (labels 1 and 2) inside a box of label 3, background
                   0 around the box: three labels + background, junction lines where the
                   balls, the box and each other meet
  noisy.nii        a checkerboard-ish noisy image: blocks of labels 0-3 with random voxels
                   flipped (edge- and corner-touching voxels of one label everywhere)
  reflected.nii.gz spheres with a negative x axis in the sform (a reflection, as RAS/LPS
                   flips make them) and anisotropic voxels
  float.nii        spheres stored as float32 (integer values), with the qform instead of the sform
  spheres.seg.nrrd the spheres as 3D Slicer writes a segmentation: gzip encoding, LPS space
                   directions, segment names (bone, marrow, muscle) as key/value pairs
  spheres_raw.nrrd the same as raw int16 big-endian data with spacings only
  spheres.mha      the spheres as ITK writes a MetaImage: LPS (TransformMatrix -1 0 0 0 -1 0 0 0 1),
                   zlib-compressed data after the header
  spheres.mhd      the same as a header + spheres.raw (uint16, big-endian)
  bad_*.nii, bad_*.nrrd, bad_*.mhd  malformed files for the readers' error messages
The module's functions are used by tests/unit via the generated files only.
"""
import gzip
import os
import struct
import sys
import zlib

import numpy as np

DTYPES = {np.dtype(np.uint8): 2, np.dtype(np.int16): 4, np.dtype(np.int32): 8, np.dtype(np.float32): 16,
          np.dtype(np.uint16): 512, np.dtype(np.float64): 64}


def header(shape, dtype, spacing=(1.0, 1.0, 1.0), sform=None, qform=None, dim0=3, extra_dims=(),
           magic=b"n+1\0", vox_offset=352.0, datatype=None, bitpix=None):
    h = bytearray(348)
    struct.pack_into("<i", h, 0, 348)
    dims = [dim0] + list(shape) + list(extra_dims)
    dims += [1] * (8 - len(dims))
    struct.pack_into("<8h", h, 40, *dims)
    dt = DTYPES[np.dtype(dtype)] if datatype is None else datatype
    struct.pack_into("<h", h, 70, dt)
    struct.pack_into("<h", h, 72, np.dtype(dtype).itemsize * 8 if bitpix is None else bitpix)
    struct.pack_into("<8f", h, 76, 1.0, *spacing, 1.0, 1.0, 1.0, 1.0)
    struct.pack_into("<f", h, 108, vox_offset)
    struct.pack_into("<f", h, 112, 1.0)
    h[123] = 2  # mm
    if sform is not None:
        struct.pack_into("<h", h, 254, 1)
        for r in range(3):
            struct.pack_into("<4f", h, 280 + 16 * r, *sform[r])
    if qform is not None:
        b, c, d, ox, oy, oz, qfac = qform
        struct.pack_into("<h", h, 252, 1)
        struct.pack_into("<6f", h, 256, b, c, d, ox, oy, oz)
        struct.pack_into("<f", h, 76, qfac)
    h[344:348] = magic
    return bytes(h) + b"\0\0\0\0"


def write(path, data, **kw):
    """data indexed [i, j, k] (x fastest on disk, as NIfTI stores it)."""
    raw = header(data.shape, data.dtype, **kw) + np.ascontiguousarray(data.transpose(2, 1, 0)).astype(data.dtype.newbyteorder("<")).tobytes()
    opener = gzip.open if path.endswith(".gz") else open
    with opener(path, "wb") as f:
        f.write(raw)


def write_nrrd(path, data, fields, encoding="gzip", endian="little", dtype_name="uint8", keys=()):
    lines = ["NRRD0004", "# written by tests/cli/lib/label_images.py", "type: " + dtype_name, "dimension: 3",
             "sizes: %d %d %d" % data.shape, "encoding: " + encoding]
    if data.dtype.itemsize > 1:
        lines.append("endian: " + endian)
    lines += fields
    lines += ["%s:=%s" % kv for kv in keys]
    arr = np.ascontiguousarray(data.transpose(2, 1, 0)).astype(data.dtype.newbyteorder("<" if endian == "little" else ">"))
    raw = arr.tobytes()
    if encoding == "gzip":
        raw = gzip.compress(raw)
    with open(path, "wb") as f:
        f.write(("\n".join(lines) + "\n\n").encode() + raw)


def write_mha(path, data, fields, compressed=False, data_file=None, msb=False, met="MET_UCHAR"):
    """MetaImage: header, then the voxels (x fastest) after it or in `data_file` next to it."""
    arr = np.ascontiguousarray(data.transpose(2, 1, 0)).astype(data.dtype.newbyteorder(">" if msb else "<"))
    raw = arr.tobytes()
    if compressed:
        raw = zlib.compress(raw)
    lines = ["ObjectType = Image", "NDims = 3", "BinaryData = True", "BinaryDataByteOrderMSB = " + str(msb),
             "CompressedData = " + str(compressed)] + fields + [
        "DimSize = %d %d %d" % data.shape, "ElementType = " + met,
        "ElementDataFile = " + (data_file or "LOCAL")]
    head = ("\n".join(lines) + "\n").encode()
    if data_file:
        open(path, "wb").write(head)
        open(os.path.join(os.path.dirname(path), data_file), "wb").write(raw)
    else:
        open(path, "wb").write(head + raw)


def spheres(n=24):
    """Ball 1 (centre left) and ball 2 (centre right) touching each other, inside box 3."""
    x, y, z = np.meshgrid(np.arange(n), np.arange(n), np.arange(n), indexing="ij")
    img = np.zeros((n, n, n), np.uint8)
    img[2:n - 2, 2:n - 4, 3:n - 3] = 3
    r = n * 0.19
    c1 = np.array([n * 0.5 - r + 0.3, n * 0.47, n * 0.5])
    c2 = np.array([n * 0.5 + r - 0.3, n * 0.47, n * 0.5])
    img[(x - c1[0]) ** 2 + (y - c1[1]) ** 2 + (z - c1[2]) ** 2 < r * r] = 1
    img[(x - c2[0]) ** 2 + (y - c2[1]) ** 2 + (z - c2[2]) ** 2 < r * r] = 2
    return img


def noisy(n=14, seed=7):
    rng = np.random.default_rng(seed)
    i, j, k = np.meshgrid(np.arange(n), np.arange(n), np.arange(n), indexing="ij")
    img = (((i // 4) + (j // 4) + (k // 4)) % 4).astype(np.int16)
    flip = rng.random(img.shape) < 0.15
    img[flip] = rng.integers(0, 4, size=int(flip.sum()))
    return img


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    s = spheres()
    write(os.path.join(out, "spheres.nii.gz"), s, sform=[(1, 0, 0, -12), (0, 1, 0, -12), (0, 0, 1, -12)])
    write(os.path.join(out, "noisy.nii"), noisy())
    write(os.path.join(out, "reflected.nii.gz"), s, spacing=(0.8, 1.0, 1.5),
          sform=[(-0.8, 0, 0, 10), (0, 1.0, 0, -12), (0, 0, 1.5, 3)])
    # qform: 90 degrees about z (b = c = 0, d = sin 45), qfac -1 (a reflection of k).
    write(os.path.join(out, "float.nii"), s.astype(np.float32), qform=(0, 0, np.sqrt(0.5), 1, 2, 3, -1.0))
    small = s[:8, :8, :8]
    write(os.path.join(out, "bad_float_values.nii"), small.astype(np.float32) + np.float32(0.5))
    write(os.path.join(out, "bad_4d.nii"), np.zeros((4, 4, 4), np.uint8), dim0=4, extra_dims=(1,))
    with open(os.path.join(out, "bad_4d.nii"), "r+b") as f:  # dim[4] = 3 volumes, data for one
        f.seek(48)
        f.write(struct.pack("<h", 3))
    write(os.path.join(out, "bad_datatype.nii"), small, datatype=32, bitpix=64)  # complex64
    raw = open(os.path.join(out, "bad_datatype.nii"), "rb").read()
    full = header(s.shape, s.dtype) + s.tobytes()
    open(os.path.join(out, "bad_truncated.nii"), "wb").write(full[:len(full) // 2])
    open(os.path.join(out, "bad_header.nii"), "wb").write(full[:200])
    write(os.path.join(out, "bad_one_label.nii"), np.zeros((5, 5, 5), np.uint8))
    assert raw
    write_nrrd(os.path.join(out, "spheres.seg.nrrd"), s,
               ["space: left-posterior-superior", "space directions: (-1,0,0) (0,-1,0) (0,0,1)",
                "kinds: domain domain domain", "space origin: (12,12,-12)"],
               keys=[("Segment0_ID", "Segment_1"), ("Segment0_LabelValue", "1"), ("Segment0_Layer", "0"),
                     ("Segment0_Name", "bone"), ("Segment1_LabelValue", "2"), ("Segment1_Name", "marrow"),
                     ("Segment1_Layer", "0"), ("Segment2_LabelValue", "3"), ("Segment2_Name", "muscle")])
    write_nrrd(os.path.join(out, "spheres_raw.nrrd"), s.astype(np.int16), ["spacings: 1 1 2"], encoding="raw",
               endian="big", dtype_name="short")
    write_nrrd(os.path.join(out, "bad_type.nrrd"), small.astype(np.float32), [], encoding="raw", dtype_name="block")
    write_nrrd(os.path.join(out, "bad_layers.nrrd"), small, [], keys=[("Segment0_Layer", "1")])
    lps = ["TransformMatrix = -1 0 0 0 -1 0 0 0 1", "Offset = 12 12 -12", "CenterOfRotation = 0 0 0",
           "AnatomicalOrientation = RAI", "ElementSpacing = 1 1 1"]
    write_mha(os.path.join(out, "spheres.mha"), s, lps, compressed=True)
    write_mha(os.path.join(out, "spheres.mhd"), s.astype(np.uint16), lps, data_file="spheres.raw", msb=True,
              met="MET_USHORT")
    write_mha(os.path.join(out, "bad_missing_data.mhd"), s, lps, data_file="nowhere.raw")
    os.remove(os.path.join(out, "nowhere.raw"))
    full = open(os.path.join(out, "spheres_raw.nrrd"), "rb").read()
    open(os.path.join(out, "bad_truncated.nrrd"), "wb").write(full[:len(full) - 100])


if __name__ == "__main__":
    main()
