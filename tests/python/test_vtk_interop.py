"""Opens bpm files with VTK's own HDF reader (vtkHDFReader, VTK 9.1 as in ParaView
5.11) through the /VTKHDF group and checks that VTK sees the coarse surface: point and
cell counts, triangle cells with the right connectivity, and the patch cell data."""
import os
import subprocess
import sys

import h5py
import numpy as np

import vtk_test_common as common


def check(path):
    from vtkmodules.vtkIOHDF import vtkHDFReader
    from vtkmodules.util.numpy_support import vtk_to_numpy

    problems = []
    reader = vtkHDFReader()
    if not reader.CanReadFile(path):
        return ["vtkHDFReader.CanReadFile says no"]
    reader.SetFileName(path)
    reader.Update()
    grid = reader.GetOutput()
    with h5py.File(path, "r") as f:
        xyz = f["coarse/vertices"][()]
        tri = f["coarse/triangles"][()]
        patches = f["coarse/patches"][()]
    if grid.GetNumberOfPoints() != len(xyz):
        problems.append("VTK sees %d points, /coarse has %d" % (grid.GetNumberOfPoints(), len(xyz)))
    if grid.GetNumberOfCells() != len(tri):
        problems.append("VTK sees %d cells, /coarse has %d triangles" % (grid.GetNumberOfCells(), len(tri)))
    if problems:
        return problems
    if not np.array_equal(vtk_to_numpy(grid.GetPoints().GetData()), xyz):
        problems.append("points differ from /coarse/vertices")
    types = vtk_to_numpy(grid.GetCellTypesArray())
    if not np.all(types == 5):
        problems.append("cell types are not all VTK_TRIANGLE (5): %s" % np.unique(types))
    conn = vtk_to_numpy(grid.GetCells().GetConnectivityArray()).reshape(-1, 3)
    if not np.array_equal(conn, tri):
        problems.append("connectivity differs from /coarse/triangles")
    arr = grid.GetCellData().GetArray("patch")
    if arr is None:
        problems.append("no cell data array 'patch'")
    elif not np.array_equal(vtk_to_numpy(arr), patches):
        problems.append("cell data 'patch' differs from /coarse/patches")
    return problems


def main():
    args = common.parse_args()
    missing = common.vtk_missing("test_vtk_interop", "vtkmodules.vtkIOHDF")
    if missing:
        print(missing)
        return 1
    work = common.work_dir(args, "vtk_interop")
    files = [os.path.join(args.source, "spec", "examples", "two_triangles.bpm")]
    for kind in (["height_field", "24", "4"], ["octahedron", "3"], ["height_field", "240", "60"]):
        out = os.path.join(work, "_".join(kind) + ".bpm")
        subprocess.run([os.path.join(args.tools, "bpm-make-example")] + kind + [out], check=True)
        files.append(out)
    failed = common.report(files, check)
    print("test_vtk_interop: vtkHDFReader reads %d of %d bpm files correctly" % (len(files) - failed, len(files)))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
