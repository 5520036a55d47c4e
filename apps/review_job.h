// `skidsim review RUN_DIR`: the review page (review.html) and a contact
// sheet (contact_sheet.png) of a run directory. With --camera or --fps it
// first draws the session again from its session.lcmlog's scene stream, as
// skidsim view does (apps/view_job.h; no physics), from that camera at that
// rate, into RUN_DIR/frames_<camera>_<fps>fps. The log is checked whole,
// and against the exercise, first (session/session_replay.h): a damaged
// one, or one of another exercise, is refused (exit 2). Frames missing from
// a set (a gap in frame_NNNNNN.png, or fewer than were recorded) are named
// on stderr and on the page.
#pragma once

#include <string>

namespace skidsim::apps {

struct ReviewJob {
  std::string run_dir;
  std::string camera;             // re-render from this camera (cab, chase, aerial, fixed)
  double fps = 0.0;               // re-render at this rate; 0: the exercise's
  int width = 0, height = 0;      // re-render size; 0: the exercise's (any of these four re-renders)
  std::string backend = "auto";   // auto, egl, osmesa
  std::string exercise_path;      // empty: the one report.json names
};

// 0 when the page was written, 2 for bad input (a run directory without
// report.json, a bad camera, a damaged log).
int review_session(const ReviewJob& job);

}  // namespace skidsim::apps
