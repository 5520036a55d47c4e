// Inside io/: an open PNG for reading, shared by the image and height-map
// readers. The file is checked for the PNG signature, libpng's read and
// info structs are made and pointed at it; all is released on scope exit.
// libpng reports errors by longjmp, so callers call
// setjmp(png_jmpbuf(reader.png)) themselves, after constructing this.
#pragma once

#include <png.h>

#include <cstdio>
#include <string>

namespace skidsim::io {

struct PngReader {
  // Throws InputError naming `path` ("cannot open `what`", "not a PNG file").
  PngReader(const std::string& path, const std::string& what);
  ~PngReader();
  PngReader(const PngReader&) = delete;
  PngReader& operator=(const PngReader&) = delete;

  std::FILE* file = nullptr;
  png_structp png = nullptr;
  png_infop info = nullptr;
};

}  // namespace skidsim::io
