// Lift and tilt cylinders: flow-limited speed, relief-limited force, holding.
#include <gtest/gtest.h>

#include <numeric>

#include "common/physical_constants.h"
#include "tests/loader_support.h"
#include "vehicle/cylinder_geometry.h"

namespace skidsim::testing {
namespace {

constexpr double kRpmToRadS = 2.0 * kPi / 60.0;

// Runs a cylinder from one end of its joint's range to the other and returns
// {simulated seconds, seconds that flow / area predict}. The prediction uses
// the pump's mean flow over the move (it follows the engine's speed); the
// spool's opening (0.15 s) adds about 0.08 s, inside the tolerance.
std::pair<double, double> stroke_time(engine::World& w, int joint, double lever) {
  const auto& d = shipped_loader();
  const vehicle::Cylinder& cyl = d.cylinders[joint];
  const vehicle::ImplementJoint& j = d.joints[joint];
  const double target = lever > 0 ? j.upper_rad : j.lower_rad;
  // Which way the cylinder goes decides the area the flow fills.
  const double l0 = vehicle::cylinder_kinematics(cyl, j, w.loader().joint_angle(joint)).length_m;
  const double l1 = vehicle::cylinder_kinematics(cyl, j, target).length_m;
  const double area = l1 > l0 ? cyl.piston_area_m2() : cyl.annulus_area_m2();
  vehicle::LoaderControls c;
  run_for(w, c, 0.5);  // spools closed: each move starts from neutral
  (joint == 0 ? c.lift : c.tilt) = lever;
  double t = 0.0, engine_speed_sum = 0.0;
  long n = 0;
  while (std::abs(w.loader().joint_angle(joint) - target) > 1e-3 && t < 30.0) {
    w.step(c);
    engine_speed_sum += w.loader().engine_speed_rpm();
    ++n;
    t += engine::kStepSeconds;
  }
  const double mean_flow = d.implement_pump.flow_at_rated_m3_per_s * (engine_speed_sum / n) / d.engine.rated_rpm;
  return {t, std::abs(l1 - l0) * area / mean_flow};
}

TEST(LoaderHydraulics, LiftFromGroundToFullHeightTakesTheTimeFlowAndAreaPredict) {
  auto w = loader_on_ground(0.0, 0.0, 0.0, -0.2);
  const auto [t, predicted] = stroke_time(*w, 0, 1.0);
  RecordProperty("lift_s", std::to_string(t));
  RecordProperty("lift_predicted_s", std::to_string(predicted));
  EXPECT_NEAR(t, predicted, 0.05 * predicted);
  // The hinge pin reaches the thesis's G = 2.80 m (less the tyres' squash).
  EXPECT_NEAR(w->loader().link_pose(2).translation().z(), 2.80, 0.03);
  // Lowering runs the rod side: faster by the area ratio.
  const auto [t_down, predicted_down] = stroke_time(*w, 0, -1.0);
  EXPECT_NEAR(t_down, predicted_down, 0.05 * predicted_down);
  EXPECT_LT(t_down, t);
}

TEST(LoaderHydraulics, BucketCurlAndDumpTakeTheTimeFlowAndAreaPredict) {
  auto w = loader_on_ground(0.0, 0.0, 0.6, 0.0);
  const auto [t_dump, predicted_dump] = stroke_time(*w, 1, 1.0);
  EXPECT_NEAR(t_dump, predicted_dump, 0.05 * predicted_dump);
  const auto [t_curl, predicted_curl] = stroke_time(*w, 1, -1.0);
  RecordProperty("curl_s", std::to_string(t_curl));
  EXPECT_NEAR(t_curl, predicted_curl, 0.05 * predicted_curl);
}

TEST(LoaderHydraulics, ClosedSpoolsHoldTheArmAndBucket) {
  auto w = loader_on_ground(0.0, 0.0, 1.0, 0.5);
  vehicle::LoaderControls c;
  run_for(*w, c, 0.5);
  const double lift = w->loader().joint_angle(0), tilt = w->loader().joint_angle(1);
  run_for(*w, c, 10.0);
  EXPECT_NEAR(w->loader().joint_angle(0), lift, 1e-4);
  EXPECT_NEAR(w->loader().joint_angle(1), tilt, 1e-4);
}

// Lowering a heavy load: the load sits on the piston side, which holds it
// (up to its relief); the arm comes down at the flow's speed, no faster.
TEST(LoaderHydraulics, HeavyLoadIsLoweredAtTheFlowsSpeed) {
  auto w = loader_on_ground(0.0, 0.0, 1.2, 0.0);  // bucket rolled back: it stays clear of the ground
  const auto& d = shipped_loader();
  const int bucket = static_cast<int>(d.links.size()) - 1;
  // 2 t in the bucket needs more than the rod side's relief to hold; a
  // counterweight on the rear keeps the machine from tipping.
  w->set_link_load(bucket, Eigen::Vector3d(0, 0, -kGravity_m_s2 * 2000.0), d.bucket_load_centre_m);
  w->set_link_load(0, Eigen::Vector3d(0, 0, -kGravity_m_s2 * 3000.0), Eigen::Vector3d(-1.3, 0.0, 0.0));
  vehicle::LoaderControls c;
  run_for(*w, c, 1.0);
  c.lift = -1.0;
  const vehicle::Cylinder& cyl = d.cylinders[0];
  double fastest = 0.0, weakest_push = 1e300;
  int moving = 0;
  for (int i = 0; i < 1500; ++i) {
    w->step(c);
    if (i < 50 || w->loader().joint_angle(0) < 0.15) continue;  // skip the start and the end stop
    const double flow = d.implement_pump.flow_at_rated_m3_per_s * w->loader().engine_speed_rpm() / d.engine.rated_rpm;
    fastest = std::max(fastest, -w->loader().cylinders()[0].speed_m_per_s / (flow / cyl.annulus_area_m2()));
    weakest_push = std::min(weakest_push, w->loader().cylinders()[0].force_N);
    ++moving;
  }
  ASSERT_GT(moving, 500);
  RecordProperty("lowering_speed_over_flow_speed", std::to_string(fastest));
  EXPECT_LT(fastest, 1.02);
  EXPECT_GT(fastest, 0.95);
  EXPECT_GT(weakest_push, 0.0);  // the piston side holds the load all the way down
}

// Pushing the lowered bucket down into firm ground: the arm lifts the
// machine's front off the ground onto the bucket, the cylinder bottoms out,
// and the pump's pressure stands at the relief setting, steady.
TEST(LoaderHydraulics, PushingTheBucketIntoTheGroundStallsAtReliefWithoutJitter) {
  auto w = loader_on_ground(0.0, 0.0, 0.1, 0.1);
  vehicle::LoaderControls c;
  c.lift = -1.0;
  run_for(*w, c, 2.5);
  const vehicle::Cylinder& cyl = shipped_loader().cylinders[0];
  std::vector<double> pressure, angle, height;
  for (int i = 0; i < 1000; ++i) {
    w->step(c);
    pressure.push_back(w->loader().cylinders()[0].pressure_Pa);
    angle.push_back(w->loader().joint_angle(0));
    height.push_back(w->loader().link_pose(0).translation().z());
  }
  auto spread = [](const std::vector<double>& v) {
    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    return *hi - *lo;
  };
  const double mean_p = std::accumulate(pressure.begin(), pressure.end(), 0.0) / pressure.size();
  RecordProperty("stall_pressure_MPa", std::to_string(mean_p / 1e6));
  EXPECT_NEAR(mean_p, cyl.relief_pressure_Pa, 0.01 * cyl.relief_pressure_Pa);
  EXPECT_LT(spread(pressure), 0.001 * cyl.relief_pressure_Pa);  // over 2 s
  EXPECT_LT(spread(angle), 1e-5);                                // rad
  EXPECT_LT(spread(height), 1e-5);                               // m
  EXPECT_TRUE(w->loader().cylinders()[0].at_relief);
  // The front wheels are off the ground: the bucket carries the front.
  for (size_t i = 0; i < shipped_loader().wheels.size(); ++i)
    if (shipped_loader().wheels[i].hub_m.x() > 0.0) {
      EXPECT_EQ(w->loader().wheels()[i].normal_load_N, 0.0);
    }
}

}  // namespace
}  // namespace skidsim::testing
