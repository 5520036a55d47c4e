// `skidsim render EXERCISE`: one frame of an exercise, off-screen: its world
// at the start, or after its operator script has played for --at-s seconds
// (in-process, as `skidsim run --script` would), from one of its cameras.
#pragma once

#include <string>

namespace skidsim::apps {

struct RenderJob {
  std::string exercise_path;
  std::string out_path = "frame.png";
  std::string camera;          // empty: the exercise's <record camera>
  std::string backend = "auto";  // auto, egl, osmesa
  int width = 0, height = 0;   // 0: the exercise's <record>
  std::string script_path;     // play this first (with at_s)
  double at_s = 0.0;
};

// 0 when the frame was written, 2 for bad input.
int render_frame(const RenderJob& job);

}  // namespace skidsim::apps
