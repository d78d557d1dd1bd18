"""VTK writes .vtp and .vtu files, bpm reads them: a vtkSphereSource with a point scalar
"temperature" and a cell data "material" array, through vtkXMLPolyDataWriter in each data
mode (ascii, binary, appended base64, appended raw) with and without zlib, UInt32 and
UInt64 headers, big-endian, and through vtkXMLUnstructuredGridWriter. For each file bpm-check
--surface must accept it, and bpm-simplify must read it with VTK's vertex and triangle
counts and store the point data in the .bpm file with VTK's values and the material as
patches. The parallel writers' .pvtp and .pvtu (3 pieces each) must read as the whole
sphere: the points the pieces share merged, every triangle once, the point data and the
material kept. Last, bpm-refine --data writes one of the results as .vtu and bpm reads it
back."""
import os
import subprocess
import sys

import h5py
import numpy as np

import vtk_test_common as common


def sphere():
    import vtk
    from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

    source = vtk.vtkSphereSource()
    source.SetThetaResolution(16)
    source.SetPhiResolution(9)
    source.Update()
    poly = source.GetOutput()
    xyz = vtk_to_numpy(poly.GetPoints().GetData()).astype(np.float64)
    temperature = numpy_to_vtk(xyz[:, 0] + 2 * xyz[:, 1] + 3 * xyz[:, 2] + 1.0, deep=True)
    temperature.SetName("temperature")
    poly.GetPointData().AddArray(temperature)
    material = numpy_to_vtk((np.arange(poly.GetNumberOfCells()) % 3 + 1).astype(np.int32), deep=True)
    material.SetName("material")
    poly.GetCellData().AddArray(material)
    return poly


def write_files(poly, work):
    import vtk

    files = []
    modes = [("ascii", "SetDataModeToAscii", None), ("binary", "SetDataModeToBinary", None),
             ("appended", "SetDataModeToAppended", True), ("appended_raw", "SetDataModeToAppended", False)]
    for name, mode, encode in modes:
        for compressor in ("None", "ZLib"):
            for header in ("UInt32", "UInt64"):
                if name == "ascii" and (compressor != "None" or header != "UInt32"):
                    continue
                w = vtk.vtkXMLPolyDataWriter()
                w.SetInputData(poly)
                getattr(w, mode)()
                if encode is not None:
                    w.SetEncodeAppendedData(encode)
                getattr(w, "SetCompressorTypeTo" + compressor)()
                getattr(w, "SetHeaderTypeTo" + header)()
                path = os.path.join(work, "sphere_%s_%s_%s.vtp" % (name, compressor.lower(), header))
                w.SetFileName(path)
                if not w.Write():
                    raise RuntimeError("VTK could not write " + path)
                files.append(path)
    for encode in (True, False):
        w = vtk.vtkXMLPolyDataWriter()
        w.SetInputData(poly)
        w.SetDataModeToAppended()
        w.SetEncodeAppendedData(encode)
        w.SetCompressorTypeToZLib()
        w.SetByteOrderToBigEndian()
        path = os.path.join(work, "sphere_big_endian_%s.vtp" % ("base64" if encode else "raw"))
        w.SetFileName(path)
        if not w.Write():
            raise RuntimeError("VTK could not write " + path)
        files.append(path)
    ugrid_filter = vtk.vtkAppendFilter()
    ugrid_filter.AddInputData(poly)
    ugrid_filter.Update()
    grid = ugrid_filter.GetOutput()
    for mode, compressor in (("SetDataModeToAppended", "ZLib"), ("SetDataModeToAscii", "None"),
                             ("SetDataModeToBinary", "None")):
        w = vtk.vtkXMLUnstructuredGridWriter()
        w.SetInputData(grid)
        getattr(w, mode)()
        getattr(w, "SetCompressorTypeTo" + compressor)()
        path = os.path.join(work, "sphere_%s_%s.vtu" % (mode[len("SetDataModeTo"):].lower(), compressor.lower()))
        w.SetFileName(path)
        if not w.Write():
            raise RuntimeError("VTK could not write " + path)
        files.append(path)
    return files


