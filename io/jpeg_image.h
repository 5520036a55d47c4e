// 8-bit RGB images as JPEG in memory (the station's live frames), through
// libjpeg-turbo's TurboJPEG API.
#pragma once

#include <string>

#include "io/png_image.h"

namespace skidsim::io {

// `quality` 1 to 100; 4:2:0 chroma. Throws std::runtime_error naming what
// TurboJPEG said.
std::string encode_jpeg(const RgbImage& image, int quality = 80);

}  // namespace skidsim::io
