// `skidsim view RUN_DIR`: the visual channel as a process of its own. It
// draws a session from its scene stream (visual/scene_stream.h), here read
// from the run's session.lcmlog, without running the physics: frames from a
// camera at a rate, as `skidsim run --record` draws them from the same
// stream (the same pixels on one renderer, tested), into
// RUN_DIR/view_<camera>_<fps>fps/frames (and a video when ffmpeg is on the
// PATH). The log is checked whole, and against the exercise, first
// (session/session_replay.h).
#pragma once

#include <string>

namespace skidsim::apps {

struct ViewJob {
  std::string source;         // a run directory, or a session.lcmlog (then --exercise)
  std::string exercise_path;  // empty: the one the run's report.json names
  std::string camera;         // empty: the exercise's
  double fps = 0.0;           // 0: the exercise's
  int width = 0, height = 0;  // 0: the exercise's
  std::string backend = "auto";
  std::string out_dir;        // empty: RUN_DIR/view_<camera>_<fps>fps
};

// 0 when the frames were drawn, 2 for bad input (io::InputError).
int run_view(const ViewJob& job);

}  // namespace skidsim::apps