def write_parallel_files(poly, work):
    """The sphere in 3 pieces through vtkXMLPPolyDataWriter and vtkXMLPUnstructuredGridWriter
    (the pieces cut from the whole data by vtkExtract*Piece), ghost level 0."""
    import vtk

    producer = vtk.vtkTrivialProducer()
    producer.SetOutput(poly)
    ugrid_filter = vtk.vtkAppendFilter()
    ugrid_filter.AddInputData(poly)
    ugrid_filter.Update()
    grid_producer = vtk.vtkTrivialProducer()
    grid_producer.SetOutput(ugrid_filter.GetOutput())
    files = []
    for name, extract, writer, source in (("pvtp", vtk.vtkExtractPolyDataPiece, vtk.vtkXMLPPolyDataWriter, producer),
                                          ("pvtu", vtk.vtkExtractUnstructuredGridPiece,
                                           vtk.vtkXMLPUnstructuredGridWriter, grid_producer)):
        pieces = extract()
        pieces.SetInputConnection(source.GetOutputPort())
        w = writer()
        w.SetInputConnection(pieces.GetOutputPort())
        w.SetNumberOfPieces(3)
        w.SetStartPiece(0)
        w.SetEndPiece(2)
        w.SetGhostLevel(0)
        path = os.path.join(work, "sphere_parallel.%s" % name)
        w.SetFileName(path)
        if not w.Write():
            raise RuntimeError("VTK could not write " + path)
        files.append(path)
    return files


