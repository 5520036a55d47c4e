// The review page of a run directory (docs/rendering.md, "Review"): the recorded
// frames under a scrubber, the timeline's plots with a marker kept at the
// scrubber's time, the events (the current one highlighted; a click seeks
// to it) and the score, term by term. One HTML file beside the frames; its
// data (from report.json) is embedded, the frames are read from their
// folders by relative path, so the run directory can be copied anywhere.
//
// For tests and links, the page takes its time from the address: opening
// review.html#t=12.5 moves the scrubber (through its own input handler) to
// 12.5 s. The page records uncaught script errors in #errors.
#pragma once

#include <nlohmann/json_fwd.hpp>

#include <string>
#include <utility>
#include <vector>

namespace skidsim::report {

// One recording of the session: frames <dir>/frame_000000.png... at `fps`.
struct FrameSet {
  std::string label;  // "chase, 10 fps"
  std::string dir;    // relative to the run directory
  double fps = 10.0;
  int frames = 0;     // frames 0 .. frames - 1 belong to the set
  std::vector<std::pair<int, int>> missing;  // runs of frames it lacks (first, last): shown as missing
};

// Never throws on missing or mistyped keys of the report.
std::string render_review_html(const nlohmann::json& report, const std::vector<FrameSet>& frame_sets);

}  // namespace skidsim::report
