// The operator's controls as they come in (README, "File formats"; the
// control tick that feeds the 2 ms step, docs/architecture.md): each message
// is validated, out-of-range values clamped, NaN and stale messages
// rejected, all counted; a watchdog returns the levers to neutral and sets
// the parking brake when valid commands stop arriving (the operator gone),
// and records it.
#pragma once

#include <cstdint>

#include "skidsim_lcm/control_t.hpp"
#include "vehicle/powertrain.h"

namespace skidsim::io {

struct ControlStats {
  std::int64_t accepted = 0;
  std::int64_t clamped = 0;         // accepted with a value brought into its range
  std::int64_t rejected_nan = 0;    // a value not finite
  std::int64_t rejected_stale = 0;  // a sequence number not above the last accepted one
  std::int64_t rejected_tick = 0;   // lockstep: stamped for another tick than the one awaited
  std::int64_t repeated = 0;        // lockstep: the accepted answer sent again (same sender, seq and tick), set aside
  std::int64_t malformed = 0;       // bytes that did not decode (counted by the bridge)
  std::int64_t watchdog_trips = 0;  // times the watchdog returned the levers to neutral
};

class ControlInput {
 public:
  // `watchdog_s`: how long without a valid command (simulated time) before
  // the levers go to neutral. Throws std::invalid_argument unless > 0.
  explicit ControlInput(double watchdog_s);

  // A received command at simulated time `sim_time_s`: kept as the newest
  // if valid (clamped into range). Returns false when rejected. A command
  // from a new sender (another sender_id: an operator restarted) starts its
  // own sequence.
  bool offer(const skidsim_lcm::control_t& command, double sim_time_s);
  void count_malformed() { ++stats_.malformed; }
  // Lockstep: from now on only a command stamped for `sim_step` is accepted
  // (one stamped for a past or a future tick is rejected and counted), so a
  // stray or far-future stamp can never stand in for the operator's answer.
  // -1 (the default, real time): any tick.
  void await_step(std::int64_t sim_step) { awaited_step_ = sim_step; }

  // The controls to apply at `sim_time_s`: the newest valid command, or
  // neutral (levers 0, throttle kept, parking brake on) once none came for
  // the watchdog's time (and before the first).
  vehicle::LoaderControls controls(double sim_time_s);
  bool neutral() const { return neutral_; }
  // The newest accepted command's lockstep tick (-1 for real time or none).
  std::int64_t last_sim_step() const { return last_sim_step_; }
  const ControlStats& stats() const { return stats_; }

 private:
  double watchdog_s_;
  vehicle::LoaderControls newest_;
  double newest_time_s_ = 0.0;
  bool have_command_ = false;
  bool neutral_ = true;
  std::int64_t last_seq_ = 0;
  std::int64_t last_sender_ = 0;
  std::int64_t last_sim_step_ = -1;
  std::int64_t awaited_step_ = -1;
  ControlStats stats_;
};

}  // namespace skidsim::io
