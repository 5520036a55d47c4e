// Runs the real skidsim binary (SKIDSIM_BINARY, set by CMake) for the
// end-to-end tests.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace skidsim::testing {

struct CommandResult {
  int exit_code;
  std::string output;  // stdout and stderr
};

// Any shell command, its stdout and stderr together.
inline CommandResult run_command(const std::string& cmd_line) {
  const std::string cmd = cmd_line + " 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  std::string out;
  std::array<char, 4096> buf{};
  while (pipe && std::fgets(buf.data(), buf.size(), pipe)) out += buf.data();
  const int status = pipe ? ::pclose(pipe) : -1;
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

inline CommandResult run_skidsim(const std::string& args) { return run_command(std::string(SKIDSIM_BINARY) + " " + args); }

}  // namespace skidsim::testing
