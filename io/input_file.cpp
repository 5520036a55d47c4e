#include "io/input_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <sys/stat.h>

#include "io/atomic_file.h"

namespace skidsim::io {

std::uintmax_t check_input_file(const std::string& path, std::uintmax_t max_bytes, const char* what) {
  const std::string name = std::string(what) + " " + (path.empty() ? std::string("\"\"") : path);
  if (path.empty()) throw InputError(std::string(what) + ": no file named (empty path)");
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    const int err = errno;
    throw InputError(name + ": " + (err == ENOENT ? "no such file" : std::strerror(err)));
  }
  if (S_ISDIR(st.st_mode)) throw InputError(name + ": is a directory, not a file");
  if (!S_ISREG(st.st_mode))
    throw InputError(name + ": not a regular file (a device, FIFO or socket cannot be read as one)");
  const auto size = static_cast<std::uintmax_t>(st.st_size);
  if (size > max_bytes)
    throw InputError(name + ": " + std::to_string(size) + " bytes, more than the " + std::to_string(max_bytes) +
                     " a file of this kind may have");
  return size;
}

std::string read_input_file(const std::string& path, std::uintmax_t max_bytes, const char* what) {
  const std::uintmax_t size = check_input_file(path, max_bytes, what);
  struct Closer {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };
  std::unique_ptr<std::FILE, Closer> f(std::fopen(path.c_str(), "rb"));
  if (!f) throw InputError(std::string(what) + " " + path + ": cannot open: " + std::strerror(errno));
  std::string data(static_cast<std::size_t>(size), '\0');
  const std::size_t got = size ? std::fread(data.data(), 1, data.size(), f.get()) : 0;
  if (got != data.size())
    throw InputError(std::string(what) + " " + path + ": read " + std::to_string(got) + " of " +
                     std::to_string(size) + " bytes (the file changed while it was read?)");
  return data;
}

Utf8Error find_invalid_utf8(const std::string& text) {
  const auto* s = reinterpret_cast<const unsigned char*>(text.data());
  const std::size_t n = text.size();
  int line = 1;
  for (std::size_t i = 0; i < n;) {
    const unsigned char c = s[i];
    if (c == '\n') ++line;
    if (c < 0x80) {
      ++i;
      continue;
    }
    int len = 0;
    unsigned cp = 0;
    if (c >= 0xC2 && c <= 0xDF) {
      len = 2;
      cp = c & 0x1Fu;
    } else if (c >= 0xE0 && c <= 0xEF) {
      len = 3;
      cp = c & 0x0Fu;
    } else if (c >= 0xF0 && c <= 0xF4) {
      len = 4;
      cp = c & 0x07u;
    } else {
      return {static_cast<long long>(i), line};
    }
    if (i + static_cast<std::size_t>(len) > n) return {static_cast<long long>(i), line};
    for (int k = 1; k < len; ++k) {
      if ((s[i + k] & 0xC0u) != 0x80u) return {static_cast<long long>(i), line};
      cp = (cp << 6) | (s[i + k] & 0x3Fu);
    }
    const bool overlong = (len == 3 && cp < 0x800) || (len == 4 && cp < 0x10000);
    if (overlong || (cp >= 0xD800 && cp <= 0xDFFF) || cp > 0x10FFFF) return {static_cast<long long>(i), line};
    i += static_cast<std::size_t>(len);
  }
  return {};
}

}  // namespace skidsim::io
