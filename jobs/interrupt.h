// Ctrl-C, SIGTERM, SIGHUP (the terminal closed) and SIGQUIT, caught while a
// job runs so that it ends cleanly instead of dying mid-write: a session ends
// at its next control tick with its report written (end_reason
// "interrupted"); a pour, push or dig stops, its staging folder is removed
// and the previous result stays. The handlers stay installed until the run
// directory is in place, so a signal while the result is written loses
// nothing either.
#pragma once

#include <stdexcept>
#include <string>

namespace skidsim::jobs {

class InterruptScope {
 public:
  InterruptScope();   // installs the handlers, clears the flag
  ~InterruptScope();  // restores what was there before
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;
};

// The signal that arrived since the scope began (0: none).
int interrupting_signal();

// Thrown by a job that stops for a signal; the command exits 128 + signal.
struct Interrupted : std::runtime_error {
  Interrupted(const std::string& what, int signal) : std::runtime_error(what), signal_number(signal) {}
  int signal_number;
};

// Throws Interrupted naming `job` and what is kept if a signal arrived.
void stop_if_interrupted(const std::string& job);

}  // namespace skidsim::jobs
