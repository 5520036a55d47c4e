#include "io/png_image.h"

#include <algorithm>

#include <png.h>

#include <cstdio>
#include <memory>
#include <stdexcept>

#include "io/atomic_file.h"
#include "io/input_file.h"
#include "io/png_reader.h"

namespace skidsim::io {
namespace {

struct FileCloser {
  void operator()(std::FILE* f) const {
    if (f) std::fclose(f);
  }
};

// libpng's error callback must not return (libpng manual, "Error
// handling"): keep the message for the InputError, then jump back to the
// reader's setjmp. Warnings (an odd ancillary chunk) are not errors here.
void keep_libpng_error(png_structp png, png_const_charp message) {
  auto* out = static_cast<char*>(png_get_error_ptr(png));
  if (out) std::snprintf(out, sizeof(PngReader::libpng_error), "%s", message ? message : "unknown error");
  png_longjmp(png, 1);
}
void ignore_libpng_warning(png_structp, png_const_charp) {}

// A frame or a contact sheet, not a poster: the most pixels on a side an
// image read back may have (the renderer's own limit, render/offscreen_context.cpp).
constexpr png_uint_32 kMaxImageSide = 16384;

}  // namespace

void write_png_rows(const std::string& path, int width, int height, int bit_depth, int colour_type,
                    const std::uint8_t* data, std::size_t row_bytes, int zlib_level) {
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "wb"));
  if (!file) throw std::runtime_error("cannot open " + path + " for writing");
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_write_struct(&png, &info);
    throw std::runtime_error("libpng: cannot create writer for " + path);
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw std::runtime_error("libpng: error while writing " + path);
  }
  png_init_io(png, file.get());
  if (zlib_level >= 0) png_set_compression_level(png, std::min(zlib_level, 9));
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), bit_depth, colour_type,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  if (bit_depth == 16) png_set_swap(png);  // PNG stores 16-bit samples big-endian
  for (int r = 0; r < height; ++r) png_write_row(png, data + static_cast<std::size_t>(r) * row_bytes);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  if (std::fflush(file.get()) != 0) throw std::runtime_error("cannot write " + path);
}

void write_png_rgb8(const std::string& path, const RgbImage& image, int zlib_level) {
  if (image.width < 1 || image.height < 1 ||
      image.rgb.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 3)
    throw std::invalid_argument("write_png_rgb8: the pixels do not match " + std::to_string(image.width) + " x " +
                                std::to_string(image.height));
  write_atomically(path, [&](const std::string& tmp) {
    write_png_rows(tmp, image.width, image.height, 8, PNG_COLOR_TYPE_RGB, image.rgb.data(),
                   static_cast<std::size_t>(image.width) * 3, zlib_level);
  });
}

PngReader::PngReader(const std::string& path_in, const std::string& what) : path(path_in) {
  check_input_file(path, kMaxPngBytes, what.c_str());
  file = std::fopen(path.c_str(), "rb");
  if (!file) throw InputError(path + ": cannot open " + what);
  png_byte signature[8];
  if (std::fread(signature, 1, 8, file) != 8 || png_sig_cmp(signature, 0, 8) != 0) {
    std::fclose(file);
    throw InputError(path + ": not a PNG file");
  }
  png = png_create_read_struct(PNG_LIBPNG_VER_STRING, libpng_error, keep_libpng_error, ignore_libpng_warning);
  info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_read_struct(&png, &info, nullptr);
    std::fclose(file);
    throw std::runtime_error("libpng: cannot create reader for " + path);
  }
  png_init_io(png, file);
  png_set_sig_bytes(png, 8);
}

PngReader::~PngReader() {
  png_destroy_read_struct(&png, &info, nullptr);
  std::fclose(file);
}

std::string PngReader::corrupt() const {
  return path + ": corrupt or truncated PNG" + (libpng_error[0] ? std::string(" (libpng: ") + libpng_error + ")" : "");
}

RgbImage read_png_rgb8(const std::string& path) {
  PngReader reader(path, "image");
  png_structp png = reader.png;
  png_infop info = reader.info;
  // libpng reports errors by longjmp: the buffers live behind a pointer made
  // before setjmp, so nothing set up after it is skipped or left undefined.
  struct Buffers {
    RgbImage image;
    std::vector<png_bytep> rows;
  };
  const auto buffers = std::make_unique<Buffers>();
  if (setjmp(png_jmpbuf(png))) throw InputError(reader.corrupt());
  png_read_info(png, info);
  // The header is not trusted: its size is checked before a pixel buffer
  // is made for it.
  const png_uint_32 width = png_get_image_width(png, info), height = png_get_image_height(png, info);
  if (width < 1 || height < 1 || width > kMaxImageSide || height > kMaxImageSide)
    throw InputError(path + ": the header says " + std::to_string(width) + " x " + std::to_string(height) +
                     " pixels (an image read back has 1 to " + std::to_string(kMaxImageSide) + " on a side)");
  // Whatever it holds, as 8-bit RGB.
  png_set_expand(png);
  png_set_strip_16(png);
  png_set_strip_alpha(png);
  png_set_gray_to_rgb(png);
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  RgbImage& image = buffers->image;
  image.width = static_cast<int>(width);
  image.height = static_cast<int>(height);
  if (png_get_rowbytes(png, info) != static_cast<std::size_t>(image.width) * 3)
    throw InputError(path + ": cannot read it as 8-bit RGB");
  image.rgb.resize(static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 3);
  buffers->rows.resize(static_cast<std::size_t>(image.height));
  for (int r = 0; r < image.height; ++r)
    buffers->rows[static_cast<std::size_t>(r)] = &image.rgb[static_cast<std::size_t>(r) * static_cast<std::size_t>(image.width) * 3];
  png_read_image(png, buffers->rows.data());
  png_read_end(png, nullptr);
  return std::move(image);
}

}  // namespace skidsim::io
