"""VTK's own legacy writers (vtkPolyDataWriter, vtkUnstructuredGridWriter; ASCII and
binary, file versions 4.2 and 5.1, polygons and triangle strips) write a sphere with a
point scalar array and an int cell array "material"; bpm-check --surface must accept every
file and bpm-simplify must store, in /original of its .bpm output, exactly the points,
triangles, material ids and point data ("temperature") that VTK's own reader
(vtkPolyDataReader / vtkUnstructuredGridReader) reads from the same file."""
import os
import subprocess
import sys

import h5py
import numpy as np

import vtk_test_common as common


def make_sphere():
    import vtk
    from vtkmodules.util.numpy_support import numpy_to_vtk

    source = vtk.vtkSphereSource()
    source.SetThetaResolution(16)
    source.SetPhiResolution(12)
    source.SetRadius(2.5)
    source.Update()
    sphere = source.GetOutput()
    points = np.array([sphere.GetPoint(i) for i in range(sphere.GetNumberOfPoints())])
    temperature = numpy_to_vtk(points[:, 0] * 10.0 + points[:, 2])
    temperature.SetName("temperature")
    sphere.GetPointData().AddArray(temperature)
    centres = []
    for c in range(sphere.GetNumberOfCells()):
        ids = sphere.GetCell(c).GetPointIds()
        centres.append(np.mean([points[ids.GetId(k)] for k in range(ids.GetNumberOfIds())], axis=0))
    material = numpy_to_vtk(np.where(np.array(centres)[:, 2] > 0, 7, 3).astype(np.int32))
    material.SetName("material")
    sphere.GetCellData().AddArray(material)
    return sphere


def write_files(work):
    import vtk

    sphere = make_sphere()
    stripper = vtk.vtkStripper()
    stripper.SetInputData(sphere)
    stripper.Update()
    strips = stripper.GetOutput()
    # vtkStripper drops the cell data: every other strip gets material 7.
    from vtkmodules.util.numpy_support import numpy_to_vtk
    strip_material = numpy_to_vtk(np.array([3 + 4 * (c % 2) for c in range(strips.GetNumberOfCells())], dtype=np.int32))
    strip_material.SetName("material")
    strips.GetCellData().AddArray(strip_material)
    grid_filter = vtk.vtkAppendFilter()
    grid_filter.AddInputData(sphere)
    grid_filter.Update()
    grid = grid_filter.GetOutput()
    files = []
    for name, data, writer_class, binary, version in [
        ("poly_ascii_51.vtk", sphere, vtk.vtkPolyDataWriter, False, None),
        ("poly_binary_51.vtk", sphere, vtk.vtkPolyDataWriter, True, None),
        ("poly_ascii_42.vtk", sphere, vtk.vtkPolyDataWriter, False, 42),
        ("poly_binary_42.vtk", sphere, vtk.vtkPolyDataWriter, True, 42),
        ("strips_binary_51.vtk", strips, vtk.vtkPolyDataWriter, True, None),
        ("strips_ascii_42.vtk", strips, vtk.vtkPolyDataWriter, False, 42),
        ("grid_ascii_51.vtk", grid, vtk.vtkUnstructuredGridWriter, False, None),
        ("grid_binary_51.vtk", grid, vtk.vtkUnstructuredGridWriter, True, None),
        ("grid_binary_42.vtk", grid, vtk.vtkUnstructuredGridWriter, True, 42),
    ]:
        path = os.path.join(work, name)
        writer = writer_class()
        writer.SetInputData(data)
        writer.SetFileName(path)
        if binary:
            writer.SetFileTypeToBinary()
        else:
            writer.SetFileTypeToASCII()
        if version is not None:
            writer.SetFileVersion(version)
        if not writer.Write():
            raise RuntimeError("VTK could not write " + path)
        files.append(path)
    return files


