#pragma once
// Internal file helpers shared by the readers and writers (not public API).

#include <cstddef>
#include <functional>
#include <optional>
#include <string>

namespace bpm::detail {

// Writes `bytes` to `path` so that `path` holds either its previous content or all of
// `bytes`, never a part: the bytes go to a temporary file in the same directory, are
// flushed to disk, and the temporary is renamed over `path` (and the directory flushed).
// "-" writes to standard output. Throws bpm::OutputError (missing directory, permission,
// disk full), after removing the temporary file.
// Temporary files: on Linux the bytes are written to an unnamed file (O_TMPFILE) that gets
// a name only once complete, so a process killed (SIGKILL, power loss) while writing
// leaves nothing. Otherwise, and in the instant between naming and renaming, the
// temporary name is ".NAME.tmpXXXXXXXX" next to NAME (hidden, 8 hex digits, never NAME's
// extension): that is the only thing a killed bpm tool can leave behind, it is never a
// complete output, and it may be deleted.
// A `path` that is a symbolic link is followed: the file it names is replaced and the
// link stays (as writing through it would do). The new file keeps the permission bits
// of the file it replaces (a private chmod 600 output stays private).
void write_file_atomically(const std::string& path, const std::string& bytes);

// The same for a writer that writes the file itself, so that no image of the whole file
// has to be built in memory (the .bpm writer: HDF5 through io/hdf5_fd_driver.h):
// `fill(fd)` writes all of the file through `fd` (open for reading and writing, at offset
// 0 of an empty file; it may seek and use pwrite/pread) and must not close it, or throws.
// The complete file is then flushed to disk and renamed over `path` as above; on any
// error nothing is left and `path` keeps its previous content. `fill` may be called a
// second time, on a fresh file, if the unnamed file cannot be given a name (no /proc).
// `path` may not be "-". Throws bpm::OutputError as above, or what `fill` throws.
void write_file_atomically(const std::string& path, const std::function<void(int fd)>& fill);

// Reads a whole file (or standard input for "-") into memory, decompressed if it is gzip
// data (core/gzip.h: by its magic bytes; a name ending in .gz must hold gzip data).
// Throws bpm::InputError for a missing file, a directory, an unreadable file, corrupt or
// truncated gzip data, or more than `max_bytes` bytes (read or decompressed).
std::string read_whole_input(const std::string& path, size_t max_bytes = size_t(16) << 30);

// A name for error messages: the path, or "<stdin>" for "-".
std::string display_name(const std::string& path);

// Runs `parse` in a child process (fork) so that a parser we cannot fix (HDF5) crashing
// on a corrupt input cannot take the caller down with it. The child's standard output
// and error go to /dev/null; it dies with its parent (PR_SET_PDEATHSIG) and never writes
// files. Outcomes:
//   * `parse` returned in the child: returns what it returned, sent back through a pipe
//     (e.g. the results of the parser's calls, for the caller to replay).
//   * `parse` threw InputError in the child: throws InputError(where, its message).
//   * the child died from a signal, or exited in any other way than the three above (an
//     ASan/UBSan report in a sanitized build): throws InputError(where, "the <library>
//     library crashed reading it (...): the file is corrupt").
//   * `parse` threw anything else, or fork() failed: returns nothing (the caller then
//     parses in-process, which reports it as usual, or runs unprotected).
// Test hook: with the environment variable BPM_TEST_ISOLATED_CRASH=N (a signal number)
// the child raises signal N instead of parsing, so that tests can exercise the crash path
// without a file that crashes the library for real.
std::optional<std::string> run_isolated(const std::string& where, const std::string& library,
                                        const std::function<std::string()>& parse);

}  // namespace bpm::detail
