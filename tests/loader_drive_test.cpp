// The loader on firm ground: top speed, turning in place, standing on a
// slope with the brake on, and bit-for-bit determinism.
#include <gtest/gtest.h>

#include <cstring>

#include "common/physical_constants.h"
#include "tests/loader_support.h"
#include "vehicle/loader_figures.h"

namespace skidsim::testing {
namespace {

TEST(LoaderDrive, TopSpeedOnFlatGroundIsTheRatedElevenKmH) {
  auto w = loader_on_ground();
  vehicle::LoaderControls c;
  c.drive_left = c.drive_right = 1.0;
  run_for(*w, c, 6.0);
  const double speed_km_h = 3.6 * w->loader().chassis_velocity().norm();
  const double rated_km_h = 3.6 * shipped_loader().drive.top_speed_m_per_s;
  RecordProperty("top_speed_km_h", std::to_string(speed_km_h));
  EXPECT_NEAR(speed_km_h, rated_km_h, 0.03 * rated_km_h);
  // Straight: equal levers keep the heading.
  EXPECT_LT(std::abs(w->loader().chassis_angular_velocity().z()), 1e-3);
  // Reverse too.
  c.drive_left = c.drive_right = -1.0;
  run_for(*w, c, 8.0);
  EXPECT_NEAR(3.6 * w->loader().chassis_velocity().norm(), rated_km_h, 0.03 * rated_km_h);
}

TEST(LoaderDrive, OppositeLeversTurnItInPlace) {
  for (double lever : {1.0, 0.3}) {
    auto w = loader_on_ground();
    const vehicle::Loader& l = w->loader();
    const Eigen::Vector3d start = l.centre_of_mass();
    vehicle::LoaderControls c;
    c.drive_left = lever;
    c.drive_right = -lever;
    run_for(*w, c, 1.0);
    double farthest = 0.0, heading_turned = 0.0;
    Eigen::Vector2d centre_sum = Eigen::Vector2d::Zero();
    const int n = 5000;
    for (int i = 0; i < n; ++i) {
      w->step(c);
      farthest = std::max(farthest, (l.centre_of_mass() - start).head<2>().norm());
      const double yaw_rate = l.chassis_angular_velocity().z();
      heading_turned += yaw_rate * engine::kStepSeconds;
      // Instantaneous centre of rotation, in the chassis frame.
      const Eigen::Isometry3d chassis = l.link_pose(0);
      const Eigen::Vector3d v_origin =
          l.chassis_velocity() + l.chassis_angular_velocity().cross(chassis.translation() - l.link_pose(0) *
                                                                        shipped_loader().links[0].com.position_m);
      const Eigen::Vector3d offset_world(-v_origin.y() / yaw_rate, v_origin.x() / yaw_rate, 0.0);
      centre_sum += (chassis.linear().transpose() * offset_world).head<2>();
    }
    const Eigen::Vector2d centre = centre_sum / n;
    RecordProperty("turn_centre_x_m_lever_" + std::to_string(lever), std::to_string(centre.x()));
    // Left forward, right back: clockwise seen from above (yaw rate < 0).
    EXPECT_LT(heading_turned, -lever * 5.0) << "lever " << lever;
    // In place: it turns about a point between its axles (nearer the heavier
    // rear axle) and near its centre line (the spin's centripetal load moves
    // it sideways a little), and its centre of mass stays on its footprint.
    EXPECT_LT(std::abs(centre.x()), 0.515) << "lever " << lever;
    EXPECT_LT(std::abs(centre.y()), 0.2) << "lever " << lever;
    EXPECT_LT(farthest, 0.8) << "lever " << lever;
    EXPECT_TRUE(w->events().finite);
  }
}

TEST(LoaderDrive, StandsOnATwentyDegreeSlopeWithTheBrakeOnWithoutCreep) {
  const double slope = 20.0 * kPi / 180.0;
  for (double yaw_deg : {0.0, 180.0, 90.0}) {
    auto w = loader_on_ground(slope, yaw_deg * kPi / 180.0);
    vehicle::LoaderControls c;
    c.parking_brake = true;
    run_for(*w, c, 1.0);  // settle the tyres' deflection
    const Eigen::Vector3d before = w->loader().link_pose(0).translation();
    run_for(*w, c, 10.0);
    const double drift_mm = 1e3 * (w->loader().link_pose(0).translation() - before).norm();
    RecordProperty("drift_mm_yaw_" + std::to_string(static_cast<int>(yaw_deg)), std::to_string(drift_mm));
    EXPECT_LT(drift_mm, 1.0) << "facing " << yaw_deg << " deg from uphill";
    EXPECT_LT(w->loader().chassis_velocity().norm(), 1e-3);
  }
}

// Throttle shut: the governor holds idle, the pumps turn slower, and the
// drive still has the engine's idle power: it drives slowly on the flat and
// holds on a slope with the levers in neutral and no brake.
TEST(LoaderDrive, ThrottleShutDrivesSlowlyAndHoldsOnASlope) {
  const auto& d = shipped_loader();
  {
    auto w = loader_on_ground();
    vehicle::LoaderControls c;
    c.throttle = 0.0;
    c.drive_left = c.drive_right = 1.0;
    run_for(*w, c, 6.0);
    // The governor sits on its idle droop line, between idle and idle plus
    // the droop; the pumps' flow, and the speed, follow the engine.
    const double rpm = w->loader().engine_speed_rpm();
    EXPECT_GT(rpm, d.engine.idle_rpm - 50.0);
    EXPECT_LT(rpm, d.engine.idle_rpm + d.engine.governor_droop * d.engine.rated_rpm);
    const double expected = d.drive.top_speed_m_per_s * rpm / (d.engine.rated_rpm * (1.0 + d.engine.governor_droop));
    EXPECT_NEAR(w->loader().chassis_velocity().norm(), expected, 0.03 * expected);
  }
  {
    auto w = loader_on_ground(10.0 * kPi / 180.0);
    vehicle::LoaderControls c;
    c.throttle = 0.0;
    const Eigen::Vector3d before = w->loader().link_pose(0).translation();
    run_for(*w, c, 3.0);
    const double drift = (w->loader().link_pose(0).translation() - before).norm();
    RecordProperty("neutral_drift_10deg_3s_m", std::to_string(drift));
    EXPECT_LT(drift, 0.05);  // the hydrostats' droop under the slope's load, no runaway
  }
  {
    // With the throttle open and no load the engine runs up to high idle,
    // and back down to idle when it is shut (friction slows it).
    auto w = loader_on_ground();
    vehicle::LoaderControls c;
    c.throttle = 1.0;
    run_for(*w, c, 3.0);
    EXPECT_GT(w->loader().engine_speed_rpm(), d.engine.rated_rpm);
    c.throttle = 0.0;
    run_for(*w, c, 5.0);
    EXPECT_NEAR(w->loader().engine_speed_rpm(), d.engine.idle_rpm * (1.0 + d.engine.governor_droop * d.engine.rated_rpm / d.engine.idle_rpm), 60.0);
  }
}

// Pushing against a wall with the bucket (a Bullet rigid contact): the
// machine stops, and its tyres push with what the drive's relief and the
// ground's friction allow: the class's push force (S570: 2535 kgf, 24.9 kN).
TEST(LoaderDrive, PushingAgainstAWallGivesTheClasssPushForce) {
  engine::FirmGround ground;
  engine::StaticBox wall;
  wall.pose.translation() = Eigen::Vector3d(4.0, 0.0, 1.0);
  wall.half_extents_m = Eigen::Vector3d(0.5, 3.0, 1.0);
  ground.boxes.push_back(wall);
  auto w = loader_on_ground(0.0, 0.0, 0.2, 0.0, ground);
  vehicle::LoaderControls c;
  c.drive_left = c.drive_right = 1.0;
  run_for(*w, c, 5.0);
  double push = 0.0;
  for (int i = 0; i < 500; ++i) {
    w->step(c);
    for (const auto& ws : w->loader().wheels()) push += ws.longitudinal_force_N / 500.0;
  }
  RecordProperty("push_force_kN", std::to_string(push / 1e3));
  EXPECT_LT(w->loader().chassis_velocity().norm(), 0.05);
  const auto& d = shipped_loader();
  const vehicle::LoaderFigures f = vehicle::loader_figures(d);
  const double friction = d.tyre.mu_x * kGravity_m_s2 * d.total_mass_kg();
  EXPECT_NEAR(push, std::min(1e3 * f.push_force_kN, friction), 0.1 * friction);
  for (int k = 0; k < 4; ++k) EXPECT_LT(w->loader().wheel_hub(k).x() + d.tyre.radius_m, 3.5);  // nothing through the wall
  EXPECT_TRUE(w->events().finite);
}

// A full-lever launch from standstill, and from a brake released with the
// levers already forward, keeps all four wheels on the ground: the pumps
// stroke up at their own pace.
TEST(LoaderDrive, FullLeverLaunchKeepsTheFrontWheelsDown) {
  const auto& d = shipped_loader();
  for (bool from_brake : {false, true}) {
    auto w = loader_on_ground();
    vehicle::LoaderControls c;
    c.drive_left = c.drive_right = 1.0;
    if (from_brake) {
      c.parking_brake = true;
      run_for(*w, c, 2.0);
      c.parking_brake = false;
    }
    double least_front = 1e300;
    for (int i = 0; i < 1500; ++i) {
      w->step(c);
      double front = 0.0;
      for (size_t k = 0; k < d.wheels.size(); ++k)
        if (d.wheels[k].hub_m.x() > 0.0) front += w->loader().wheels()[k].normal_load_N;
      least_front = std::min(least_front, front);
    }
    RecordProperty(std::string("least_front_load_N") + (from_brake ? "_from_brake" : ""), std::to_string(least_front));
    EXPECT_GT(least_front, 0.05 * kGravity_m_s2 * d.total_mass_kg()) << (from_brake ? "from the brake" : "from standstill");
  }
}

// Pulled back hard while driving at full lever: the pumps take no more than
// the engine can give (anti-stall), so the engine keeps turning near its
// rated speed and the machine slows instead.
TEST(LoaderDrive, HeavyPullDoesNotStallTheEngine) {
  for (double pull_kN : {16.0, 20.0}) {
    auto w = loader_on_ground();
    vehicle::LoaderControls c;
    c.drive_left = c.drive_right = 1.0;
    run_for(*w, c, 4.0);
    w->set_link_load(0, Eigen::Vector3d(-1e3 * pull_kN, 0, 0), Eigen::Vector3d(-1.35, 0.0, 0.0));
    double slowest_rpm = 1e300;
    for (int i = 0; i < 5000; ++i) {
      w->step(c);
      slowest_rpm = std::min(slowest_rpm, w->loader().engine_speed_rpm());
    }
    RecordProperty("slowest_rpm_at_" + std::to_string(static_cast<int>(pull_kN)) + "_kN", std::to_string(slowest_rpm));
    EXPECT_GT(slowest_rpm, 0.8 * shipped_loader().engine.rated_rpm) << pull_kN << " kN";
    EXPECT_GT(w->loader().chassis_velocity().x(), 0.2) << pull_kN << " kN";  // still going, slower
  }
}

TEST(LoaderDrive, SameControlsGiveTheSameStateBitForBit) {
  auto run = [] {
    auto w = loader_on_ground();
    vehicle::LoaderControls c;
    for (int i = 0; i < 3000; ++i) {
      c.drive_left = std::sin(i * 0.003);
      c.drive_right = std::cos(i * 0.002);
      c.lift = i < 1500 ? 0.8 : -0.5;
      c.tilt = i % 700 < 350 ? 0.4 : -0.4;
      w->step(c);
    }
    const Eigen::Isometry3d p = w->loader().link_pose(2);
    return std::array<double, 5>{p.translation().x(), p.translation().y(), p.translation().z(),
                                 w->loader().joint_angle(0), w->loader().side_wheel_speed(1)};
  };
  const auto a = run(), b = run();
  EXPECT_EQ(0, std::memcmp(a.data(), b.data(), sizeof(a)));
}

}  // namespace
}  // namespace skidsim::testing
