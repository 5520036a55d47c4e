// The loader on dry sand: wheel sinkage and drawbar pull against the
// Wong-Reece wheel (its closed form), the hard cases (a 1 m drop onto sand, a
// full-speed pivot turn on sand), and standing still on a sand slope and
// across the edge of firm ground.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "common/physical_constants.h"
#include "engine/soil_site.h"
#include "io/soil_table.h"
#include "tests/loader_support.h"
#include "experiments/wong_reece_closed_form.h"

namespace skidsim::testing {
namespace {

constexpr double kSandDepth = 0.5;  // m of sand over the hard base at z = 0

struct SandSite {
  io::SoilRecord soil = io::load_soil_table(io::default_soil_table_path()).at("dry_sand");
  double cells_per_m = 20.0;
  double length_m = 16.0, width_m = 4.0;
  Eigen::Vector2d origin_m{-3.0, -2.0};
};

// The loader on a sand site, its wheels resting on the surface (the plane of
// the firm ground is the site's hard base).
std::unique_ptr<engine::World> loader_on_sand(const SandSite& site, Eigen::Vector3d chassis_at = {0, 0, 0},
                                              engine::FirmGround ground = {}) {
  auto grid = engine::flat_soil_grid(site.soil.flow, site.cells_per_m, site.origin_m, site.length_m, site.width_m,
                                     kSandDepth);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = chassis_at + Eigen::Vector3d(0, 0, kSandDepth + shipped_loader().tyre.radius_m);
  auto w = std::make_unique<engine::World>(shipped_loader(), ground, pose, 0.2, 0.0);
  w->add_soil_site(std::move(grid), site.soil.terramechanics);
  return w;
}

struct AxleFigures {
  double load_N = 0.0, slip = 0.0, sinkage_m = 0.0, pull_N = 0.0;  // per wheel, means
};

// Drives slowly (levers at `lever`) for 6 s to leave the hole it stood in,
// then averages each axle's load, slip, sinkage below the untouched surface
// and pull for 10 s. A hitch pull of `hitch_pull_N` holds it back.
std::array<AxleFigures, 2> rolling_axles(const SandSite& site, double lever, double hitch_pull_N = 0.0) {
  auto w = loader_on_sand(site);
  vehicle::LoaderControls c;
  c.drive_left = c.drive_right = lever;
  const Eigen::Vector3d hitch(-1.35, 0.0, 0.0);
  const auto step = [&] {
    const Eigen::Isometry3d chassis = w->loader().link_pose(0);
    w->loader().add_force(0, -hitch_pull_N * chassis.linear().col(0), chassis * hitch);
    w->step(c);
  };
  for (int s = 0; s < 3000; ++s) step();
  const auto& d = shipped_loader();
  std::array<AxleFigures, 2> out{};
  long n = 0;
  for (int s = 0; s < 5000; ++s, ++n) {
    step();
    for (size_t k = 0; k < d.wheels.size(); ++k) {
      AxleFigures& a = out[d.wheels[k].hub_m.x() > 0.0 ? 0 : 1];
      const vehicle::WheelState& ws = w->loader().wheels()[k];
      a.load_N += ws.normal_load_N;
      a.slip += ws.slip_ratio;
      a.sinkage_m += kSandDepth - (w->loader().wheel_hub(static_cast<int>(k)).z() - d.tyre.radius_m);
      a.pull_N += ws.longitudinal_force_N;
    }
  }
  EXPECT_TRUE(w->events().finite);
  for (AxleFigures& a : out) {
    a.load_N /= 2.0 * n;  // two wheels an axle
    a.slip /= 2.0 * n;
    a.sinkage_m /= 2.0 * n;
    a.pull_N /= 2.0 * n;
  }
  return out;
}

// The front wheels roll on untouched sand: their sinkage and pull are the
// Wong-Reece wheel's at their own load and slip (the closed form,
// experiments/wong_reece_closed_form.h), at two cell sizes, within 10 % (the pull
// within 10 % of the load's traction scale, W tan(phi): at small slip it
// is a difference of two large terms). The rear wheels run in the front
// wheels' ruts.
TEST(LoaderSoftSoil, WheelsOnSandFollowWongReece) {
  const auto& d = shipped_loader();
  for (const double cells_per_m : {10.0, 20.0}) {
    SandSite site;
    site.cells_per_m = cells_per_m;
    const closed_form::WongReeceSoil ref = closed_form::reference_soil_of(site.soil.terramechanics);
    const std::array<AxleFigures, 2> axles = rolling_axles(site, 0.15);
    const AxleFigures& front = axles[0];
    const double z_ref = closed_form::wong_reece_reference_sinkage(ref, d.tyre.radius_m, d.tyre.width_m, front.load_N, front.slip);
    const closed_form::WongReeceResult f_ref =
        closed_form::wong_reece_reference(ref, d.tyre.radius_m, d.tyre.width_m, z_ref, front.slip);
    std::printf("%2.0f cells/m: front %.0f N at slip %.3f: sinkage %.4f m (Wong-Reece %.4f), pull %+.0f N (%+.0f); "
                "rear %.0f N at slip %.3f: sinkage %.4f m, pull %+.0f N\n",
                cells_per_m, front.load_N, front.slip, front.sinkage_m, z_ref, front.pull_N, f_ref.DP,
                axles[1].load_N, axles[1].slip, axles[1].sinkage_m, axles[1].pull_N);
    std::printf("   rear on untouched sand would sink %.4f m\n",
                closed_form::wong_reece_reference_sinkage(ref, d.tyre.radius_m, d.tyre.width_m, axles[1].load_N, axles[1].slip));
    RecordProperty("front_sinkage_over_wong_reece_" + std::to_string(static_cast<int>(cells_per_m)),
                   std::to_string(front.sinkage_m / z_ref));
    EXPECT_NEAR(front.sinkage_m, z_ref, 0.10 * z_ref) << cells_per_m << " cells/m";
    EXPECT_NEAR(front.pull_N, f_ref.DP, 0.10 * front.load_N * std::tan(ref.phi_rad)) << cells_per_m << " cells/m";
    // The rear wheels (three times the front's load on the empty machine)
    // press the rut past its depth: beyond the front's peak the soil is on
    // its loading curve again, so they sink about as deep as on untouched
    // sand (Wong's multi-pass), a little less for the reloaded top.
    const AxleFigures& rear = axles[1];
    const double z_rear = closed_form::wong_reece_reference_sinkage(ref, d.tyre.radius_m, d.tyre.width_m, rear.load_N, rear.slip);
    EXPECT_LT(rear.sinkage_m, 1.02 * z_rear) << cells_per_m << " cells/m";
    EXPECT_GT(rear.sinkage_m, 0.85 * z_rear) << cells_per_m << " cells/m";
  }
}

// Drawbar pull against slip: a horizontal pull on the hitch, levers at 0.3,
// steady state. More pull takes more slip; the front wheels' pull is the
// Wong-Reece wheel's at their load and slip, within 10 % of the traction
// scale W tan(phi).
TEST(LoaderSoftSoil, DrawbarPullAgainstSlipFollowsWongReece) {
  const auto& d = shipped_loader();
  std::vector<std::pair<double, double>> pull_vs_slip;
  for (const double pull_kN : {0.0, 0.7, 1.4, 2.1}) {
    SandSite site;
    site.cells_per_m = 10.0;
    site.length_m = 24.0;
    const closed_form::WongReeceSoil ref = closed_form::reference_soil_of(site.soil.terramechanics);
    const std::array<AxleFigures, 2> axles = rolling_axles(site, 0.3, 1e3 * pull_kN);
    const AxleFigures& front = axles[0];
    const double z_ref = closed_form::wong_reece_reference_sinkage(ref, d.tyre.radius_m, d.tyre.width_m, front.load_N, front.slip);
    const double dp_ref = closed_form::wong_reece_reference(ref, d.tyre.radius_m, d.tyre.width_m, z_ref, front.slip).DP;
    std::printf("hitch %.1f kN: front slip %.3f, load %.0f N, sinkage %.4f m (%.4f), pull %+.0f N (Wong-Reece %+.0f), "
                "rear slip %.3f, pull %+.0f N\n",
                pull_kN, front.slip, front.load_N, front.sinkage_m, z_ref, front.pull_N, dp_ref, axles[1].slip,
                axles[1].pull_N);
    RecordProperty("front_slip_at_" + std::to_string(static_cast<int>(pull_kN * 1000.0)) + "_N", std::to_string(front.slip));
    EXPECT_NEAR(front.pull_N, dp_ref, 0.10 * front.load_N * std::tan(ref.phi_rad)) << pull_kN << " kN";
    pull_vs_slip.emplace_back(front.slip, front.pull_N);
  }
  for (size_t k = 1; k < pull_vs_slip.size(); ++k) {
    EXPECT_GT(pull_vs_slip[k].first, pull_vs_slip[k - 1].first);
    EXPECT_GT(pull_vs_slip[k].second, pull_vs_slip[k - 1].second);
  }
}

// Hard case: driven at full speed off a 1 m ledge onto soft sand.
TEST(LoaderSoftSoil, DrivenOffAOneMetreLedgeOntoSand) {
  SandSite site;
  site.cells_per_m = 10.0;
  site.origin_m = {-6.0, -2.0};
  engine::FirmGround ground;
  engine::StaticBox ledge;  // top 1 m above the sand, ending at x = 0
  ledge.pose.translation() = Eigen::Vector3d(-3.0, 0.0, 0.5 * (kSandDepth + 1.0));
  ledge.half_extents_m = Eigen::Vector3d(3.0, 3.0, 0.5 * (kSandDepth + 1.0));
  ground.boxes.push_back(ledge);
  auto w = loader_on_sand(site, Eigen::Vector3d(-2.5, 0.0, 1.0), ground);
  vehicle::LoaderControls c;
  c.drive_left = c.drive_right = 1.0;
  double lowest_hub = 1e9;
  for (int s = 0; s < 2000; ++s) {
    w->step(c);
    for (int k = 0; k < 4; ++k) lowest_hub = std::min(lowest_hub, w->loader().wheel_hub(k).z());
  }
  EXPECT_TRUE(w->events().finite);
  EXPECT_GT(w->loader().link_pose(0).translation().x(), 2.0);  // off the ledge and on
  EXPECT_LT(w->loader().link_pose(0).translation().z(), kSandDepth + 0.5);  // down on the sand
  // No wheel went through the hard base under the sand.
  EXPECT_GT(lowest_hub, 0.5 * shipped_loader().tyre.radius_m);
  RecordProperty("lowest_hub_m", std::to_string(lowest_hub));
}

// Hard case: a full-speed pivot turn on soft sand.
TEST(LoaderSoftSoil, FullSpeedPivotTurnOnSand) {
  SandSite site;
  site.cells_per_m = 10.0;
  site.origin_m = {-5.0, -5.0};
  site.length_m = site.width_m = 10.0;
  auto w = loader_on_sand(site);
  vehicle::LoaderControls c;
  c.drive_left = 1.0;
  c.drive_right = -1.0;
  double turned = 0.0, lowest_hub = 1e9;
  for (int s = 0; s < 2500; ++s) {
    w->step(c);
    turned += w->loader().chassis_angular_velocity().z() * engine::kStepSeconds;
    for (int k = 0; k < 4; ++k) lowest_hub = std::min(lowest_hub, w->loader().wheel_hub(k).z());
  }
  EXPECT_TRUE(w->events().finite);
  EXPECT_LT(turned, -1.0);  // it turns (clockwise), digging in
  EXPECT_GT(lowest_hub, 0.5 * shipped_loader().tyre.radius_m);
  EXPECT_LT((w->loader().centre_of_mass() - Eigen::Vector3d(-0.2, 0, 0)).head<2>().norm(), 1.5);
  RecordProperty("pivot_turn_rad", std::to_string(turned));
}

}  // namespace
}  // namespace skidsim::testing

