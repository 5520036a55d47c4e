// The one conversion between the operator's control message (LCM's
// control_t) and the loader's levers, both ways.
#pragma once

#include <cstdint>

#include "skidsim_lcm/control_t.hpp"
#include "vehicle/powertrain.h"

namespace skidsim::session {

inline vehicle::LoaderControls to_controls(const skidsim_lcm::control_t& m) {
  vehicle::LoaderControls c;
  c.drive_left = m.drive_left;
  c.drive_right = m.drive_right;
  c.lift = m.lift;
  c.tilt = m.tilt;
  c.throttle = m.throttle;
  c.parking_brake = m.parking_brake;
  return c;
}

// `seq` and `sim_step` as the sender numbers them; sender_id and the
// sender's clock are the sender's to fill.
inline skidsim_lcm::control_t to_message(const vehicle::LoaderControls& c, std::int64_t seq, std::int64_t sim_step) {
  skidsim_lcm::control_t m{};
  m.seq = seq;
  m.sim_step = sim_step;
  m.drive_left = c.drive_left;
  m.drive_right = c.drive_right;
  m.lift = c.lift;
  m.tilt = c.tilt;
  m.throttle = c.throttle;
  m.parking_brake = c.parking_brake;
  return m;
}

}  // namespace skidsim::session
