// Engine, implement pump and hydrostatic drive alone.
#include <gtest/gtest.h>

#include "tests/loader_support.h"
#include "vehicle/powertrain.h"

namespace skidsim::vehicle {
namespace {

constexpr double kRpm = 2.0 * skidsim::kPi / 60.0;
const LoaderDescription& loader() { return skidsim::testing::shipped_loader(); }

TEST(Powertrain, EngineGivesRatedPowerAtRatedSpeedAndNothingAtHighIdle) {
  const EngineParameters& e = loader().engine;
  EXPECT_NEAR(full_load_power_W(e, e.rated_rpm * kRpm), 44e3, 1.0);  // thesis: 44 kW at 2800 rpm
  EXPECT_NEAR(engine_torque_N_m(e, 1.0, e.rated_rpm * kRpm) * e.rated_rpm * kRpm, 44e3, 1.0);
  EXPECT_NEAR(engine_torque_N_m(e, 1.0, e.rated_rpm * (1.0 + e.governor_droop) * kRpm), 0.0, 1e-6);
  // Half throttle governs lower.
  EXPECT_EQ(engine_torque_N_m(e, 0.0, e.rated_rpm * kRpm), 0.0);
  EXPECT_GT(engine_torque_N_m(e, 0.0, e.idle_rpm * kRpm), 0.0);
}

TEST(Powertrain, ImplementValvesShareThePumpFlow) {
  const auto& d = loader();
  const double rated = d.engine.rated_rpm * kRpm, q = d.implement_pump.flow_at_rated_m3_per_s;
  auto f = implement_flows_m3_per_s(d.implement_pump, d.engine, rated, 1.0, 0.0);
  EXPECT_DOUBLE_EQ(f[0], q);
  EXPECT_DOUBLE_EQ(f[1], 0.0);
  f = implement_flows_m3_per_s(d.implement_pump, d.engine, rated, 1.0, -1.0);
  EXPECT_DOUBLE_EQ(f[0], 0.5 * q);
  EXPECT_DOUBLE_EQ(f[1], -0.5 * q);
  f = implement_flows_m3_per_s(d.implement_pump, d.engine, 0.5 * rated, 0.4, 0.2);
  EXPECT_DOUBLE_EQ(f[0], 0.4 * 0.5 * q);
}

TEST(Powertrain, DriveFollowsTheLeverUntilReliefAndTheBrakeHolds) {
  const auto& d = loader();
  const double high_idle = d.engine.rated_rpm * (1.0 + d.engine.governor_droop) * kRpm;
  const double r = d.tyre.radius_m;
  DriveSideCommand c = drive_side_command(d.drive, d.engine, r, high_idle, 1.0, 1e9, 0.0, false);
  EXPECT_NEAR(c.target_speed_rad_s * r, d.drive.top_speed_m_per_s, 1e-9);
  const double relief = d.drive.relief_pressure_Pa * d.drive.motor_displacement_m3_per_rad * d.drive.final_drive_ratio *
                        d.drive.efficiency;
  EXPECT_NEAR(c.torque_limit_N_m, relief, 1e-6);
  // Light load: the wheel reaches the target (within the servo's droop).
  double w = 0.0;
  for (int i = 0; i < 2000; ++i) advance_drive_side(d.drive, c, 100.0, 0.002, w);
  EXPECT_NEAR(w, c.target_speed_rad_s - 100.0 / d.drive.servo_gain_N_m_s, 1e-9);
  // Stalled against more than relief: the motor gives exactly relief torque.
  w = 0.0;
  const double torque = advance_drive_side(d.drive, c, 2.0 * relief, 0.002, w);
  EXPECT_DOUBLE_EQ(torque, relief);
  EXPECT_LT(w, 0.0);  // pushed back
  // Power limit: with little power the torque bound drops.
  const DriveSideCommand weak = drive_side_command(d.drive, d.engine, r, high_idle, 1.0, 1000.0, 5.0, false);
  EXPECT_NEAR(weak.motoring_torque_limit_N_m, d.drive.efficiency * 1000.0 / 5.0, 1e-9);
  EXPECT_NEAR(weak.torque_limit_N_m, relief, 1e-6);  // holding costs no power
  w = 5.0;
  EXPECT_NEAR(advance_drive_side(d.drive, weak, 2.0 * relief, 0.002, w), weak.motoring_torque_limit_N_m, 1e-9);
  // Below relief but above the power: the power still bounds it.
  w = 5.0;
  EXPECT_NEAR(advance_drive_side(d.drive, weak, 0.5 * relief, 0.002, w), weak.motoring_torque_limit_N_m, 1e-9);
  w = -1.0;  // pushed backwards against a forward lever: braking, up to relief
  EXPECT_NEAR(advance_drive_side(d.drive, weak, 2.0 * relief, 0.002, w), relief, 1e-9);
  // Parking brake: locked below its torque, slips above it.
  const DriveSideCommand brake = drive_side_command(d.drive, d.engine, r, high_idle, 1.0, 1e9, 0.0, true);
  w = 0.0;
  for (int i = 0; i < 100; ++i) advance_drive_side(d.drive, brake, 0.9 * d.drive.brake_torque_N_m, 0.002, w);
  EXPECT_EQ(w, 0.0);
  advance_drive_side(d.drive, brake, 1.5 * d.drive.brake_torque_N_m, 0.002, w);
  EXPECT_LT(w, 0.0);
}

}  // namespace
}  // namespace skidsim::vehicle
