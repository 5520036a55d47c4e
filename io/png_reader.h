// Inside io/: an open PNG for reading, shared by the image and height-map
// readers. The file is checked first (a regular file of at most
// kMaxPngBytes, io/input_file.h), then for the PNG signature; libpng's read
// and info structs are made and pointed at it; all is released on scope
// exit. libpng reports errors by longjmp, so callers call
// setjmp(png_jmpbuf(reader.png)) themselves, after constructing this, and
// throw corrupt() there: it carries libpng's own reason ("Image width
// exceeds user limit in IHDR", "IDAT: CRC error").
#pragma once

#include <png.h>

#include <cstdio>
#include <string>

namespace skidsim::io {

struct PngReader {
  // Throws InputError naming `path` (missing, not a regular file, too
  // large, "cannot open `what`", "not a PNG file").
  PngReader(const std::string& path, const std::string& what);
  ~PngReader();
  PngReader(const PngReader&) = delete;
  PngReader& operator=(const PngReader&) = delete;

  // "PATH: corrupt or truncated PNG (libpng: REASON)", after a longjmp.
  std::string corrupt() const;

  std::string path;
  std::FILE* file = nullptr;
  png_structp png = nullptr;
  png_infop info = nullptr;
  char libpng_error[192] = "";  // libpng's last error message, kept by its error callback
};

}  // namespace skidsim::io
