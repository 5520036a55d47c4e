#include "io/control_input.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace skidsim::io {

ControlInput::ControlInput(double watchdog_s) : watchdog_s_(watchdog_s) {
  if (!(watchdog_s > 0.0 && std::isfinite(watchdog_s)))
    throw std::invalid_argument("control watchdog: the time must be > 0 s");
}

bool ControlInput::offer(const skidsim_lcm::control_t& m, double sim_time_s) {
  const double values[] = {m.drive_left, m.drive_right, m.lift, m.tilt, m.throttle};
  for (double v : values)
    if (!std::isfinite(v)) {
      ++stats_.rejected_nan;
      return false;
    }
  // Lockstep: an operator answers a state sent again with the same answer
  // (a lost datagram is so asked for again); the copies are not commands.
  if (awaited_step_ >= 0 && have_command_ && m.sender_id == last_sender_ && m.seq == last_seq_ &&
      m.sim_step == last_sim_step_) {
    ++stats_.repeated;
    return false;
  }
  if (awaited_step_ >= 0 && m.sim_step != awaited_step_) {
    ++stats_.rejected_tick;
    return false;
  }
  if (have_command_ && m.sender_id == last_sender_ && m.seq <= last_seq_) {
    ++stats_.rejected_stale;
    return false;
  }
  bool clamped = false;
  const auto clamp = [&clamped](double v, double lo, double hi) {
    const double c = std::clamp(v, lo, hi);
    clamped = clamped || c != v;
    return c;
  };
  newest_.drive_left = clamp(m.drive_left, -1.0, 1.0);
  newest_.drive_right = clamp(m.drive_right, -1.0, 1.0);
  newest_.lift = clamp(m.lift, -1.0, 1.0);
  newest_.tilt = clamp(m.tilt, -1.0, 1.0);
  newest_.throttle = clamp(m.throttle, 0.0, 1.0);
  newest_.parking_brake = m.parking_brake;
  stats_.clamped += clamped;
  ++stats_.accepted;
  last_seq_ = m.seq;
  last_sender_ = m.sender_id;
  last_sim_step_ = m.sim_step;
  newest_time_s_ = sim_time_s;
  have_command_ = true;
  return true;
}

vehicle::LoaderControls ControlInput::controls(double sim_time_s) {
  const bool fresh = have_command_ && sim_time_s - newest_time_s_ <= watchdog_s_;
  if (fresh) {
    neutral_ = false;
    return newest_;
  }
  if (!neutral_) ++stats_.watchdog_trips;
  neutral_ = true;
  vehicle::LoaderControls c;
  c.throttle = have_command_ ? newest_.throttle : c.throttle;
  c.parking_brake = true;
  return c;
}

}  // namespace skidsim::io
