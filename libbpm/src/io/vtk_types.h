#pragma once
// Internal to the VTK readers (read_vtk.cpp: legacy .vtk; read_vtk_xml.cpp: .vtp / .vtu):
// the value types of VTK data arrays. Each reader maps its own spelling of the type names
// (legacy "unsigned_char", XML "UInt8", ...) onto these.

#include <cstddef>

namespace bpm::detail {

// Bit and String occur only in legacy files.
enum class VtkType { Bit, Int8, UInt8, Int16, UInt16, Int32, UInt32, Int64, UInt64, Float32, Float64, String };

// Bytes of one value in a binary file (Bit: one byte holds eight values; String: per
// character), used for bounds checks and for reading.
inline size_t vtk_type_size(VtkType t) {
    switch (t) {
        case VtkType::Bit:
        case VtkType::String:
        case VtkType::Int8:
        case VtkType::UInt8: return 1;
        case VtkType::Int16:
        case VtkType::UInt16: return 2;
        case VtkType::Int32:
        case VtkType::UInt32:
        case VtkType::Float32: return 4;
        case VtkType::Int64:
        case VtkType::UInt64:
        case VtkType::Float64: return 8;
    }
    return 8;
}

inline bool vtk_type_is_integer(VtkType t) {
    return t != VtkType::Float32 && t != VtkType::Float64 && t != VtkType::String;
}

}  // namespace bpm::detail
