#include "io/jpeg_image.h"

#include <turbojpeg.h>

#include <memory>
#include <stdexcept>

namespace skidsim::io {

std::string encode_jpeg(const RgbImage& image, int quality) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 3)
    throw std::runtime_error("JPEG: an image of " + std::to_string(image.width) + " x " + std::to_string(image.height) +
                             " pixels with " + std::to_string(image.rgb.size()) + " bytes");
  const std::unique_ptr<void, int (*)(tjhandle)> handle(tjInitCompress(), tjDestroy);
  if (!handle) throw std::runtime_error("JPEG: TurboJPEG did not start");
  unsigned char* out = nullptr;
  unsigned long size = 0;
  if (tjCompress2(handle.get(), image.rgb.data(), image.width, 0, image.height, TJPF_RGB, &out, &size, TJSAMP_420, quality,
                  TJFLAG_FASTDCT) != 0) {
    const std::string why = tjGetErrorStr2(handle.get());
    tjFree(out);
    throw std::runtime_error("JPEG: " + why);
  }
  std::string bytes(reinterpret_cast<const char*>(out), size);
  tjFree(out);
  return bytes;
}

}  // namespace skidsim::io
