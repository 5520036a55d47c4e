// The operator's controls over LCM (README, "File formats"): validation, clamping,
// rejection and counting; the watchdog; the bridge over a real LCM provider
// (in-process memq://, and UDP multicast on this host).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <thread>
#include <vector>

#include "io/atomic_file.h"
#include "io/control_input.h"
#include "io/lcm_bridge.h"

namespace skidsim::io {
namespace {

skidsim_lcm::control_t command(std::int64_t seq, double drive = 0.5) {
  skidsim_lcm::control_t c{};
  c.seq = seq;
  c.sender_time_us = 0;
  c.sim_step = -1;
  c.drive_left = c.drive_right = drive;
  c.lift = 0.2;
  c.tilt = -0.3;
  c.throttle = 1.0;
  c.parking_brake = false;
  return c;
}

TEST(ControlInput, ClampsOutOfRangeRejectsNanAndStaleAndCountsEach) {
  ControlInput in(0.2);
  EXPECT_TRUE(in.offer(command(1), 0.0));
  skidsim_lcm::control_t wild = command(2, 7.0);
  wild.throttle = -3.0;
  EXPECT_TRUE(in.offer(wild, 0.01));
  vehicle::LoaderControls c = in.controls(0.01);
  EXPECT_EQ(c.drive_left, 1.0);
  EXPECT_EQ(c.throttle, 0.0);
  skidsim_lcm::control_t bad = command(3);
  bad.lift = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(in.offer(bad, 0.02));
  EXPECT_FALSE(in.offer(command(2), 0.02)) << "a sequence number not above the last is stale";
  EXPECT_EQ(in.controls(0.02).drive_left, 1.0) << "rejected commands change nothing";
  EXPECT_EQ(in.stats().accepted, 2);
  EXPECT_EQ(in.stats().clamped, 1);
  EXPECT_EQ(in.stats().rejected_nan, 1);
  EXPECT_EQ(in.stats().rejected_stale, 1);
}

TEST(ControlInput, RestartedOperatorIsANewSenderNotStale) {
  ControlInput in(0.2);
  skidsim_lcm::control_t a = command(500);
  a.sender_id = 11;
  EXPECT_TRUE(in.offer(a, 0.0));
  skidsim_lcm::control_t b = command(1, 0.9);
  b.sender_id = 12;  // the operator restarted: its count starts again
  EXPECT_TRUE(in.offer(b, 0.5));
  EXPECT_EQ(in.controls(0.5).drive_left, 0.9);
  EXPECT_EQ(in.stats().rejected_stale, 0);
}

// Lockstep: only the awaited tick's answer counts. A command stamped for a
// far-future tick must not stand in for every tick after it (the session
// would run on with nobody at the controls), nor one for a past tick.
TEST(ControlInput, LockstepAcceptsOnlyTheAwaitedTick) {
  ControlInput in(0.2);
  in.await_step(10);
  skidsim_lcm::control_t future = command(1, 0.9);
  future.sim_step = 1000000000;
  EXPECT_FALSE(in.offer(future, 0.02));
  skidsim_lcm::control_t past = command(2, 0.9);
  past.sim_step = 5;
  EXPECT_FALSE(in.offer(past, 0.02));
  EXPECT_EQ(in.last_sim_step(), -1);
  EXPECT_EQ(in.stats().rejected_tick, 2);
  skidsim_lcm::control_t now = command(3, 0.4);
  now.sim_step = 10;
  EXPECT_TRUE(in.offer(now, 0.02));
  EXPECT_EQ(in.last_sim_step(), 10);
  EXPECT_EQ(in.controls(0.02).drive_left, 0.4);
  in.await_step(15);
  EXPECT_FALSE(in.offer(now, 0.03)) << "the same tick again is not the next one";
}

TEST(ControlInput, WatchdogReturnsToNeutralWhenCommandsStop) {
  ControlInput in(0.2);
  EXPECT_TRUE(in.neutral());
  EXPECT_TRUE(in.controls(0.0).parking_brake) << "before the first command: neutral, braked";
  in.offer(command(1), 1.0);
  EXPECT_EQ(in.controls(1.1).drive_left, 0.5);
  EXPECT_FALSE(in.neutral());
  const vehicle::LoaderControls c = in.controls(1.3);  // 0.3 s without a command
  EXPECT_TRUE(in.neutral());
  EXPECT_EQ(c.drive_left, 0.0);
  EXPECT_EQ(c.lift, 0.0);
  EXPECT_TRUE(c.parking_brake);
  EXPECT_EQ(in.stats().watchdog_trips, 1);
  in.controls(1.4);
  EXPECT_EQ(in.stats().watchdog_trips, 1) << "one trip per silence";
  in.offer(command(2), 1.5);
  EXPECT_EQ(in.controls(1.5).drive_left, 0.5) << "commands resume";
  EXPECT_THROW(ControlInput(0.0), std::invalid_argument);
}

TEST(LcmBridge, ControlsInStateOutOverMemq) {
  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  ControlInput in(0.2);
  LcmBridge bridge(lcm, LcmChannels{}, &in);
  // A command, then garbage on the control channel.
  skidsim_lcm::control_t c = command(1, 0.25);
  lcm.publish("SKIDSIM_CONTROL", &c);
  const char garbage[] = "not an lcm message";
  lcm.publish("SKIDSIM_CONTROL", garbage, sizeof garbage);
  EXPECT_EQ(bridge.poll(0.5), 2);
  EXPECT_EQ(in.controls(0.5).drive_left, 0.25);
  EXPECT_EQ(in.stats().malformed, 1);
  // State out: someone listening gets it whole.
  struct Listener {
    std::vector<skidsim_lcm::state_t> got;
    void on(const lcm::ReceiveBuffer*, const std::string&, const skidsim_lcm::state_t* s) { got.push_back(*s); }
  } listener;
  lcm.subscribe("SKIDSIM_STATE", &Listener::on, &listener);
  skidsim_lcm::state_t s{};
  s.step = 250;
  s.sim_time_s = 0.5;
  s.num_wheels = 4;
  s.wheel_speed_rad_s.assign(4, 1.5);
  s.wheel_slip.assign(4, 0.1);
  s.active_task = "move";
  bridge.publish_state(s);
  bridge.poll(0.5);
  ASSERT_EQ(listener.got.size(), 1u);
  EXPECT_EQ(listener.got[0].step, 250);
  EXPECT_EQ(listener.got[0].wheel_speed_rad_s[3], 1.5);
  EXPECT_EQ(listener.got[0].active_task, "move");
}

// Two processes' worth of LCM (two instances) over UDP multicast on this
// host, ttl 0: an operator publishes, the simulator's bridge receives.
TEST(LcmBridge, ControlsArriveOverUdpMulticast) {
  const std::string url = "udpm://239.255.76.67:7669?ttl=0";
  lcm::LCM operator_side(url);
  ASSERT_TRUE(operator_side.good()) << "no UDP multicast on this host";
  ControlInput in(0.2);
  LcmBridge bridge(url, LcmChannels{}, &in);
  bool arrived = false;
  for (int attempt = 1; attempt <= 40 && !arrived; ++attempt) {
    skidsim_lcm::control_t c = command(attempt, 0.75);
    operator_side.publish("SKIDSIM_CONTROL", &c);
    arrived = bridge.wait(50, 0.0) && in.stats().accepted > 0;
  }
  ASSERT_TRUE(arrived) << "a command sent over " << url << " did not arrive";
  EXPECT_EQ(in.controls(0.0).drive_left, 0.75);
}

TEST(LcmBridge, UnopenableProviderIsAnInputError) {
  ControlInput in(0.2);
  EXPECT_THROW(LcmBridge("nonsense://here", LcmChannels{}, &in), InputError);
}

}  // namespace
}  // namespace skidsim::io
