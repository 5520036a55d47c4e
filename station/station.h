// The live station (`skidsim station`; docs/rendering.md, "The live
// station"): a live session served to browsers. It joins the session's
// scene stream over LCM as a live view does (visual/scene_view.h), draws the
// trainee's camera and one from above as JPEG at its own rate, and serves a
// page (assets/station/index.html) that shows them with the session's
// state, tasks, events and score. The page holding the driver token drives:
// its keys and gamepad become control_t messages on the session's control
// channel, 50 a second while it keeps sending, neutral when it stops or
// goes. Any number of pages watch. It listens on this host alone unless it
// is given a token, which every request then carries.
#pragma once

#include <string>

namespace skidsim::station {

struct StationOptions {
  std::string session;        // the live session's name (skidsim run --session)
  std::string exercise_path;  // its exercise
  std::string lcm_url;        // empty: io::kDefaultLcmUrl
  std::string bind = "127.0.0.1";
  int port = 8080;            // 0: any free port (printed)
  std::string token;          // needed for any address but this host's; then every request carries it
  std::string driver_token;   // empty: one drawn at random (printed)
  std::string camera;         // the trainee's camera (default: the exercise's)
  double fps = 10.0;          // frames drawn a second of the session's time, 0.1 to 25
  int width = 640, height = 360;
  std::string backend = "auto";
  double linger_s = 5.0;      // serving on after the session's end, for the pages to show it
};

// Serves until the session ends (and linger_s more) or a signal (then
// jobs::Interrupted). 0 when the session ended; io::InputError for bad
// options (a token missing for another address, a port in use).
int run_station(const StationOptions& options);

}  // namespace skidsim::station
