// Plays an operator script (io/operator_script.h) against the machine's
// state, one control tick at a time: the built-in operator of a session, and
// what `skidsim operator` publishes over LCM. Closed loops on the heading,
// the arm's angle and the bucket's pitch (this machine has no
// self-levelling: raising the arm rolls the bucket back).
#pragma once

#include <string>
#include <vector>

#include "io/operator_script.h"
#include "skidsim_lcm/state_t.hpp"
#include "vehicle/powertrain.h"

namespace skidsim::session {

class OperatorPlayer {
 public:
  explicit OperatorPlayer(io::OperatorScript script);

  // The levers for this tick; moves to the next phase when this one reached
  // its goal or its time limit.
  vehicle::LoaderControls step(const skidsim_lcm::state_t& state);
  bool done() const { return phase_ >= script_.phases.size(); }
  std::string phase_name() const;
  // Phases that ran out of time ("line 12 dump"), in order.
  const std::vector<std::string>& timed_out() const { return timed_out_; }

 private:
  void next(double time_s);

  io::OperatorScript script_;
  std::size_t phase_ = 0;
  bool started_ = false;
  double start_s_ = 0.0;
  Eigen::Vector2d start_xy_ = Eigen::Vector2d::Zero();
  io::ScriptLevers from_;  // the levers when a ramp began
  io::ScriptLevers last_;  // the last levers given
  double start_payload_kg_ = 0.0, check_payload_kg_ = 0.0, check_s_ = 0.0, slow_since_s_ = -1.0, at_target_since_s_ = -1.0;
  std::vector<std::string> timed_out_;
};

}  // namespace skidsim::session
