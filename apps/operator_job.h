// `skidsim operator SCRIPT`: a scripted operator as a process of its own,
// as a person's controls or a policy would be: it listens to the
// simulator's state over LCM and answers each state with the command for
// that control tick (what lockstep waits for; in real time the newest
// command wins).
#pragma once

#include <string>

namespace skidsim::apps {

struct OperatorJob {
  std::string script_path;
  std::string lcm_url;  // empty: the default provider
  std::string session;  // the live session to drive (skidsim run --session; io::session_channels)
  std::string control_channel = "SKIDSIM_CONTROL";  // its base name (the exercise's <operator channel>)
  double idle_timeout_s = 10.0;  // no state for this long: the session is over
};

// 0 when the script finished, 1 when the session stopped sending state
// first, 2 for bad input.
int run_operator(const OperatorJob& job);

}  // namespace skidsim::apps
