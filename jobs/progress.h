// A progress line for long jobs: a bar with simulated time, real-time factor
// and ETA when stderr is a terminal; silent otherwise (machine-readable runs).
#pragma once

#include <chrono>
#include <string>

namespace skidsim::jobs {

class Progress {
 public:
  Progress(std::string label, double total_sim_s);
  // Cheap to call every step: redraws at most 10 times per second.
  void update(double sim_s, const std::string& extra = "");
  void finish();
  double wall_seconds() const;

 private:
  std::string label_;
  double total_sim_s_;
  bool enabled_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
};

}  // namespace skidsim::jobs
