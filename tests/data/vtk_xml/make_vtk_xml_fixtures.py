#!/usr/bin/python3
"""Writes small VTK XML files with VTK itself (python3-vtk9), next to this script: the
unit tests read them (tests/unit/vtk_xml_test.cpp: real VTK bytes, not only bpm's own
encoder) and scripts/fuzz.sh uses them as seeds. A coarse vtkSphereSource (6 points, 8
triangles) with the point scalar "temperature" = x + 2y + 3z + 1 (Float64) and the cell
data "material" = 1, 2, 3, 1, ... (Int32), in each data mode VTK writes.

    /usr/bin/python3 tests/data/vtk_xml/make_vtk_xml_fixtures.py
"""
import os

import numpy as np
import vtk
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

HERE = os.path.dirname(os.path.abspath(__file__))


def sphere():
    source = vtk.vtkSphereSource()
    source.SetThetaResolution(4)
    source.SetPhiResolution(3)
    source.Update()
    poly = source.GetOutput()
    xyz = vtk_to_numpy(poly.GetPoints().GetData()).astype(np.float64)
    t = numpy_to_vtk(xyz[:, 0] + 2 * xyz[:, 1] + 3 * xyz[:, 2] + 1.0, deep=True)
    t.SetName("temperature")
    poly.GetPointData().AddArray(t)
    m = numpy_to_vtk((np.arange(poly.GetNumberOfCells()) % 3 + 1).astype(np.int32), deep=True)
    m.SetName("material")
    poly.GetCellData().AddArray(m)
    return poly


def write(writer, data, name, mode, compressor="None", encode=True, header="UInt32", order="LittleEndian"):
    writer.SetInputData(data)
    getattr(writer, "SetDataModeTo" + mode)()
    writer.SetEncodeAppendedData(encode)
    getattr(writer, "SetCompressorTypeTo" + compressor)()
    getattr(writer, "SetHeaderTypeTo" + header)()
    getattr(writer, "SetByteOrderTo" + order)()
    writer.SetFileName(os.path.join(HERE, name))
    assert writer.Write(), name


def main():
    poly = sphere()
    write(vtk.vtkXMLPolyDataWriter(), poly, "sphere_ascii.vtp", "Ascii")
    write(vtk.vtkXMLPolyDataWriter(), poly, "sphere_binary.vtp", "Binary")
    write(vtk.vtkXMLPolyDataWriter(), poly, "sphere_binary_zlib.vtp", "Binary", "ZLib")
    write(vtk.vtkXMLPolyDataWriter(), poly, "sphere_appended_base64_zlib_uint64.vtp", "Appended", "ZLib", True, "UInt64")
    write(vtk.vtkXMLPolyDataWriter(), poly, "sphere_appended_raw.vtp", "Appended", "None", False)
    write(vtk.vtkXMLPolyDataWriter(), poly, "sphere_appended_raw_zlib_big_endian.vtp", "Appended", "ZLib", False,
          "UInt64", "BigEndian")
    append = vtk.vtkAppendFilter()
    append.AddInputData(poly)
    append.Update()
    write(vtk.vtkXMLUnstructuredGridWriter(), append.GetOutput(), "sphere_appended_raw_zlib.vtu", "Appended", "ZLib",
          False)
    write(vtk.vtkXMLUnstructuredGridWriter(), append.GetOutput(), "sphere_ascii.vtu", "Ascii")
    print("wrote 8 files to %s (VTK %s)" % (HERE, vtk.vtkVersion.GetVTKVersion()))


if __name__ == "__main__":
    main()
