// Static tipping load (SAE J818 / ISO 14397-1: the load at the bucket's load
// centre, arm at the reach of the rating, that lifts the rear wheels) from
// the simulation against the moment balance of the same model.
#include <gtest/gtest.h>

#include "common/physical_constants.h"
#include "tests/loader_support.h"
#include "vehicle/loader_figures.h"

namespace skidsim::testing {
namespace {


// Payload (N, downward at the load centre) that balances the machine about
// its front contact line, for the pose the simulation is in now.
double moment_balance_tipping_load(const vehicle::Loader& l) {
  const auto& d = l.description();
  double front_x = 0.0;
  int front = 0;
  for (size_t i = 0; i < d.wheels.size(); ++i)
    if (d.wheels[i].hub_m.x() > 0.0) {
      front_x += l.wheels()[i].contact_point_m.x();
      ++front;
    }
  front_x /= front;
  double restoring = 0.0;
  for (size_t k = 0; k < d.links.size(); ++k)
    restoring += d.links[k].mass_kg * kGravity_m_s2 * (front_x - (l.link_pose(static_cast<int>(k)) * d.links[k].com.position_m).x());
  const int bucket = static_cast<int>(d.links.size()) - 1;
  const double load_x = (l.link_pose(bucket) * d.bucket_load_centre_m).x();
  return restoring / (load_x - front_x);
}

TEST(LoaderTipping, StaticTippingLoadMatchesTheMomentBalanceAndTheClass) {
  const double q = vehicle::rating_lift_angle(shipped_loader());
  auto w = loader_on_ground(0.0, 0.0, q, q);  // bucket level at full reach
  const auto& d = shipped_loader();
  const int bucket = static_cast<int>(d.links.size()) - 1;
  vehicle::LoaderControls hold;
  double payload_N = 0.0, balance_N = 0.0;
  while (w->events().rear_wheels_unloaded_s < 0.0 && payload_N < 60000.0) {
    payload_N += 200.0 * engine::kStepSeconds;  // 200 N/s: quasi-static
    w->set_link_load(bucket, Eigen::Vector3d(0, 0, -payload_N), d.bucket_load_centre_m);
    w->step(hold);
    balance_N = moment_balance_tipping_load(w->loader());
  }
  ASSERT_GE(w->events().rear_wheels_unloaded_s, 0.0);
  const double tipping_kg = payload_N / kGravity_m_s2, balance_kg = balance_N / kGravity_m_s2;
  RecordProperty("tipping_load_kg", std::to_string(tipping_kg));
  RecordProperty("moment_balance_kg", std::to_string(balance_kg));
  EXPECT_NEAR(tipping_kg, balance_kg, 0.05 * balance_kg);
  // Its class: wheeled skid steers of 2.3-2.9 t tip at about 0.5-0.6 of their
  // operating weight (Bobcat specification sheets: S450 about 0.51, S570 0.61).
  const double ratio = tipping_kg / d.total_mass_kg();
  EXPECT_GT(ratio, 0.45);
  EXPECT_LT(ratio, 0.65);
}

// Raising twice the tipping load from the ground: the machine tips forward
// onto its bucket, the event is reported, and nothing blows up.
TEST(LoaderTipping, LiftingPastTheTippingLoadTipsAndIsReported) {
  auto w = loader_on_ground(0.0, 0.0, 0.1, 0.1);
  const auto& d = shipped_loader();
  const int bucket = static_cast<int>(d.links.size()) - 1;
  w->set_link_load(bucket, Eigen::Vector3d(0, 0, -2.0 * 0.5 * kGravity_m_s2 * d.total_mass_kg()), d.bucket_load_centre_m);
  vehicle::LoaderControls c;
  c.lift = 1.0;
  double lowest_chassis_z = 1e9;
  for (int i = 0; i < 4000; ++i) {
    w->step(c);
    lowest_chassis_z = std::min(lowest_chassis_z, w->loader().link_pose(0).translation().z());
  }
  EXPECT_GE(w->events().rear_wheels_unloaded_s, 0.0);
  EXPECT_TRUE(w->events().finite);
  // Nothing sinks through the ground: the axles stay above it.
  EXPECT_GT(lowest_chassis_z, 0.2);
  for (int i = 0; i < 4; ++i) EXPECT_GT(w->loader().wheel_hub(i).z(), 0.2);
}

}  // namespace
}  // namespace skidsim::testing
