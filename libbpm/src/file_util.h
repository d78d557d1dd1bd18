#pragma once
// Internal file helpers shared by the readers and writers (not public API).

#include <cstddef>
#include <string>

namespace bpm::detail {

// Writes `bytes` to `path` so that `path` holds either its previous content or all of
// `bytes`, never a part: the bytes go to a temporary file in the same directory, are
// flushed to disk, and the temporary is renamed over `path`. "-" writes to standard
// output. Throws bpm::OutputError (missing directory, permission, disk full).
void write_file_atomically(const std::string& path, const std::string& bytes);

// Reads a whole file (or standard input for "-") into memory. Throws bpm::InputError
// for a missing file, a directory, an unreadable file, or more than `max_bytes` bytes.
std::string read_whole_input(const std::string& path, size_t max_bytes = size_t(16) << 30);

// A name for error messages: the path, or "<stdin>" for "-".
std::string display_name(const std::string& path);

}  // namespace bpm::detail
