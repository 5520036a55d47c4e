// libFuzzer: control_t bytes as they arrive on the control channel:
// decoded by the lcm-gen code, then through io::ControlInput (directly, and
// through io::LcmBridge over memq://). Whatever comes in, the controls the
// simulator applies stay finite and in range, and every message is counted
// exactly once.
#include <cmath>
#include <cstdlib>

#include <lcm/lcm-cpp.hpp>

#include "io/control_input.h"
#include "io/lcm_bridge.h"

namespace {

void check(bool ok) {
  if (!ok) std::abort();
}

void check_controls(skidsim::io::ControlInput& input, double now) {
  const skidsim::vehicle::LoaderControls c = input.controls(now);
  for (double v : {c.drive_left, c.drive_right, c.lift, c.tilt}) check(std::isfinite(v) && std::abs(v) <= 1.0);
  check(std::isfinite(c.throttle) && c.throttle >= 0.0 && c.throttle <= 1.0);
}

std::int64_t counted(const skidsim::io::ControlStats& s) {
  return s.malformed + s.accepted + s.rejected_nan + s.rejected_stale;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace skidsim;
  // Direct: a fresh input, the bytes decoded as one message, then the same
  // bytes cut into messages of the encoded size (a stream of commands).
  {
    io::ControlInput input(0.2);
    skidsim_lcm::control_t m{};
    const int n = m.decode(data, 0, static_cast<int>(size));
    if (n >= 0) {
      check(n <= static_cast<int>(size));
      input.offer(m, 0.0);
    }
    check_controls(input, 0.0);
    const std::size_t step = static_cast<std::size_t>(skidsim_lcm::control_t{}.getEncodedSize());
    double now = 0.0;
    for (std::size_t at = 0; at + step <= size; at += step) {
      skidsim_lcm::control_t c{};
      now += 0.01;
      if (c.decode(data + at, 0, static_cast<int>(step)) >= 0) input.offer(c, now);
      check_controls(input, now);
    }
  }
  // Through the bridge, as the simulator receives it.
  static lcm::LCM lcm("memq://");
  static io::ControlInput input(0.2);
  static io::LcmBridge bridge(lcm, io::LcmChannels{}, &input);
  static double now = 0.0;
  const std::int64_t before = counted(input.stats());
  const std::uint8_t empty = 0;
  lcm.publish(io::LcmChannels{}.control, size ? data : &empty, static_cast<unsigned>(size));
  now += 0.01;
  check(bridge.poll(now) == 1);
  check(counted(input.stats()) == before + 1);
  check_controls(input, now);
  return 0;
}