namespace skidsim::testing {
namespace {

// The bucket pushed down onto the hard base of a soil site (no sand, or a
// thin layer) behaves as on firm ground without a site: the base is a rigid
// contact, not a stiff explicit spring that would launch the machine. (The
// arm pushing down lifts the machine's front, on either.)
TEST(LoaderSoftSoil, BucketPressedOntoTheSitesHardBaseIsLikeFirmGround) {
  struct Motion {
    double fastest = 0.0, highest = 0.0;
  };
  auto run = [](bool site, double layer_m, double start_lift) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation().z() = shipped_loader().tyre.radius_m - 0.01 + layer_m;
    engine::FirmGround ground;
    ground.has_plane = !site;  // on the site, its base is the only ground
    engine::World w(shipped_loader(), ground, pose, start_lift, start_lift);
    if (site) {
      const io::SoilRecord sand = io::load_soil_table(io::default_soil_table_path()).at("dry_sand");
      w.add_soil_site(engine::flat_soil_grid(sand.flow, 20.0, {-6.0, -4.0}, 12.0, 8.0, layer_m), sand.terramechanics);
    }
    vehicle::LoaderControls c;
    c.parking_brake = true;
    c.lift = -1.0;
    Motion m;
    for (int s = 0; s < 2000; ++s) {
      w.step(c);
      m.fastest = std::max(m.fastest, w.loader().chassis_velocity().norm());
      m.highest = std::max(m.highest, w.loader().link_pose(0).translation().z());
    }
    EXPECT_TRUE(w.events().finite);
    return m;
  };
  for (double start_lift : {0.0, 0.1}) {
    const Motion firm = run(false, 0.0, start_lift);
    for (double layer_m : {0.0, 0.02}) {
      const Motion soil = run(true, layer_m, start_lift);
      // (Starting with the bucket 15 mm into the ground, the heightfield and
      // the plane push it out a little differently; the fault this guards
      // against threw the machine at 24 m/s.)
      EXPECT_LT(soil.fastest, firm.fastest + 0.5) << layer_m << " m of sand, lift " << start_lift;
      EXPECT_LT(soil.highest, firm.highest + layer_m + 0.1) << layer_m << " m of sand, lift " << start_lift;
    }
  }
}

}  // namespace
}  // namespace skidsim::testing

