// `skidsim view`: the visual channel as a process of its own. It draws a
// session from its scene stream (visual/scene_stream.h) without running the
// physics: frames from a camera at a rate, as `skidsim run --record` draws
// them from the same stream (the same pixels on one renderer, tested).
//  - `skidsim view RUN_DIR`: from the run's session.lcmlog, checked whole and
//    against the exercise first (session/session_replay.h), into
//    RUN_DIR/view_<camera>_<fps>fps/frames (and a video when ffmpeg is on
//    the PATH).
//  - `skidsim view --session NAME --exercise FILE`: a live session's stream
//    over LCM (SKIDSIM_SCENE@NAME), joined at any time: frames begin once
//    the picture is whole (visual::kSceneRefreshMessages) and go on until
//    the session's "end" event. Frame k is the one due at k / fps of the
//    session's time, the same frame a view of its log draws; a view that
//    falls behind skips drawing frames (never the messages), and says how
//    many.
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
  std::string out_dir;        // empty: RUN_DIR/view_<camera>_<fps>fps (live: ./view_<session>_<camera>_<fps>fps)
  // Live:
  std::string session;        // the session's name (empty: from a log)
  std::string lcm_url;        // empty: io::kDefaultLcmUrl
  double idle_s = 10.0;       // stop when no scene message came for this long
  bool every_frame = false;   // draw every frame due even when behind (the session never waits for a view)
};

// 0 when the frames were drawn (live: the session ended), 1 when a live
// session fell silent or its stream stopped fitting (a second of messages
// refused in a row), 2 for bad input (io::InputError); a live view keeps the
// frames it drew when it ends so, or for a signal.
int run_view(const ViewJob& job);

}  // namespace skidsim::apps
