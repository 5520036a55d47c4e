// The stability suite (docs/validation.md, "Stability on hard cases"): each hard
// case must end with finite numbers, material conserved to the quantum, no
// energy from nowhere (a machine left to itself never ends higher or
// faster than it started), nothing through the hard base, and no jitter at
// rest (the braked machine still to 1 mm over its last second).
#include <gtest/gtest.h>

#include <cmath>

#include "common/physical_constants.h"
#include "engine/soil_site.h"
#include "io/soil_table.h"
#include "tests/loader_support.h"

namespace skidsim::testing {
namespace {

const io::SoilRecord& sand() { return dry_sand(); }

vehicle::LoaderControls braked() {
  vehicle::LoaderControls c;
  c.parking_brake = true;
  return c;
}

// Watches a world step by step for what must hold throughout.
struct Watch {
  std::int64_t quanta = -1;  // the books at the start (all automata, parcels, off-site)
  double lowest_hub_above_base_m = 1e9;
  double base_m = 0.0;       // the hard base (or firm ground) under the machine

  static std::int64_t books(const engine::World& w) {
    if (w.material()) return w.material()->total_quanta();
    return w.terrain() ? w.terrain()->total_quanta() + w.terrain()->ledger().off_site_total() : 0;
  }
  void start(const engine::World& w) { quanta = books(w); }
  void step(engine::World& w, const vehicle::LoaderControls& c) {
    w.step(c);
    ASSERT_TRUE(w.events().finite) << "at " << w.time_s() << " s";
    ASSERT_EQ(books(w), quanta) << "material at " << w.time_s() << " s";
    const vehicle::Loader& l = w.loader();
    for (const vehicle::Wheel& wheel : l.description().wheels) {
      const double hub_z = (l.link_pose(0) * wheel.hub_m).z();
      lowest_hub_above_base_m = std::min(lowest_hub_above_base_m, hub_z - base_m);
    }
  }
  void run(engine::World& w, const vehicle::LoaderControls& c, double seconds) {
    const long n = std::lround(seconds / engine::kStepSeconds);
    for (long k = 0; k < n && !::testing::Test::HasFatalFailure(); ++k) step(w, c);
  }
  // Braked for `settle_s`, then still over a second: moves < 1 mm, < 5 mm/s.
  void expect_at_rest(engine::World& w, double settle_s = 2.0) {
    run(w, braked(), settle_s);
    const Eigen::Vector3d before = w.loader().link_pose(0).translation();
    double fastest = 0.0;
    for (int k = 0; k < 500 && !::testing::Test::HasFatalFailure(); ++k) {
      step(w, braked());
      fastest = std::max(fastest, w.loader().chassis_velocity().norm());
    }
    EXPECT_LT((w.loader().link_pose(0).translation() - before).norm(), 1e-3) << "jitter at rest";
    EXPECT_LT(fastest, 5e-3) << "jitter at rest";
    std::printf("[ measured ] at rest: %.3f mm in the last second, %.2f mm/s at most\n",
                (w.loader().link_pose(0).translation() - before).norm() * 1e3, fastest * 1e3);
  }
  // Nothing through the base: a hub stays over its rim's radius above it
  // (the tyre may deflect all the way to the rim: a 16.5 in rim in a
  // 0.41 m tyre, half its radius).
  void expect_above_base(double tyre_radius_m) const {
    EXPECT_GT(lowest_hub_above_base_m, 0.5 * tyre_radius_m) << "a wheel went into the hard base";
  }
};

double energy_J(const engine::World& w) {  // the chassis's share: m g z + 1/2 m v^2
  const double m = w.loader().description().total_mass_kg();
  const double v = w.loader().chassis_velocity().norm();
  return m * kGravity_m_s2 * w.loader().link_pose(0).translation().z() + 0.5 * m * v * v;
}

// A column of sand 2 m tall on one 5 cm cell collapses into a cone: the
// books hold, the flank ends at the repose angle, the terrain comes to rest.
TEST(Stability, TallThinColumnCollapses) {
  for (const double cells_per_m : {20.0, 40.0, 100.0}) {  // 1 cm cells: the flow step must sub-step
    auto grid = engine::flat_soil_grid(sand().flow, cells_per_m, {0.0, 0.0}, 4.0, 4.0, 0.0);
    const int c = grid->nx() / 2;
    grid->set_material_m(c, c, 2.0);
    const std::int64_t total = grid->total_quanta();
    int steps = 0;
    while (!grid->at_rest() && steps < 100000) {
      grid->step();
      ++steps;
    }
    EXPECT_TRUE(grid->at_rest()) << cells_per_m;
    EXPECT_EQ(grid->total_quanta() + grid->ledger().off_site_total(), total);
    double steepest = 0.0;
    for (int j = 1; j + 1 < grid->ny(); ++j)
      for (int i = 1; i + 1 < grid->nx(); ++i)
        steepest = std::max(steepest, (grid->surface_m(i, j) - grid->surface_m(i + 1, j)) * cells_per_m);
    const double steepest_deg = std::atan(steepest) * 180.0 / kPi;
    std::printf("[ measured ] 2 m column at %.0f cells/m: at rest after %.2f s, steepest %.1f deg (alpha %.0f)\n", cells_per_m,
                steps * engine::kStepSeconds, steepest_deg, sand().flow.repose_angle_deg);
    EXPECT_LT(steepest_deg, sand().flow.repose_angle_deg + 3.0);
  }
}

// Standing braked on a 20 degree slope: no creep, no jitter.
// The same column in the second ground model (Li & Moshell's slippage,
// dry sand: c = 0, phi = the repose angle), down to 1 cm cells. Its wedge
// speeds are capped and sub-stepped to the Courant bound, so nothing may
// overshoot: the surface never rises above the column's top.
TEST(Stability, TallThinColumnCollapsesInTheSlippageModel) {
  for (const double cells_per_m : {20.0, 50.0, 100.0}) {
    terrain::SoilFlowParameters soil = sand().flow;
    soil.model = terrain::GroundModel::kSlippage;
    auto grid = engine::flat_soil_grid(soil, cells_per_m, {0.0, 0.0}, 3.0, 3.0, 0.0);
    const int c = grid->nx() / 2;
    grid->set_material_m(c, c, 2.0);
    const std::int64_t total = grid->total_quanta();
    double highest = 2.0;
    int steps = 0;
    while (!grid->at_rest() && steps < 60000) {
      grid->step();
      ++steps;
      for (int j = 0; j < grid->ny(); ++j)  // every step, everywhere: no overshoot ever
        for (int i = 0; i < grid->nx(); ++i) highest = std::max(highest, grid->surface_m(i, j));
    }
    EXPECT_TRUE(grid->at_rest()) << cells_per_m;
    EXPECT_EQ(grid->total_quanta() + grid->ledger().off_site_total(), total);
    EXPECT_TRUE(grid->ledger().balanced());
    EXPECT_LE(highest, 2.0);
    double steepest = 0.0;
    for (int j = 0; j < grid->ny(); ++j)
      for (int i = 0; i < grid->nx(); ++i) {
        EXPECT_TRUE(std::isfinite(grid->surface_m(i, j)));
        steepest = std::max(steepest, grid->downhill_slope_tan(i, j));
      }
    const double steepest_deg = std::atan(steepest) * 180.0 / kPi;
    std::printf("[ measured ] 2 m column, slippage model, %.0f cells/m: at rest after %.2f s, steepest %.2f deg (phi %.0f)\n",
                cells_per_m, steps * engine::kStepSeconds, steepest_deg, soil.slip_friction_deg());
    EXPECT_LE(steepest_deg, soil.slip_friction_deg() + 0.1);
  }
}

TEST(Stability, BrakedOnATwentyDegreeSlope) {
  auto w = loader_on_ground(20.0 * kPi / 180.0);
  const Eigen::Vector3d start = w->loader().link_pose(0).translation();
  const double e0 = energy_J(*w);
  Watch watch;
  watch.start(*w);
  watch.run(*w, braked(), 5.0);
  watch.expect_at_rest(*w);
  const double crept = (w->loader().link_pose(0).translation() - start).norm();
  std::printf("[ measured ] braked on 20 deg: crept %.2f mm in 8 s\n", crept * 1e3);
  EXPECT_LT(crept, 0.01);
  EXPECT_LE(energy_J(*w), e0 + 1.0) << "no energy from nowhere";
}

// The arm at full height, then the lift lever slammed down at full speed:
// the bucket hits the ground; the machine stays whole and on the ground.
TEST(Stability, BucketSlammedIntoTheGround) {
  auto w = loader_on_ground(0.0, 0.0, 1.3, 0.0);
  Watch watch;
  watch.start(*w);
  vehicle::LoaderControls slam;
  slam.lift = -1.0;
  slam.throttle = 1.0;
  slam.parking_brake = true;
  watch.run(*w, slam, 4.0);
  watch.expect_at_rest(*w);
  watch.expect_above_base(shipped_loader().tyre.radius_m);
  EXPECT_GT(w->loader().link_pose(0).translation().z(), 0.0);
}

// Dropped from 5 m (about 10 m/s at impact) onto firm ground: it lands,
// comes to rest, and holds no more energy than it started with.
TEST(Stability, DroppedFromFiveMetres) {
  for (const bool onto_sand : {false, true}) {  // a body hitting soil at 10 m/s, too
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() = Eigen::Vector3d(0, 0, 5.0 + shipped_loader().tyre.radius_m);
    engine::World w(shipped_loader(), engine::FirmGround{}, pose, 0.2, 0.0);
    if (onto_sand) w.add_soil_site(engine::flat_soil_grid(sand().flow, 10.0, {-4.0, -4.0}, 8.0, 8.0, 0.3), sand().terramechanics);
    const double e0 = energy_J(w);
    Watch watch;
    watch.start(w);
    watch.run(w, braked(), 4.0);
    watch.expect_at_rest(w, onto_sand ? 5.0 : 2.0);
    watch.expect_above_base(shipped_loader().tyre.radius_m);
    std::printf("[ measured ] dropped 5 m onto %s: energy %.0f kJ before, %.0f kJ at rest, lowest hub %.3f m over the base\n",
                onto_sand ? "0.3 m of sand" : "firm ground", e0 / 1e3, energy_J(w) / 1e3, watch.lowest_hub_above_base_m);
    EXPECT_LT(energy_J(w), e0);
  }
}

// A load past the tipping load on the bucket, the arm raised: the machine
// tips forward, the event is raised, nothing blows up; lowered again, it
// comes to rest.
TEST(Stability, LiftingPastTheTippingLoad) {
  auto w = loader_on_ground(0.0, 0.0, 0.2, 0.3);
  const int bucket = static_cast<int>(w->loader().description().links.size()) - 1;
  w->set_link_load(bucket, Eigen::Vector3d(0, 0, -kGravity_m_s2 * 2500.0), Eigen::Vector3d(0.4, 0.0, 0.0));  // 2.5 t: tipping load 1.36 t
  Watch watch;
  watch.start(*w);
  vehicle::LoaderControls raise;
  raise.lift = 1.0;
  raise.throttle = 1.0;
  raise.parking_brake = true;
  watch.run(*w, raise, 5.0);
  EXPECT_GT(w->events().rear_wheels_unloaded_s, 0.0) << "tipping detected";
  std::printf("[ measured ] 2.5 t on the bucket: rear wheels unloaded at %.2f s of raising\n", w->events().rear_wheels_unloaded_s - 1.0);
  vehicle::LoaderControls lower = raise;
  lower.lift = -1.0;
  watch.run(*w, lower, 5.0);
  watch.expect_at_rest(*w, 3.0);
}

// Sand heaped a metre deep in the bucket, far over its capacity: it spills,
// the books hold, everything comes to rest.
TEST(Stability, OverfilledBucket) {
  auto w = loader_on_ground(0.0, 0.0, 0.6, 0.2);
  w->enable_material(sand().flow, 0.05);
  terrain::GranularGrid& g = w->bucket_material()->grid();
  for (int j = 0; j < g.ny(); ++j)
    for (int i = 0; i < g.nx(); ++i) g.set_material_m(i, j, 1.0);
  const double loaded = w->bucket_material()->material_mass_kg();
  Watch watch;
  watch.start(*w);
  watch.run(*w, braked(), 6.0);
  const double kept = w->bucket_material()->material_mass_kg();
  std::printf("[ measured ] %.0f kg heaped in the bucket: %.0f kg stay, the rest spilt\n", loaded, kept);
  EXPECT_LT(kept, 0.8 * loaded);
  EXPECT_TRUE(w->material()->parcels().empty()) << "all landed";
  watch.expect_at_rest(*w);
}

// A full-speed pivot turn on soft sand for 5 s, then braked: the books
// hold, no wheel goes through the hard base, it comes to rest.
TEST(Stability, FullSpeedPivotTurnOnSoftSand) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(0, 0, 0.1 + shipped_loader().tyre.radius_m);
  engine::World w(shipped_loader(), engine::FirmGround{}, pose, 0.2, 0.0);
  w.add_soil_site(engine::flat_soil_grid(sand().flow, 10.0, {-4.0, -4.0}, 8.0, 8.0, 0.1), sand().terramechanics);
  Watch watch;
  watch.start(w);
  watch.run(w, braked(), 1.0);
  vehicle::LoaderControls pivot;
  pivot.drive_left = 1.0;
  pivot.drive_right = -1.0;
  pivot.throttle = 1.0;
  watch.run(w, pivot, 5.0);
  const double yaw_rate = std::abs(w.loader().link_pose(0).linear().col(0).y());
  watch.expect_at_rest(w, 5.0);  // sand under braked wheels settles for a while
  watch.expect_above_base(shipped_loader().tyre.radius_m);
  std::printf("[ measured ] pivot on sand: lowest hub %.3f m over the base, heading's y %.2f\n", watch.lowest_hub_above_base_m, yaw_rate);
}

// Driven off a 1 m ledge onto soft sand: lands, stays whole and above the
// base, books hold, comes to rest.
TEST(Stability, DrivenOffAOneMetreLedgeOntoSoftSand) {
  engine::FirmGround ground;
  engine::StaticBox ledge;
  ledge.pose.translation() = Eigen::Vector3d(-3.0, 0.0, 0.5);
  ledge.half_extents_m = Eigen::Vector3d(3.0, 3.0, 0.5);  // top at 1 m, edge at x = 0
  ground.boxes.push_back(ledge);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(-2.0, 0.0, 1.0 + shipped_loader().tyre.radius_m);
  engine::World w(shipped_loader(), ground, pose, 0.3, 0.0);
  w.add_soil_site(engine::flat_soil_grid(sand().flow, 10.0, {0.2, -3.0}, 6.0, 6.0, 0.2), sand().terramechanics);
  Watch watch;
  watch.start(w);
  watch.run(w, braked(), 1.0);
  vehicle::LoaderControls ahead;
  ahead.drive_left = ahead.drive_right = 0.6;
  ahead.throttle = 1.0;
  watch.run(w, ahead, 4.0);
  EXPECT_GT(w.loader().link_pose(0).translation().x(), 1.0) << "it went over the edge";
  EXPECT_LT(w.loader().link_pose(0).translation().z(), 1.0) << "and came down";
  // Braked from driving on the sand: it pitches onto its ruts and settles
  // (the motion falls by e every 0.3 s), then stands.
  watch.expect_at_rest(w, 3.0);
  watch.expect_above_base(shipped_loader().tyre.radius_m);
}

// Sand in a closed box (walls all round, taller than the load), the box
// standing still: nothing leaves, it settles and stays settled.
TEST(Stability, MaterialInAClosedContainer) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(0, 0, shipped_loader().tyre.radius_m - 0.01);
  engine::World w(shipped_loader(), engine::FirmGround{}, pose, 0.2, 0.0);
  w.enable_material(sand().flow, 0.05);
  engine::TraySpec box;
  box.shape.length_m = 2.0;
  box.shape.width_m = 1.5;
  box.shape.back_height_m = box.shape.side_height_back_m = box.shape.side_height_front_m = box.shape.front_height_m = 1.0;
  box.shape.heel_radius_m = 0.0;
  box.pose.translation() = Eigen::Vector3d(5.0, -0.75, 0.5);
  const int k = w.add_tray(box);
  terrain::GranularGrid& g = w.tray(k).grid();
  g.set_material_m(g.nx() / 2, g.ny() / 2, 0.9);  // a column in the middle
  const double kg = w.tray(k).material_mass_kg();
  Watch watch;
  watch.start(w);
  watch.run(w, braked(), 6.0);
  EXPECT_DOUBLE_EQ(w.tray(k).material_mass_kg(), kg) << "nothing left the box";
  EXPECT_TRUE(g.at_rest());
  EXPECT_TRUE(w.material()->parcels().empty());
}

}  // namespace
}  // namespace skidsim::testing
