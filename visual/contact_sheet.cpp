#include "visual/contact_sheet.h"

#include <algorithm>
#include <stdexcept>

#include "io/atomic_file.h"

namespace skidsim::visual {
namespace {

// Box filter: each thumbnail pixel averages the frame pixels it covers.
void shrink_into(const io::RgbImage& frame, io::RgbImage& sheet, int x0, int y0, int w, int h) {
  for (int y = 0; y < h; ++y) {
    const int fy0 = y * frame.height / h, fy1 = std::max(fy0 + 1, (y + 1) * frame.height / h);
    for (int x = 0; x < w; ++x) {
      const int fx0 = x * frame.width / w, fx1 = std::max(fx0 + 1, (x + 1) * frame.width / w);
      unsigned sum[3] = {0, 0, 0};
      for (int fy = fy0; fy < fy1; ++fy)
        for (int fx = fx0; fx < fx1; ++fx)
          for (int c = 0; c < 3; ++c) sum[c] += frame.rgb[(static_cast<std::size_t>(fy) * frame.width + fx) * 3 + c];
      const auto n = static_cast<unsigned>((fy1 - fy0) * (fx1 - fx0));
      for (int c = 0; c < 3; ++c)
        sheet.rgb[(static_cast<std::size_t>(y0 + y) * sheet.width + x0 + x) * 3 + c] = static_cast<std::uint8_t>(sum[c] / n);
    }
  }
}

void fill(io::RgbImage& img, int x0, int y0, int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  for (int y = y0; y < y0 + h; ++y)
    for (int x = x0; x < x0 + w; ++x) {
      std::uint8_t* p = &img.rgb[(static_cast<std::size_t>(y) * img.width + x) * 3];
      p[0] = r;
      p[1] = g;
      p[2] = b;
    }
}

}  // namespace

io::RgbImage contact_sheet(const std::vector<std::string>& frame_paths, const ContactSheetLayout& layout) {
  if (frame_paths.empty()) throw std::invalid_argument("contact_sheet: no frames");
  const int n = std::min<int>(layout.count, static_cast<int>(frame_paths.size()));
  const int columns = std::min(layout.columns, n), rows = (n + columns - 1) / columns;
  io::RgbImage sheet;
  int thumb_h = 0, frame_w = 0, frame_h = 0;
  for (int k = 0; k < n; ++k) {
    // Evenly from the first frame to the last.
    const std::size_t index = n == 1 ? 0 : static_cast<std::size_t>(k) * (frame_paths.size() - 1) / static_cast<std::size_t>(n - 1);
    const io::RgbImage frame = io::read_png_rgb8(frame_paths[index]);
    if (k == 0) {
      frame_w = frame.width;
      frame_h = frame.height;
      thumb_h = std::max(1, layout.thumb_width * frame.height / frame.width);
      sheet.width = layout.gap + columns * (layout.thumb_width + layout.gap);
      sheet.height = layout.gap + rows * (thumb_h + layout.bar_height + layout.gap);
      sheet.rgb.assign(static_cast<std::size_t>(sheet.width) * sheet.height * 3, 40);
    } else if (frame.width != frame_w || frame.height != frame_h) {
      throw io::InputError(frame_paths[index] + ": a frame of another size than the first");
    }
    const int x0 = layout.gap + (k % columns) * (layout.thumb_width + layout.gap);
    const int y0 = layout.gap + (k / columns) * (thumb_h + layout.bar_height + layout.gap);
    shrink_into(frame, sheet, x0, y0, layout.thumb_width, thumb_h);
    // The time bar: how far into the recording this frame is.
    const int done = frame_paths.size() == 1 ? layout.thumb_width
                                             : static_cast<int>(static_cast<double>(index) / static_cast<double>(frame_paths.size() - 1) * layout.thumb_width);
    fill(sheet, x0, y0 + thumb_h, layout.thumb_width, layout.bar_height, 90, 90, 90);
    fill(sheet, x0, y0 + thumb_h, done, layout.bar_height, 230, 160, 20);
  }
  return sheet;
}

}  // namespace skidsim::visual
