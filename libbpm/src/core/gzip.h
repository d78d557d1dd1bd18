#pragma once
// gzip-compressed input (FILE.off.gz, a .bpm.gz, `zcat`-able data on standard input):
// every reader takes its bytes through detail::read_whole_input (core/file_util.h) or a
// *_from_memory entry point, and both hand them to decompress_if_gzip, so that this is
// the one place where inputs are decompressed (internal, not public API).

#include <cstddef>
#include <string>

namespace bpm::detail {

// True if `bytes` start like a gzip member (RFC 1952): the magic 1f 8b, compression
// method 8 (deflate, the only one defined) and no reserved flag bit set. Four bytes
// rather than two, so that a binary STL whose free 80-byte header happens to begin with
// 1f 8b is not taken for gzip.
bool looks_like_gzip(const std::string& bytes);

// The path without a final ".gz" (any case): "femur.off.gz" -> "femur.off"; other paths
// unchanged. The format of a compressed file is told by the extension before ".gz".
std::string without_gz_suffix(const std::string& path);

// True if `path` ends in ".gz" (any case).
bool has_gz_suffix(const std::string& path);

// `bytes` decompressed if they are gzip data (looks_like_gzip; several members, as `cat
// a.gz b.gz` makes, are joined as gzip does), else `bytes` unchanged. `where` names the
// input in errors; `named_gz` says the name ends in .gz, so that data without the gzip
// magic is an error rather than read as it is. Throws bpm::InputError for a truncated
// or corrupt stream (saying which, and after how many decompressed bytes), a bad
// checksum, or more than `max_bytes` decompressed bytes.
std::string decompress_if_gzip(std::string bytes, const std::string& where, bool named_gz,
                               size_t max_bytes = size_t(16) << 30);

}  // namespace bpm::detail
