// The load in the bucket feels the apparent gravity of its accelerating
// frame (fast flows, World::enable_fast_flow; issue "Fast granular flows"):
// a heaped bucket braked hard from full speed throws its heap over the lip,
// a level-struck one carried and stopped gently keeps its load. The spill is
// set beside a rigid-wedge estimate: the load above the plane through the
// lip at the stop angle to the apparent horizontal at the peak deceleration
// (a Coulomb wedge sliding out), evaluated on the load as braking starts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "common/physical_constants.h"
#include "engine/soil_site.h"
#include "engine/world.h"
#include "tests/loader_support.h"

namespace skidsim::testing {
namespace {

// A loader on a bare site (a soil grid with no soil over firm ground), its
// bucket rolled back, loaded level-struck to its lip's height in the world
// and, when `heaped`, with a heap on top rising from the lip at 0.9 of the
// repose slope to 0.25 m above the struck level.
std::unique_ptr<engine::World> loaded_loader(double cells_per_m, bool heaped, bool fast_flow) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(0, 0, shipped_loader().tyre.radius_m - 0.01);
  auto w = std::make_unique<engine::World>(shipped_loader(), engine::FirmGround{}, pose, 0.3, 0.0);
  w->add_soil_site(engine::flat_soil_grid(dry_sand().flow, cells_per_m, {-3.0, -4.0}, 40.0, 8.0, 0.0), dry_sand().terramechanics);
  if (fast_flow) w->enable_fast_flow(terrain::session_flow_parameters());  // as the sessions run it
  vehicle::LoaderControls c;
  for (int s = 0; s < 1500; ++s) {
    c = {};
    hold_pitch(*w, 0.3, c);
    w->step(c);
  }
  terrain::BodyAutomaton& b = *w->bucket_material();
  terrain::GranularGrid& g = b.grid();
  const double d = g.cell_size_m();
  const Eigen::Vector3d up = b.geometric_up();
  // The lip: the floor's front edge; the struck level its world height.
  const double lip_z = b.world_point(g.nx() - 0.5, 0.5 * g.ny(), 0.0).z();
  const double tan_repose = std::tan(dry_sand().flow.repose_angle_deg * kPi / 180.0);
  for (int j = 0; j < g.ny(); ++j)
    for (int i = 0; i < g.nx(); ++i) {
      const double floor_z = b.world_point(i, j, 0.0).z();
      double h = std::max(0.0, (lip_z - floor_z) / up.z());
      if (heaped) h += std::min(0.25, (g.nx() - 0.5 - i) * d * tan_repose * 0.9);
      g.set_material_m(i, j, h);
    }
  // What the bucket cannot hold at rest runs off before the test starts.
  for (int s = 0; s < 1500; ++s) {
    c = {};
    hold_pitch(*w, 0.3, c);
    w->step(c);
  }
  return w;
}

struct Carry {
  double loaded_kg = 0.0, spilled_kg = 0.0, peak_decel_m_s2 = 0.0, wedge_kg = 0.0;
};

// The rigid-wedge estimate: the load above the plane through the lip (the
// floor's front edge) at the stop angle to the apparent horizontal, the
// apparent up being g z + a for a deceleration `decel` along the machine's
// heading (world +x), in the bucket as it stands (heights, pose).
double wedge_spill_kg(const terrain::BodyAutomaton& b, const std::vector<double>& heights_m, const Eigen::Matrix3d& world_from_container,
                      double decel_m_s2) {
  const terrain::GranularGrid& g = b.grid();
  const double d = g.cell_size_m(), tan_stop = std::tan(dry_sand().flow.stop_angle_deg * kPi / 180.0);
  const Eigen::Vector3d up =
      (world_from_container.transpose() * Eigen::Vector3d(-decel_m_s2, 0.0, kGravity_m_s2)).normalized();
  double excess_m = 0.0;
  for (int j = 0; j < g.ny(); ++j)
    for (int i = 0; i < g.nx(); ++i) {
      const double h = heights_m[static_cast<std::size_t>(g.index(i, j))];
      const Eigen::Vector3d lip(g.nx() * d, (j + 0.5) * d, 0.0);
      const auto stable = [&](double z) {
        const Eigen::Vector3d v = Eigen::Vector3d((i + 0.5) * d, (j + 0.5) * d, z) - lip;
        const double rise = up.dot(v);
        return rise <= (v - rise * up).norm() * tan_stop;
      };
      if (stable(h)) continue;
      double lo = 0.0, hi = h;  // the column's highest stable point
      for (int k = 0; k < 40; ++k) (stable(0.5 * (lo + hi)) ? lo : hi) = 0.5 * (lo + hi);
      excess_m += h - lo;
    }
  return excess_m / terrain::kHeightQuantumM * g.quantum_mass_kg();
}

// Drives straight at `speed` lever for 3 s holding the bucket's pitch, then
// lets the levers go to neutral over `stop_s` (0: at once) and waits 3 s.
Carry drive_and_stop(engine::World& w, double speed, double stop_s) {
  Carry r;
  r.loaded_kg = w.bucket_material()->material_mass_kg();
  vehicle::LoaderControls c;
  const int drive_steps = 1500, stop_steps = static_cast<int>(stop_s / 0.002);
  std::vector<double> heights;
  Eigen::Matrix3d frame = Eigen::Matrix3d::Identity();
  for (int s = 0; s < drive_steps + 1500; ++s) {
    if (s == drive_steps) {
      const terrain::GranularGrid& g = w.bucket_material()->grid();
      heights.assign(static_cast<std::size_t>(g.nx() * g.ny()), 0.0);
      for (int j = 0; j < g.ny(); ++j)
        for (int i = 0; i < g.nx(); ++i) heights[static_cast<std::size_t>(g.index(i, j))] = g.material_m(i, j);
      frame = w.bucket_material()->pose().linear();
    }
    c = {};
    hold_pitch(w, 0.3, c);
    const double lever = s < drive_steps ? speed : std::max(0.0, speed * (1.0 - (s - drive_steps) / std::max(1.0, double(stop_steps))));
    c.drive_left = c.drive_right = lever;
    w.step(c);
    const Eigen::Vector3d a = w.bucket_material()->frame_acceleration();
    r.peak_decel_m_s2 = std::max(r.peak_decel_m_s2, -a.x());
  }
  for (int s = 0; s < 1500; ++s) w.step({});
  r.spilled_kg = r.loaded_kg - w.bucket_material()->material_mass_kg();
  r.wedge_kg = wedge_spill_kg(*w.bucket_material(), heights, frame, r.peak_decel_m_s2);
  return r;
}

class LoaderSpill : public ::testing::TestWithParam<double> {};

// Braked hard from full speed (levers to neutral at once: 2.7 m/s^2 at the
// bucket, filtered), the heap goes over the lip: between 0.4 and 1 of the
// rigid wedge's estimate, which is an upper bound (the wedge slides out
// whole only if the deceleration lasts; the automaton moves it at its
// rolling rate for the 0.5 s it does). Without the apparent gravity the
// same braking spills nothing: the heap only saw the machine's pitch.
TEST_P(LoaderSpill, AHeapedBucketBrakedHardSpillsOverTheLip) {
  auto w = loaded_loader(GetParam(), true, true);
  const Carry r = drive_and_stop(*w, 1.0, 0.0);
  EXPECT_GT(r.loaded_kg, 500.0);
  EXPECT_GT(r.peak_decel_m_s2, 2.0);
  EXPECT_GT(r.spilled_kg, 0.08 * r.loaded_kg);
  EXPECT_GT(r.spilled_kg, 0.4 * r.wedge_kg);
  EXPECT_LT(r.spilled_kg, 1.0 * r.wedge_kg);
  EXPECT_TRUE(w->events().finite);
  auto plain = loaded_loader(GetParam(), true, false);
  EXPECT_LT(drive_and_stop(*plain, 1.0, 0.0).spilled_kg, 1.0);
  std::printf("[ measured ] %.0f cells/m: heaped %.0f kg braked at %.2f m/s^2 spills %.1f kg (rigid wedge %.1f kg)\n",
              GetParam(), r.loaded_kg, r.peak_decel_m_s2, r.spilled_kg, r.wedge_kg);
}

struct Parked {
  int cells_changed = 0;
  double jitter_m_s2 = 0.0, lost_kg = 0.0;
};

// The loaded machine parked 2 s with the bucket held: how many of the load's
// cells changed, the largest filtered acceleration, the mass lost.
Parked park(engine::World& w) {
  const terrain::GranularGrid& g = w.bucket_material()->grid();
  std::vector<std::int64_t> before;
  for (int k = 0; k < g.nx() * g.ny(); ++k) before.push_back(g.loose_quanta(k));
  const double kg = w.bucket_material()->material_mass_kg();
  Parked p;
  vehicle::LoaderControls c;
  for (int s = 0; s < 1000; ++s) {
    c = {};
    hold_pitch(w, 0.3, c);
    w.step(c);
    p.jitter_m_s2 = std::max(p.jitter_m_s2, w.bucket_material()->frame_acceleration().norm());
  }
  for (int k = 0; k < g.nx() * g.ny(); ++k) p.cells_changed += g.loose_quanta(k) != before[static_cast<std::size_t>(k)];
  p.lost_kg = kg - w.bucket_material()->material_mass_kg();
  return p;
}

// Level-struck, driven at 0.4 of full speed and stopped over 3 s, the load
// stays (under 1 %). Parked, the filtered acceleration stays under
// 0.05 m/s^2 and the load moves about as much as without the apparent
// gravity: the automaton's own slow creep on the struck surface, within a
// tenth (the load's inertia parks the machine a hair differently); the
// contacts' chatter does not rock it.
TEST_P(LoaderSpill, ALevelStruckBucketCarriedGentlyKeepsItsLoad) {
  auto w = loaded_loader(GetParam(), false, true);
  auto plain = loaded_loader(GetParam(), false, false);
  const Parked felt = park(*w), still = park(*plain);
  EXPECT_LT(felt.jitter_m_s2, 0.05);
  EXPECT_LE(felt.cells_changed, still.cells_changed + still.cells_changed / 10 + 2);
  EXPECT_LT(felt.lost_kg, 0.01);
  const Carry r = drive_and_stop(*w, 0.4, 3.0);
  EXPECT_GT(r.loaded_kg, 250.0);
  EXPECT_LT(r.spilled_kg, 0.01 * r.loaded_kg);
  EXPECT_LT(r.peak_decel_m_s2, 0.6);
  std::printf("[ measured ] %.0f cells/m: level-struck %.0f kg stopped at %.2f m/s^2 spills %.1f kg; parked: %.3f m/s^2, "
              "%d cells changed (%d without the apparent gravity)\n",
              GetParam(), r.loaded_kg, r.peak_decel_m_s2, r.spilled_kg, felt.jitter_m_s2, felt.cells_changed, still.cells_changed);
}

// The load's inertia on the machine (with the apparent gravity): a
// level-struck load driven at full speed and let go at once pushes on the
// bucket while the machine stops, and over the stop that push's impulse
// is the load's momentum m v0 (what it must lose), though it acts through
// the filtered acceleration; the machine, heavier to stop, runs on farther
// than with the load's weight alone (a little: the hydrostatic drive holds
// the deceleration it is asked for, and takes the momentum), and ends at
// rest without rocking.
struct Stop {
  double impulse_Ns = 0.0, momentum_Ns = 0.0, distance_m = 0.0, end_speed_m_s = 0.0, end_push_N = 0.0;
};
Stop full_speed_stop(engine::World& w) {
  Stop r;
  vehicle::LoaderControls c;
  for (int s = 0; s < 1500; ++s) {
    c = {};
    hold_pitch(w, 0.3, c);
    c.drive_left = c.drive_right = 1.0;
    w.step(c);
  }
  const double x0 = w.loader().link_pose(0).translation().x();
  r.momentum_Ns = w.bucket_material()->material_mass_kg() * w.loader().chassis_velocity().x();
  for (int s = 0; s < 2000; ++s) {
    c = {};
    hold_pitch(w, 0.3, c);
    w.step(c);
    r.impulse_Ns += w.bucket_load_force_N().x() * 0.002;
  }
  r.distance_m = w.loader().link_pose(0).translation().x() - x0;
  r.end_speed_m_s = w.loader().chassis_velocity().norm();
  r.end_push_N = std::abs(w.bucket_load_force_N().x());
  return r;
}

TEST_P(LoaderSpill, TheLoadsMomentumPushesOnTheMachineAsItStops) {
  auto w = loaded_loader(GetParam(), false, true);
  auto plain = loaded_loader(GetParam(), false, false);
  const Stop felt = full_speed_stop(*w), weight_only = full_speed_stop(*plain);
  std::printf("[ measured ] %.0f cells/m: stopping from full speed, the load's push %.1f N s against its momentum %.1f N s; "
              "stopped in %.3f m (%.3f m with its weight alone); at rest %.4f m/s, push %.2f N\n",
              GetParam(), felt.impulse_Ns, felt.momentum_Ns, felt.distance_m, weight_only.distance_m, felt.end_speed_m_s, felt.end_push_N);
  EXPECT_GT(felt.momentum_Ns, 250.0);
  EXPECT_NEAR(felt.impulse_Ns, felt.momentum_Ns, 0.05 * felt.momentum_Ns);
  EXPECT_NEAR(weight_only.impulse_Ns, 0.0, 1e-9);
  EXPECT_GT(felt.distance_m, weight_only.distance_m);
  EXPECT_LT(felt.end_speed_m_s, 0.01);
  EXPECT_LT(felt.end_push_N, 1.0);
  EXPECT_TRUE(w->events().finite);
}

INSTANTIATE_TEST_SUITE_P(TwoCellSizes, LoaderSpill, ::testing::Values(20.0, 10.0));

}  // namespace
}  // namespace skidsim::testing
