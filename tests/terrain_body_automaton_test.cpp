// Automata fixed to moving bodies (thesis 6.1-6.3): world slopes on a tilted
// base, spilling past the repose angle, parcels that fall for the time their
// height takes, exchange between automata and the ground, exact books.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "common/physical_constants.h"
#include "body_automaton_support.h"
#include "terrain/body_automaton.h"
#include "terrain/material_exchange.h"
#include "test_support.h"

namespace skidsim::terrain {
namespace {

using testing::kDt;

constexpr double kDeg = kPi / 180.0;

ContainerShape flat_plate(double size_m) {
  ContainerShape s;
  s.length_m = s.width_m = size_m;
  s.back_height_m = s.side_height_back_m = s.side_height_front_m = s.front_height_m = s.heel_radius_m = 0.0;
  return s;
}

GranularGrid make_ground(double cell_m, double size_m, double depth_m) {
  GridSpec spec;
  spec.cell_size_m = cell_m;
  spec.nx = spec.ny = static_cast<int>(std::lround(size_m / cell_m));
  spec.origin_m = Eigen::Vector2d::Constant(-0.5 * size_m + 0.5 * cell_m);
  GranularGrid g(spec, SoilFlowParameters{}, kDt);
  for (int j = 0; j < spec.ny; ++j)
    for (int i = 0; i < spec.nx; ++i) g.set_material_m(i, j, depth_m);
  return g;
}

class BodyCellSizes : public ::testing::TestWithParam<double> {};

// (6.2) On a base tilted by theta a level layer has the world slope theta:
// the automaton's slope measure says tan(theta), whatever the cell size.
TEST_P(BodyCellSizes, TiltedLayerHasTheWorldSlope) {
  const double d = GetParam();
  BodyAutomaton a(flat_plate(1.0), SoilFlowParameters{}, d, kDt);
  testing::fill_to(a, 0.05);
  for (double tilt_deg : {5.0, 20.0, 40.0}) {
    testing::pose_about_front(a, Eigen::Vector3d(0, 0, 1), tilt_deg * kDeg);
    const int mid = a.grid().nx() / 2;
    EXPECT_NEAR(a.grid().downhill_slope_tan(mid, a.grid().ny() / 2), std::tan(tilt_deg * kDeg), 1e-9) << tilt_deg;
  }
  // Tilted sideways as well: the steepest world slope of the plane.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = (Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()) * Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()))
                      .toRotationMatrix();
  a.set_pose(pose, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  const Eigen::Vector3d normal = pose.linear().col(2);
  const double expected = std::sqrt(1.0 - normal.z() * normal.z()) / normal.z();
  EXPECT_NEAR(a.grid().downhill_slope_tan(a.grid().nx() / 2, a.grid().ny() / 2), expected, 1e-9);
}

// A layer on a plate with open edges, held at 20 deg (10 deg under alpha_I),
// stays: only its downhill end slumps, to a taper whose world slope is
// alpha_I (locally 10 deg: about 0.5 h / tan(10 deg) = 14 % of a 5 cm layer
// on 1 m). Held at alpha + 3 deg it slides off the low edge and lands on
// firm ground, every quantum accounted for.
TEST_P(BodyCellSizes, LayerSpillsOnlyPastTheReposeAngle) {
  const double d = GetParam();
  const SoilFlowParameters soil;
  for (double offset_deg : {-10.0, 3.0}) {
    BodyAutomaton a(flat_plate(1.0), soil, d, kDt);
    testing::fill_to(a, 0.05);
    // Let the open rim erode level first.
    testing::pose_about_front(a, Eigen::Vector3d(0, 0, 0.5), 0.0);
    MaterialExchange ex(nullptr, kDt);
    ex.add_body(&a);
    const std::int64_t total = ex.total_quanta();
    for (int s = 0; s < 1500; ++s) {
      a.grid().step();
      ex.step();
    }
    const std::int64_t level = a.grid().total_quanta();
    const double tilt_deg = offset_deg < 0.0 ? soil.stop_angle_deg + offset_deg : soil.repose_angle_deg + offset_deg;
    testing::pose_about_front(a, Eigen::Vector3d(0, 0, 0.5), tilt_deg * kDeg);
    for (int s = 0; s < 2500; ++s) {
      a.grid().step();
      ex.step();
      ASSERT_EQ(ex.total_quanta(), total);
    }
    const double kept = static_cast<double>(a.grid().total_quanta()) / static_cast<double>(level);
    std::printf("[ measured ] d = %.3f, held at %.0f deg: kept %.1f %%\n", d, tilt_deg, 100.0 * kept);
    if (offset_deg < 0.0) {
      EXPECT_GT(kept, 0.75) << "below the stop angle the layer must stay, d = " << d;
      EXPECT_LT(kept, 0.95) << "its downhill end must slump to alpha_I in the world, d = " << d;
    } else {
      EXPECT_LT(kept, 0.2) << "past the repose angle the layer must slide off, d = " << d;
      EXPECT_GT(ex.on_firm_ground_quanta(), 0);
    }
    EXPECT_TRUE(a.grid().ledger().balanced());
  }
}

// Material leaves an edge as a parcel and lands after the time its height
// takes, sqrt(2 h / g), not at once.
TEST(BodyAutomaton, SpilledMaterialFallsForItsHeight) {
  const double d = 0.05, height = 1.8;
  BodyAutomaton a(flat_plate(0.5), SoilFlowParameters{}, d, kDt);
  GranularGrid ground = make_ground(d, 4.0, 0.0);
  MaterialExchange ex(&ground, kDt);
  ex.add_body(&a);
  testing::pose_about_front(a, Eigen::Vector3d(0, 0, height), 0.0);
  a.grid().set_material_m(a.grid().nx() - 1, 5, 0.2);  // a heap on the front edge: it falls at once
  const std::int64_t total = ex.total_quanta();
  double first_spawn = -1.0, first_landing = -1.0;
  for (int s = 1; s <= 1000 && first_landing < 0.0; ++s) {
    a.grid().step();
    ground.step();
    ex.step();
    ASSERT_EQ(ex.total_quanta(), total);
    if (first_spawn < 0.0 && ex.stats().parcels_spawned > 0) first_spawn = s * kDt;
    if (ex.stats().parcels_landed > 0) first_landing = s * kDt;
  }
  ASSERT_GT(first_spawn, 0.0);
  ASSERT_GT(first_landing, 0.0);
  const double expected = std::sqrt(2.0 * height / kGravity_m_s2);
  EXPECT_NEAR(first_landing - first_spawn, expected, 3 * kDt);
}

// A bucket-shaped container dumped from 1.2 m over bare ground: the load
// leaves over the lip, lands, and forms a pile whose flanks stand at the
// repose angle; every quantum is accounted for at every step.
TEST_P(BodyCellSizes, DumpedLoadFormsAPileAtTheReposeAngle) {
  const double d = GetParam();
  const SoilFlowParameters soil;
  BodyAutomaton bucket(ContainerShape{}, soil, d, kDt);
  GranularGrid ground = make_ground(d, 4.0, 0.0);
  MaterialExchange ex(&ground, kDt);
  ex.add_body(&bucket);
  const Eigen::Vector3d lip(0.0, 0.0, 1.2);
  testing::pose_about_front(bucket, lip, -0.3);  // rolled back, carrying
  testing::fill_to(bucket, 0.35);  // over-full: the heap beyond the rims runs off
  for (int s = 0; s < 20000 && !(s > 1000 && ex.parcels().empty() && bucket.grid().at_rest()); ++s) {
    bucket.grid().step();
    ground.step();
    ex.step();
  }
  ASSERT_TRUE(ex.parcels().empty());
  const std::int64_t load = bucket.grid().total_quanta();
  ASSERT_GT(load * ex.quantum_mass_kg(), 300.0) << "the bucket must carry a real load";
  // Carried rolled back for 2 s (travelling at 2 m/s: the parcels would
  // carry that speed; the automaton has no inertia): it keeps its load.
  const std::int64_t spawned = ex.stats().parcels_spawned;
  for (int s = 0; s < 1000; ++s) {
    testing::pose_about_front(bucket, lip, -0.3, 0.0, Eigen::Vector3d(2.0, 0, 0));
    bucket.grid().step();
    ex.step();
  }
  EXPECT_EQ(ex.stats().parcels_spawned, spawned) << "rolled back, the bucket must keep its load";
  EXPECT_EQ(bucket.grid().total_quanta(), load);
  const std::int64_t total = ex.total_quanta();
  const std::int64_t ground_before = ground.total_quanta();
  // Dump: the bucket turns nose-down at 0.8 rad/s to 60 deg and holds
  // there 2 s (the avalanches empty it, long before shedding at 85 deg
  // would), then on to 100 deg.
  double pitch = -0.3;
  for (int s = 0; s < 6000; ++s) {
    if (s == 2500) {
      EXPECT_LT(bucket.grid().total_quanta(), load / 20) << "held at 60 deg the load must slide out";
      EXPECT_EQ(ex.stats().quanta_shed, 0);
    }
    const double rate = (pitch < 60.0 * kDeg || (s > 2500 && pitch < 100.0 * kDeg)) ? 0.8 : 0.0;
    pitch += rate * kDt;
    testing::pose_about_front(bucket, lip, pitch, rate);
    bucket.grid().step();
    ground.step();
    ex.step();
    ASSERT_EQ(ex.total_quanta(), total) << "step " << s;
  }
  EXPECT_TRUE(ex.parcels().empty());
  EXPECT_EQ(bucket.grid().total_quanta(), 0) << "tipped past the vertical the bucket must be empty";
  EXPECT_EQ(ground.total_quanta() - ground_before, load);
  EXPECT_TRUE(ground.ledger().balanced());
  for (int s = 0; s < 20000 && !ground.at_rest(); ++s) ground.step();
  ASSERT_TRUE(ground.at_rest());
  double peak = 0.0;
  for (int j = 0; j < ground.ny(); ++j)
    for (int i = 0; i < ground.nx(); ++i) peak = std::max(peak, ground.material_m(i, j));
  EXPECT_GT(peak, 0.15) << "the load must form a pile, not a film";
  const double max_slope_deg = testing::max_slope_deg(ground);
  EXPECT_LE(max_slope_deg, soil.repose_angle_deg + testing::kRestSlopeToleranceDeg);
  const double flank_deg = testing::median_flank_slope_deg(ground);
  EXPECT_GE(flank_deg, soil.stop_angle_deg - 4.0) << "the flanks must stand near the repose angle";
  std::printf("[ measured ] d = %.3f: dumped pile's flank (median) %.1f deg, steepest %.1f deg, peak %.2f m\n", d,
              flank_deg, max_slope_deg, peak);
}

// A truck bed under a dumping bucket holds the load; overfilled, it spills
// over its sides onto the ground.
TEST(BodyAutomaton, TruckBedHoldsThenSpillsOverItsSides) {
  const double d = 0.05;
  const SoilFlowParameters soil;
  ContainerShape bed_shape;
  bed_shape.length_m = 1.2;
  bed_shape.width_m = 2.0;
  bed_shape.back_height_m = bed_shape.side_height_back_m = bed_shape.side_height_front_m = bed_shape.front_height_m = 0.25;
  bed_shape.heel_radius_m = 0.0;
  BodyAutomaton bed(bed_shape, soil, d, kDt);
  BodyAutomaton bucket(ContainerShape{}, soil, d, kDt);
  GranularGrid ground = make_ground(d, 5.0, 0.0);
  MaterialExchange ex(&ground, kDt);
  ex.add_body(&bed);
  ex.add_body(&bucket);
  Eigen::Isometry3d bed_pose = Eigen::Isometry3d::Identity();
  bed_pose.translation() = Eigen::Vector3d(-0.6, -1.0, 1.0);  // floor 1 m up, centred on the origin
  bed.set_pose(bed_pose, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  const Eigen::Vector3d lip(0.25, 0.0, 2.2);
  const double capacity_m3 = (1.2 - 2 * d) * (2.0 - 2 * d) * 0.25;
  const std::int64_t bed_capacity = static_cast<std::int64_t>(capacity_m3 / ground.quantum_volume_m3());
  std::int64_t total = ex.total_quanta();
  for (int load = 0; load < 4; ++load) {
    testing::pose_about_front(bucket, lip, -0.3);
    testing::fill_to(bucket, 0.3);
    total = ex.total_quanta();
    double pitch = -0.3;
    for (int s = 0; s < 3000; ++s) {
      const double rate = pitch < 100.0 * kDeg ? 1.0 : 0.0;
      pitch += rate * kDt;
      testing::pose_about_front(bucket, lip, pitch, rate);
      bucket.grid().step();
      bed.grid().step();
      ground.step();
      ex.step();
      ASSERT_EQ(ex.total_quanta(), total);
    }
    for (int s = 0; s < 5000 && !(bed.grid().at_rest() && ex.parcels().empty()); ++s) {
      bed.grid().step();
      ground.step();
      ex.step();
    }
    const std::int64_t in_bed = bed.grid().total_quanta();
    if (load == 0) {
      EXPECT_EQ(ground.total_quanta(), 0) << "one bucket load must stay in the bed";
      EXPECT_GT(in_bed, 0);
    }
    EXPECT_LE(in_bed, bed_capacity * 2) << "the bed holds its struck load and a heap, no more";
  }
  EXPECT_GT(ground.total_quanta(), 0) << "overfilled, the bed must spill onto the ground";
  // Over its walls: what lies on the ground left the bed over its edges
  // (the bucket's own spills all landed in the bed, first load above).
  EXPECT_GE(bed.grid().ledger().exported, ground.total_quanta()) << "the spill must come over the bed's walls";
  EXPECT_GT(bed.grid().total_quanta(), bed_capacity * 3 / 4) << "overfilled, the bed must be nearly full";
  EXPECT_TRUE(bed.grid().ledger().balanced());
  EXPECT_TRUE(ground.ledger().balanced());
}

// A parcel that finds the list full lands straight below at once: on a
// tray under it, not through it (review: it had skipped every body).
TEST(BodyAutomaton, ParcelsLandedAtOnceStillFindTheTrayBelow) {
  const double d = 0.05;
  BodyAutomaton plate(flat_plate(0.5), SoilFlowParameters{}, d, kDt);
  ContainerShape tray_shape = flat_plate(2.0);
  tray_shape.back_height_m = tray_shape.side_height_back_m = tray_shape.side_height_front_m =
      tray_shape.front_height_m = 0.3;
  BodyAutomaton tray(tray_shape, SoilFlowParameters{}, d, kDt);
  MaterialExchange ex(nullptr, kDt, 1);  // room for one parcel
  ex.add_body(&plate);
  ex.add_body(&tray);
  Eigen::Isometry3d tray_pose = Eigen::Isometry3d::Identity();
  tray_pose.translation() = Eigen::Vector3d(-1.0, -1.0, 0.5);
  tray.set_pose(tray_pose, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  testing::fill_to(plate, 0.05);
  const std::int64_t total = ex.total_quanta();
  // Tipped past the vertical over the tray: it sheds all it holds at once.
  testing::pose_about_front(plate, Eigen::Vector3d(0.25, 0, 1.5), 1.7);
  for (int s = 0; s < 500; ++s) {
    plate.grid().step();
    tray.grid().step();
    ex.step();
    ASSERT_EQ(ex.total_quanta(), total);
  }
  EXPECT_GT(ex.stats().parcels_forced, 0) << "the test must fill the parcel list";
  EXPECT_EQ(ex.stats().parcels_in_flight_peak, 1) << "the list never holds more than its room";
  EXPECT_EQ(ex.on_firm_ground_quanta(), 0);
  EXPECT_EQ(tray.grid().total_quanta() + ex.in_flight_quanta(), total);
}

// (6.3.3) Soil heaped against a low container's edge above its base flows
// in: the ground cell takes the border cell as its neighbour.
TEST(BodyAutomaton, GroundHigherThanTheRimFlowsIn) {
  const double d = 0.05;
  ContainerShape tray = flat_plate(1.0);
  BodyAutomaton a(tray, SoilFlowParameters{}, d, kDt);
  GranularGrid ground = make_ground(d, 3.0, 0.0);
  // A heap just beyond the tray's +x edge, higher than the tray's floor.
  for (int j = 25; j < 35; ++j)
    for (int i = 30; i < 34; ++i) ground.set_material_m(i, j, 0.5);
  MaterialExchange ex(&ground, kDt);
  ex.add_body(&a);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(-1.0, -0.5, 0.1);  // +x edge at x = 0, floor 10 cm up
  a.set_pose(pose, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  const std::int64_t total = ex.total_quanta();
  for (int s = 0; s < 3000; ++s) {
    ground.step();
    a.grid().step();
    ex.step();
    ASSERT_EQ(ex.total_quanta(), total);
  }
  EXPECT_GT(ex.stats().quanta_over_lip, 0);
  EXPECT_GT(a.grid().total_quanta(), 0) << "soil above the rim must flow into the tray";
}

INSTANTIATE_TEST_SUITE_P(TwoCellSizes, BodyCellSizes, ::testing::Values(0.05, 0.025));

}  // namespace
}  // namespace skidsim::terrain
