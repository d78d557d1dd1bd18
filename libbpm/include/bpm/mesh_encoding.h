#pragma once
// How the MSH and VTU writers store numbers (write_surface in bpm/surface_io.h,
// write_surface_vtu in bpm/write_vtu.h, write_tetmesh in bpm/write_tetmesh.h). On a
// level-6 refinement (3.2M triangles, bench/RESULTS.md "Output formats") binary VTU is
// 40 % of the ASCII size (zlib 24 %), binary MSH 74 %, and binary writes take 0.6-0.7 of
// the ASCII CPU time; ASCII stays the default, as it is what people read and diff. Formats with one encoding (OFF and OBJ: text; STL, PLY: binary)
// accept Ascii, and Binary only when they are binary.

namespace bpm {

enum class MeshEncoding {
    Ascii,       // text: MSH file type 0, VTU format="ascii"
    Binary,      // MSH 4.1 file type 1 (little endian); VTU appended raw data (little endian)
    BinaryZlib,  // VTU only: appended data in zlib-compressed blocks of 32 KiB, as VTK's
                 // vtkZLibDataCompressor writes them (compressor="vtkZLibDataCompressor")
};

}  // namespace bpm
