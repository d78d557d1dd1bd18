#pragma once
// Byte and number writers shared by the unit tests that build input files in code.

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <sstream>
#include <string>

namespace bpm::test_bytes {

// Appends the bytes of `value` in the given byte order, whatever the host's.
template <class T>
void put(std::string& out, T value, bool big_endian) {
    unsigned char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));
    const uint16_t probe = 1;
    unsigned char first;
    std::memcpy(&first, &probe, 1);
    const bool host_big = first == 0;
    if (host_big != big_endian) std::reverse(raw, raw + sizeof(T));
    out.append(reinterpret_cast<const char*>(raw), sizeof(T));
}

// x with 17 significant digits: read back, it is the same double.
inline std::string text(double x) {
    std::ostringstream s;
    s.precision(17);
    s << x;
    return s.str();
}

}  // namespace bpm::test_bytes
