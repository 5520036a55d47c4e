// A scripted operator for benchmarks, tests and demos: a wide circle with
// the arm and bucket cycling (lift every 3 s, tilt every 1.4 s), which keeps
// the machine busy on its own site.
#pragma once

#include "vehicle/powertrain.h"

namespace skidsim::engine {

inline vehicle::LoaderControls circle_work_cycle(long step) {
  vehicle::LoaderControls c;
  c.drive_left = 0.8;
  c.drive_right = 0.4;
  c.lift = (step / 1500) % 2 == 0 ? 0.6 : -0.6;
  c.tilt = (step / 700) % 2 == 0 ? 0.5 : -0.5;
  return c;
}

}  // namespace skidsim::engine