namespace skidsim::testing {
namespace {

// Driving from firm ground onto sand at the same level: each wheel's load
// moves from the Magic Formula's firm contact to the soil, and its forces
// change smoothly, step by step (no jump at the edge).
TEST(LoaderSoftSoil, TyreForcesChangeContinuouslyFromFirmGroundToSand) {
  SandSite site;
  site.cells_per_m = 20.0;
  site.origin_m = {0.0, -2.0};
  site.length_m = 8.0;
  engine::FirmGround ground;
  engine::StaticBox pad;  // firm ground level with the sand, ending at x = 0
  pad.pose.translation() = Eigen::Vector3d(-5.0, 0.0, 0.5 * kSandDepth);
  pad.half_extents_m = Eigen::Vector3d(5.0, 3.0, 0.5 * kSandDepth);
  ground.boxes.push_back(pad);
  auto w = loader_on_sand(site, Eigen::Vector3d(-3.0, 0.0, 0.0), ground);
  vehicle::LoaderControls c;
  c.drive_left = c.drive_right = 0.3;
  run_for(*w, c, 2.0);
  const auto& d = shipped_loader();
  std::vector<Eigen::Vector2d> previous(d.wheels.size(), Eigen::Vector2d::Zero());
  double largest_jump = 0.0, largest_soil_share = 0.0;
  bool crossed = false;
  for (int s = 0; s < 5000 && w->loader().link_pose(0).translation().x() < 3.0; ++s) {
    w->step(c);
    for (size_t k = 0; k < d.wheels.size(); ++k) {
      const vehicle::WheelState& ws = w->loader().wheels()[k];
      const Eigen::Vector2d f(ws.longitudinal_force_N, ws.lateral_force_N);
      if (s > 0) largest_jump = std::max(largest_jump, (f - previous[k]).norm());
      previous[k] = f;
      if (ws.normal_load_N > 0.0) largest_soil_share = std::max(largest_soil_share, ws.soil_load_N / ws.normal_load_N);
    }
    crossed = w->loader().link_pose(0).translation().x() > 1.5;
  }
  EXPECT_TRUE(crossed);
  EXPECT_GT(largest_soil_share, 0.99);  // the wheels did go over to the soil
  RecordProperty("largest_force_step_N", std::to_string(largest_jump));
  std::printf("[ measured ] firm ground onto sand: largest step of a tyre's force %.0f N\n", largest_jump);
  // Per 2 ms step, under a tenth of a wheel's share of the weight: the firm
  // edge passes smoothly (Bullet's contact test meets the edge as the disc
  // does), and what is left is the soil's own cell-by-cell grain.
  EXPECT_LT(largest_jump, 0.1 * kGravity_m_s2 * d.total_mass_kg() / d.wheels.size());
  EXPECT_TRUE(w->events().finite);
}

// Parked on a soil site's bare hard base (a heightfield, no plane): it stands
// as on a plane. (Bullet meets a heightfield triangle by triangle; contacts
// with the edge of a triangle ending beside the tyre pointed sideways and
// pushed the machine across.)
TEST(LoaderSoftSoil, ParkedOnABareSiteBaseStandsStill) {
  for (double y : {0.0, 0.013, 0.031}) {  // different alignments of the wheels with the grid
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() = Eigen::Vector3d(0.0, y, shipped_loader().tyre.radius_m - 0.01);
    engine::FirmGround ground;
    ground.has_plane = false;
    engine::World w(shipped_loader(), ground, pose, 0.2, 0.0);
    const io::SoilRecord sand = io::load_soil_table(io::default_soil_table_path()).at("dry_sand");
    w.add_soil_site(engine::flat_soil_grid(sand.flow, 20.0, {-4.0, -3.0}, 8.0, 6.0, 0.0), sand.terramechanics);
    vehicle::LoaderControls c;
    c.parking_brake = true;
    run_for(w, c, 1.0);
    const Eigen::Vector3d before = w.loader().link_pose(0).translation();
    double largest_lateral = 0.0;
    for (int i = 0; i < 2500; ++i) {
      w.step(c);
      for (const auto& ws : w.loader().wheels()) largest_lateral = std::max(largest_lateral, std::abs(ws.lateral_force_N));
    }
    EXPECT_LT((w.loader().link_pose(0).translation() - before).norm(), 1e-3) << "offset " << y;
    EXPECT_LT(largest_lateral, 300.0) << "offset " << y;
  }
}

// Standing for `seconds` with fixed controls: the chassis's fastest speed and
// the largest change of a wheel's soil load from one step to the next.
struct Standing {
  double fastest_m_s = 0.0, largest_load_step_N = 0.0;
};
Standing stand(engine::World& w, const vehicle::LoaderControls& c, double seconds) {
  Standing out;
  std::vector<double> before;
  for (const vehicle::WheelState& ws : w.loader().wheels()) before.push_back(ws.soil_load_N);
  for (long i = 0; i < std::lround(seconds / engine::kStepSeconds); ++i) {
    w.step(c);
    out.fastest_m_s = std::max(out.fastest_m_s, w.loader().chassis_velocity().norm());
    for (size_t k = 0; k < before.size(); ++k) {
      const double load = w.loader().wheels()[k].soil_load_N;
      out.largest_load_step_N = std::max(out.largest_load_step_N, std::abs(load - before[k]));
      before[k] = load;
    }
  }
  return out;
}

// A wheel's load standing still changes by less than this a step: a
// hundredth of the machine's weight on a wheel (the contact's cells changing
// hands once took 10-20 % of it off and put it back).
const double kNoJitterLoadStepN = 0.01 * kGravity_m_s2 * shipped_loader().total_mass_kg() / 4.0;

// Parked on a 15 deg sand slope (dry sand stops sliding at 30 deg), facing
// uphill, downhill and across it: once the wheels have pressed their ruts it
// stands still, with no creep down the slope and no jitter, the hand-over
// at standstill the deflection's spring holds (docs/loader.md).
TEST(LoaderSoftSoil, ParkedOnASandSlopeStandsStillWithoutJitter) {
  const double slope = deg_to_rad(15.0);
  const double x_foot = -4.0;  // where the slope starts rising from the sand's depth
  for (const double yaw_deg : {0.0, 180.0, 90.0}) {
    SandSite site;
    site.origin_m = {-5.0, -4.0};
    site.length_m = 10.0;
    site.width_m = 8.0;
    auto grid = engine::flat_soil_grid(site.soil.flow, site.cells_per_m, site.origin_m, site.length_m, site.width_m,
                                       kSandDepth);
    for (int j = 0; j < grid->ny(); ++j)
      for (int i = 0; i < grid->nx(); ++i) {
        const double x = site.origin_m.x() + i / site.cells_per_m;
        grid->set_material_m(i, j, kSandDepth + std::max(0.0, x - x_foot) * std::tan(slope));
      }
    const Eigen::Vector3d normal(-std::sin(slope), 0.0, std::cos(slope));
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = (Eigen::AngleAxisd(-slope, Eigen::Vector3d::UnitY()) *
                     Eigen::AngleAxisd(deg_to_rad(yaw_deg), Eigen::Vector3d::UnitZ()))
                        .toRotationMatrix();
    const double surface_at_origin = kSandDepth + (0.0 - x_foot) * std::tan(slope);
    pose.translation() = Eigen::Vector3d(0.0, 0.0, surface_at_origin) + shipped_loader().tyre.radius_m * normal;
    engine::World w(shipped_loader(), engine::FirmGround{}, pose, 0.2, 0.0);
    w.add_soil_site(std::move(grid), site.soil.terramechanics);
    vehicle::LoaderControls c;
    c.parking_brake = true;
    run_for(w, c, 4.0);  // the wheels press their ruts and the machine settles into them
    const Eigen::Vector3d before = w.loader().link_pose(0).translation();
    const Standing s = stand(w, c, 5.0);
    const double drift_mm = 1e3 * (w.loader().link_pose(0).translation() - before).norm();
    std::printf("[ measured ] parked on a 15 deg sand slope, facing %.0f deg from uphill: drift %.3f mm in 5 s, "
                "fastest %.2e m/s, largest step of a wheel's soil load %.1f N\n", yaw_deg, drift_mm, s.fastest_m_s,
                s.largest_load_step_N);
    EXPECT_LT(drift_mm, 1.0) << "facing " << yaw_deg << " deg from uphill";
    EXPECT_LT(s.fastest_m_s, 1e-3) << "facing " << yaw_deg << " deg from uphill";
    EXPECT_LT(s.largest_load_step_N, kNoJitterLoadStepN) << "facing " << yaw_deg << " deg from uphill";
    EXPECT_TRUE(w.events().finite);
  }
}

// Parked across the edge of firm ground and sand at one level (front wheels
// on the firm pad, rear on the sand, and the other way round): the machine's
// load shares between the Magic Formula's firm contact and the soil, and it
// stands still without jitter.
TEST(LoaderSoftSoil, ParkedAcrossTheFirmEdgeStandsStill) {
  for (const double pad_side : {1.0, -1.0}) {
    SandSite site;
    site.origin_m = {-4.0, -3.0};
    site.length_m = 8.0;
    site.width_m = 6.0;
    engine::FirmGround ground;
    engine::StaticBox pad;  // firm ground level with the sand, its edge at x = 0
    pad.pose.translation() = Eigen::Vector3d(pad_side * 5.0, 0.0, 0.5 * kSandDepth);
    pad.half_extents_m = Eigen::Vector3d(5.0, 3.0, 0.5 * kSandDepth);
    ground.boxes.push_back(pad);
    auto w = loader_on_sand(site, Eigen::Vector3d::Zero(), ground);
    vehicle::LoaderControls c;
    c.parking_brake = true;
    run_for(*w, c, 4.0);
    const Eigen::Vector3d before = w->loader().link_pose(0).translation();
    const Standing s = stand(*w, c, 5.0);
    double on_soil = 0.0, load = 0.0;
    for (const vehicle::WheelState& ws : w->loader().wheels()) on_soil += ws.soil_load_N, load += ws.normal_load_N;
    const double drift_mm = 1e3 * (w->loader().link_pose(0).translation() - before).norm();
    std::printf("[ measured ] parked across the firm edge (%s on the pad): drift %.3f mm in 5 s, fastest %.2e m/s, "
                "largest step of a wheel's soil load %.1f N, %.0f %% of the load on the soil\n",
                pad_side > 0 ? "front" : "rear", drift_mm, s.fastest_m_s, s.largest_load_step_N, 100.0 * on_soil / load);
    EXPECT_GT(on_soil, 0.2 * load);  // both kinds of ground carry the machine
    EXPECT_LT(on_soil, 0.8 * load);
    EXPECT_LT(drift_mm, 1.0);
    EXPECT_LT(s.fastest_m_s, 1e-3);
    EXPECT_LT(s.largest_load_step_N, kNoJitterLoadStepN);
    EXPECT_TRUE(w->events().finite);
  }
}

// The same controls on sand give the same machine and terrain, bit for bit.
TEST(LoaderSoftSoil, SameControlsOnSandGiveTheSameStateBitForBit) {
  auto run = [] {
    SandSite site;
    site.cells_per_m = 10.0;
    auto w = loader_on_sand(site);
    vehicle::LoaderControls c;
    for (int i = 0; i < 2000; ++i) {
      c.drive_left = 0.6 + 0.4 * std::sin(i * 0.004);
      c.drive_right = 0.6;
      c.lift = i < 1000 ? -0.5 : 0.5;
      c.tilt = i % 600 < 300 ? 0.4 : -0.4;
      w->step(c);
    }
    std::vector<double> state;
    const Eigen::Isometry3d p = w->loader().link_pose(2);
    for (int k = 0; k < 3; ++k) state.push_back(p.translation()[k]);
    const terrain::GranularGrid& g = *w->terrain();
    for (int j = 0; j < g.ny(); ++j)
      for (int i = 0; i < g.nx(); ++i) state.push_back(g.surface_m(i, j));
    return state;
  };
  const auto a = run(), b = run();
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(double)));
}

}  // namespace
}  // namespace skidsim::testing
