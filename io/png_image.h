// 8-bit RGB images as PNG files (rendered frames, contact sheets), through
// libpng. Writes are atomic (io/atomic_file.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace skidsim::io {

struct RgbImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  // top row first, 3 bytes a pixel
};

// Throws std::runtime_error on I/O failure (the target is then untouched).
// `zlib_level`: 0 (none) to 9 (smallest), -1 zlib's default; recorded
// frames use 1, which writes a 1280 x 720 frame several times faster for
// files about a third larger.
void write_png_rgb8(const std::string& path, const RgbImage& image, int zlib_level = -1);

// Any PNG, converted to 8-bit RGB. Throws InputError naming the file.
RgbImage read_png_rgb8(const std::string& path);

// The libpng writer behind both image kinds: `height` rows of `row_bytes`
// from `data`; 16-bit samples are given in host order (written big-endian).
void write_png_rows(const std::string& path, int width, int height, int bit_depth, int colour_type,
                    const std::uint8_t* data, std::size_t row_bytes, int zlib_level = -1);

}  // namespace skidsim::io
