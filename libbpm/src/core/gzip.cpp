#include "core/gzip.h"

#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <climits>

#include "bpm/errors.h"

namespace bpm::detail {

bool looks_like_gzip(const std::string& bytes) {
    return bytes.size() >= 4 && static_cast<unsigned char>(bytes[0]) == 0x1f &&
           static_cast<unsigned char>(bytes[1]) == 0x8b && static_cast<unsigned char>(bytes[2]) == 8 &&
           (static_cast<unsigned char>(bytes[3]) & 0xe0) == 0;
}

bool has_gz_suffix(const std::string& path) {
    if (path.size() < 4) return false;
    std::string tail = path.substr(path.size() - 3);
    std::transform(tail.begin(), tail.end(), tail.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return tail == ".gz" && path[path.size() - 4] != '/';
}

std::string without_gz_suffix(const std::string& path) {
    return has_gz_suffix(path) ? path.substr(0, path.size() - 3) : path;
}

namespace {

// One inflate pass over every member of the stream.
class Inflater {
public:
    Inflater() {
        // 16 + MAX_WBITS: gzip wrapper (header and CRC-32 / length trailer checked by zlib).
        ok_ = inflateInit2(&stream_, 16 + MAX_WBITS) == Z_OK;
    }
    ~Inflater() {
        if (ok_) inflateEnd(&stream_);
    }
    Inflater(const Inflater&) = delete;
    Inflater& operator=(const Inflater&) = delete;

    std::string run(const std::string& in, const std::string& where, size_t max_bytes) {
        if (!ok_) throw InputError(where, "cannot decompress gzip data: zlib could not start (out of memory?)");
        std::string out;
        // Compressed text typically expands 4-10 times; grow from there as needed.
        out.reserve(std::min(max_bytes, in.size() < (size_t(1) << 40) ? in.size() * 4 : in.size()));
        size_t consumed = 0;
        char buffer[1 << 16];
        int members = 0;
        while (consumed < in.size()) {
            // After a member: what follows must be another member (gzip -d ignores
            // trailing zeros, as tar pads; so do we), anything else is corrupt.
            if (members > 0) {
                const std::string next = in.substr(consumed, 4);
                if (std::all_of(in.begin() + static_cast<std::ptrdiff_t>(consumed), in.end(),
                                [](char c) { return c == 0; }))
                    break;
                if (!looks_like_gzip(next))
                    throw InputError(where, "corrupt gzip data: unexpected bytes after gzip member " +
                                                std::to_string(members) + " (at compressed byte " +
                                                std::to_string(consumed) + ")");
                inflateReset(&stream_);
            }
            // Fed in slices: avail_in is 32 bits.
            size_t fed = consumed;
            stream_.avail_in = 0;
            for (;;) {
                if (stream_.avail_in == 0) {
                    if (fed == in.size())
                        throw InputError(where, "truncated gzip data: the compressed stream ends after " +
                                                    std::to_string(out.size()) +
                                                    " decompressed bytes, before its end (an interrupted download "
                                                    "or copy?)");
                    const size_t slice = std::min(in.size() - fed, size_t(1) << 30);
                    stream_.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data() + fed));
                    stream_.avail_in = static_cast<uInt>(slice);
                    fed += slice;
                }
                stream_.next_out = reinterpret_cast<Bytef*>(buffer);
                stream_.avail_out = sizeof buffer;
                const int rc = inflate(&stream_, Z_NO_FLUSH);
                const size_t produced = sizeof buffer - stream_.avail_out;
                if (out.size() + produced > max_bytes)
                    throw InputError(where, "gzip data decompresses to more than the limit of " +
                                                std::to_string(max_bytes) + " bytes");
                out.append(buffer, produced);
                if (rc == Z_STREAM_END) break;
                if (rc == Z_DATA_ERROR || rc == Z_NEED_DICT)
                    throw InputError(where, "corrupt gzip data" +
                                                (stream_.msg ? " (" + std::string(stream_.msg) + ")" : std::string()) +
                                                " after " + std::to_string(out.size()) + " decompressed bytes");
                if (rc == Z_MEM_ERROR) throw InputError(where, "cannot decompress gzip data: out of memory");
                // Z_OK, or Z_BUF_ERROR (no progress without more input): go on.
            }
            consumed = fed - stream_.avail_in;
            ++members;
        }
        return out;
    }

private:
    z_stream stream_{};
    bool ok_ = false;
};

}  // namespace

std::string decompress_if_gzip(std::string bytes, const std::string& where, bool named_gz, size_t max_bytes) {
    if (!looks_like_gzip(bytes)) {
        if (!named_gz) return bytes;
        if (bytes.empty()) throw InputError(where, "is empty, but its name ends in .gz (gzip data expected)");
        throw InputError(where, "is not gzip data (it does not start with the gzip magic bytes 1f 8b 08), but its "
                                "name ends in .gz");
    }
    Inflater inflater;
    return inflater.run(bytes, where, max_bytes);
}

}  // namespace bpm::detail
