// Every file skidsim reads is checked here before a byte of it is parsed:
// it must exist, be a regular file (a folder, a device such as /dev/zero or a
// FIFO would fail late or never end) and be no larger than its format's cap,
// so a parser never allocates for, or waits on, what is not a real input.
#pragma once

#include <cstdint>
#include <string>

namespace skidsim::io {

// Caps per format, in bytes: far above any real file of that kind.
constexpr std::uintmax_t kMaxXmlBytes = 64ull << 20;        // exercises, scripts, soil tables, loader files
constexpr std::uintmax_t kMaxJsonBytes = 64ull << 20;       // height-map metadata, reports, batch lists
constexpr std::uintmax_t kMaxPngBytes = 1ull << 30;         // height maps and frames
constexpr std::uintmax_t kMaxMeshBytes = 256ull << 20;      // visual meshes
constexpr std::uintmax_t kMaxLcmLogBytes = 64ull << 30;     // session logs

// Throws InputError naming `path` and `what` (e.g. "exercise") unless the
// path is an existing regular file of at most max_bytes; returns its size.
std::uintmax_t check_input_file(const std::string& path, std::uintmax_t max_bytes, const char* what);

// The whole file, after check_input_file.
std::string read_input_file(const std::string& path, std::uintmax_t max_bytes, const char* what);

// The 1-based line and byte offset of the first byte that is not valid
// UTF-8 (overlong forms, surrogates and code points past U+10FFFF included);
// offset -1 when the text is valid.
struct Utf8Error {
  long long offset = -1;
  int line = 0;
};
Utf8Error find_invalid_utf8(const std::string& text);

}  // namespace skidsim::io