def check_parallel(path, poly, tools, work):
    """bpm reads the pieces as the whole sphere."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    r = subprocess.run([os.path.join(tools, "bpm-check"), "--surface", path], capture_output=True, text=True)
    if r.returncode != 0:
        return ["bpm-check --surface: exit %d: %s" % (r.returncode, (r.stderr or r.stdout).strip()[:300])]
    out = os.path.join(work, os.path.basename(path) + ".bpm")
    r = subprocess.run([os.path.join(tools, "bpm-simplify"), path, "-o", out, "--ratio", "0.5", "--deterministic"],
                       capture_output=True, text=True)
    if r.returncode != 0:
        return ["bpm-simplify: exit %d: %s" % (r.returncode, r.stderr.strip()[:300])]
    problems = []
    if "3 pieces joined" not in r.stderr:
        problems.append("no '3 pieces joined' note in the log: " + r.stderr.strip()[:300])
    with h5py.File(out, "r") as f:
        vertices = f["original/vertices"][()]
        triangles = f["original/triangles"][()]
        patches = np.asarray(f["original/patches"][()]).reshape(-1)
        stored = np.asarray(f["original/point_data/temperature"][()]).reshape(-1)
    if len(vertices) != poly.GetNumberOfPoints():
        problems.append("bpm read %d vertices, the whole sphere has %d points" % (len(vertices), poly.GetNumberOfPoints()))
    if len(triangles) != poly.GetNumberOfCells():
        problems.append("bpm read %d triangles, the whole sphere has %d" % (len(triangles), poly.GetNumberOfCells()))
    # The point data went with its points: temperature = x + 2y + 3z + 1 at every vertex.
    expected = vertices[:, 0] + 2 * vertices[:, 1] + 3 * vertices[:, 2] + 1.0
    if len(stored) != len(vertices) or not np.array_equal(stored, expected):
        problems.append("point data 'temperature' does not match its points")
    # Each triangle kept its material: the same count of each material as the whole sphere.
    material = vtk_to_numpy(poly.GetCellData().GetArray("material"))
    if sorted(np.unique(patches, return_counts=True)[1]) != sorted(np.unique(material, return_counts=True)[1]):
        problems.append("patch sizes differ from the materials' cell counts")
    return problems


def vtk_counts(path):
    import vtk
    from vtkmodules.util.numpy_support import vtk_to_numpy

    reader = vtk.vtkXMLPolyDataReader() if path.endswith(".vtp") else vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    data = reader.GetOutput()
    temperature = vtk_to_numpy(data.GetPointData().GetArray("temperature"))
    material = vtk_to_numpy(data.GetCellData().GetArray("material"))
    return data.GetNumberOfPoints(), data.GetNumberOfCells(), temperature, material


def check(path, tools, work):
    problems = []
    npoints, ncells, temperature, material = vtk_counts(path)
    r = subprocess.run([os.path.join(tools, "bpm-check"), "--surface", path], capture_output=True, text=True)
    if r.returncode != 0:
        return ["bpm-check --surface: exit %d: %s" % (r.returncode, (r.stderr or r.stdout).strip()[:300])]
    out = os.path.join(work, os.path.basename(path) + ".bpm")
    r = subprocess.run([os.path.join(tools, "bpm-simplify"), path, "-o", out, "--ratio", "0.5", "--deterministic",
                        "-q"], capture_output=True, text=True)
    if r.returncode != 0:
        return ["bpm-simplify: exit %d: %s" % (r.returncode, r.stderr.strip()[:300])]
    with h5py.File(out, "r") as f:
        vertices = f["original/vertices"][()]
        triangles = f["original/triangles"][()]
        patches = f["original/patches"][()] if "original/patches" in f else None
        group = f.get("original/point_data")
        stored = group["temperature"][()] if group is not None and "temperature" in group else None
    if len(vertices) != npoints:
        problems.append("bpm read %d vertices, VTK %d points" % (len(vertices), npoints))
    if len(triangles) != ncells:
        problems.append("bpm read %d triangles, VTK %d cells" % (len(triangles), ncells))
    if stored is None:
        problems.append("no /original/point_data/temperature in the .bpm file")
    elif not np.array_equal(np.asarray(stored).reshape(-1), temperature.astype(np.float64)):
        problems.append("point data 'temperature' differs from what VTK reads")
    if patches is None or not np.array_equal(np.asarray(patches).reshape(-1), material):
        problems.append("patches differ from the cell data 'material'")
    return problems


def main():
    args = common.parse_args()
    missing = common.vtk_missing("test_vtk_xml_reader", "vtk")
    if missing:
        print(missing)
        return 1
    work = common.work_dir(args, "vtk_xml_reader")
    poly = sphere()
    files = write_files(poly, work)
    failed = common.report(files, lambda path: check(path, args.tools, work))
    parallel = write_parallel_files(poly, work)
    failed += common.report(parallel, lambda path: check_parallel(path, poly, args.tools, work))
    files += parallel
    # Round trip through bpm-refine's own .vtu writer: the refined surface and its
    # interpolated point data read back.
    coarse = os.path.join(work, os.path.basename(files[0]) + ".bpm")
    refined = os.path.join(work, "refined.vtu")
    again = os.path.join(work, "refined.bpm")
    problems = []
    r = subprocess.run([os.path.join(args.tools, "bpm-refine"), coarse, "-o", refined, "--levels", "1", "--data", "-q"],
                       capture_output=True, text=True)
    if r.returncode != 0:
        problems.append("bpm-refine -o refined.vtu --data: exit %d: %s" % (r.returncode, r.stderr.strip()[:300]))
    else:
        r = subprocess.run([os.path.join(args.tools, "bpm-simplify"), refined, "-o", again, "--ratio", "0.5", "-q",
                            "--deterministic"], capture_output=True, text=True)
        if r.returncode != 0:
            problems.append("bpm-simplify refined.vtu: exit %d: %s" % (r.returncode, r.stderr.strip()[:300]))
        else:
            import vtk
            reader = vtk.vtkXMLUnstructuredGridReader()
            reader.SetFileName(refined)
            reader.Update()
            grid = reader.GetOutput()
            with h5py.File(again, "r") as f:
                if len(f["original/vertices"]) != grid.GetNumberOfPoints():
                    problems.append("refined.vtu: bpm read %d vertices, VTK %d" % (len(f["original/vertices"]),
                                                                                  grid.GetNumberOfPoints()))
                if "original/point_data/temperature" not in f:
                    problems.append("refined.vtu: the interpolated temperature did not come through")
    print("refined.vtu (bpm-refine --data, read back): %s" % ("ok" if not problems else "FAILED"))
    for p in problems:
        print("  " + p)
    failed += bool(problems)
    print("test_vtk_xml_reader: bpm reads %d of %d VTK XML files correctly" % (len(files) + 1 - failed, len(files) + 1))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