def vtk_reads(path):
    """Points, triangles and material per triangle as VTK reads them; polydata (strips
    too) through vtkTriangleFilter, which splits strips the way bpm must."""
    import vtk
    from vtkmodules.util.numpy_support import vtk_to_numpy

    grid = "grid" in os.path.basename(path)
    reader = vtk.vtkUnstructuredGridReader() if grid else vtk.vtkPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    data = reader.GetOutput()
    points = vtk_to_numpy(data.GetPoints().GetData()).astype(np.float64)
    if grid:
        types = vtk_to_numpy(data.GetCellTypesArray())
        if not np.all(types == 5):
            raise RuntimeError("%s: cell types other than triangles: %s" % (path, np.unique(types)))
        triangles = vtk_to_numpy(data.GetCells().GetConnectivityArray()).reshape(-1, 3)
        patches = vtk_to_numpy(data.GetCellData().GetArray("material"))
    else:
        split = vtk.vtkTriangleFilter()
        split.SetInputData(data)
        split.Update()
        out = split.GetOutput()
        triangles = vtk_to_numpy(out.GetPolys().GetConnectivityArray()).reshape(-1, 3)
        patches = vtk_to_numpy(out.GetCellData().GetArray("material"))
    temperature = vtk_to_numpy(data.GetPointData().GetArray("temperature")).astype(np.float64)
    return points, triangles, patches, temperature


def check(path, tools, work):
    problems = []
    result = subprocess.run([os.path.join(tools, "bpm-check"), "--surface", path], capture_output=True, text=True)
    if result.returncode != 0:
        problems.append("bpm-check --surface: exit %d: %s%s" % (result.returncode, result.stdout, result.stderr))
    out = os.path.join(work, os.path.basename(path) + ".bpm")
    result = subprocess.run([os.path.join(tools, "bpm-simplify"), path, "-o", out, "--ratio", "0.5", "--deterministic"],
                            capture_output=True, text=True)
    if result.returncode != 0:
        return problems + ["bpm-simplify: exit %d: %s" % (result.returncode, result.stderr)]
    if "patch ids from the cell data array 'material'" not in result.stderr:
        problems.append("bpm-simplify does not report the material array: %s" % result.stderr)
    points, triangles, patches, temperature = vtk_reads(path)
    with h5py.File(out, "r") as f:
        xyz = f["original/vertices"][()]
        tri = f["original/triangles"][()]
        pat = f["original/patches"][()]
        data = f["original/point_data/temperature"][()] if "original/point_data/temperature" in f else None
    # VTK reads the text of an ASCII "POINTS n float" as float, bpm as double: the same
    # after rounding to float. Binary floats are the same doubles.
    if "ascii" in os.path.basename(path):
        xyz = xyz.astype(np.float32).astype(np.float64)
    if xyz.shape != points.shape or not np.array_equal(xyz, points):
        problems.append("/original/vertices differ from the points VTK reads (%s vs %s)" % (xyz.shape, points.shape))
    if tri.shape != triangles.shape or not np.array_equal(tri, triangles):
        problems.append("/original/triangles differ from VTK's triangles (%s vs %s)" % (tri.shape, triangles.shape))
    if pat.shape != patches.shape or not np.array_equal(pat, patches):
        problems.append("/original/patches differ from the cell data 'material'")
    elif set(np.unique(pat)) != {3, 7}:
        problems.append("patches are %s, expected 3 and 7" % np.unique(pat))
    if data is None:
        problems.append("no /original/point_data/temperature")
    elif data.shape != (len(points), 1) or not np.array_equal(data[:, 0], temperature):
        problems.append("/original/point_data/temperature differs from the point data VTK reads")
    return problems


def main():
    args = common.parse_args()
    missing = common.vtk_missing("test_vtk_legacy_reader", "vtk")
    if missing:
        print(missing)
        return 1
    work = common.work_dir(args, "vtk_legacy_reader")
    files = write_files(work)
    failed = common.report(files, lambda path: check(path, args.tools, work))
    print("test_vtk_legacy_reader: bpm reads %d of %d VTK-written .vtk files like VTK does" % (len(files) - failed, len(files)))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
