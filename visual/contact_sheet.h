// A contact sheet: a recording's frames at a glance, as one PNG beside the
// review page. Evenly spaced frames from the first to the last, shrunk by
// box filtering, in rows; under each, a bar showing where in the session
// it was taken.
#pragma once

#include <string>
#include <vector>

#include "io/png_image.h"

namespace skidsim::visual {

struct ContactSheetLayout {
  int count = 12;          // frames shown (fewer if fewer were recorded)
  int columns = 4;
  int thumb_width = 320;   // pixels; heights keep the frames' aspect
  int gap = 6;             // pixels between thumbnails (dark grey)
  int bar_height = 5;      // the time bar under each thumbnail
};

// `frame_paths`: the recording's frames in order (all the same size).
// Throws io::InputError naming a frame that cannot be read or differs in
// size; std::invalid_argument if there are none.
io::RgbImage contact_sheet(const std::vector<std::string>& frame_paths, const ContactSheetLayout& layout = {});

}  // namespace skidsim::visual
