// A training session: `skidsim run EXERCISE`. The exercise's world, its
// operator (a built-in script, or commands over LCM with the watchdog),
// tasks, events and score; the machine's state and the events published on
// LCM; a run directory with the LCM log of every channel, report.json and
// the final terrain. Modes: fast (as fast as it goes; a script), real time
// (paced to the wall clock; the newest command wins) and lockstep (each
// control tick waits for the command stamped for it).
#pragma once

#include <string>

namespace skidsim::apps {

struct RunJob {
  std::string exercise_path;
  std::string out_dir = "runs/session";
  std::string script_path;  // empty: the exercise's operator
  std::string lcm_url;      // empty: the exercise's, else the default provider
  std::string mode;         // fast, realtime, lockstep; empty: fast with a script, realtime over LCM
  std::string replay_path;  // a session's session.lcmlog: its applied controls, tick by tick (mode fast)
  double max_s = 0.0;       // 0: not given (the exercise's time limit); --max-s takes 0.001 to 86400 s
  // Frames (the exercise's <record>: rate, camera, size) rendered on a second
  // thread into RUN/frames; a video too when ffmpeg is on the PATH.
  bool record = false;
  std::string render_backend = "auto";  // auto, egl, osmesa
  int frame_width = 0, frame_height = 0;  // 0: the exercise's
  double frame_fps = 0.0;                 // 0: the exercise's
  std::string camera;                   // empty: the exercise's
  bool terrain_tiles = false;  // publish and log the soil's changed tiles every 0.5 s (SKIDSIM_TERRAIN)
  // A live session's name, in its channels' names (io::session_channels);
  // empty: io::default_session_name. Only with LCM.
  std::string session;
};

// Returns the exit code: 0 when the session ran (report.json says whether
// it passed), 2 for bad input (io::InputError).
int run_session(const RunJob& job);

}  // namespace skidsim::apps
