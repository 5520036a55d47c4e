// Agents in the world (issue 9): a person is a body the machine meets but
// does not push (the contact is reported, the machine's motion is that of
// a world without the person); a truck carries its bed, with what is in
// it, from its route to the loading spot and away once loaded.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "engine/world.h"
#include "common/physical_constants.h"
#include "io/soil_table.h"
#include "tests/loader_support.h"

namespace skidsim::testing {
namespace {

const io::SoilRecord& sand() { return dry_sand(); }

vehicle::LoaderControls forward() {
  vehicle::LoaderControls c;
  c.drive_left = c.drive_right = 0.5;
  c.throttle = 1.0;
  return c;
}

TEST(WorldAgents, TheMachineMeetsAPersonWithoutBeingPushed) {
  std::vector<std::unique_ptr<engine::World>> worlds;
  for (int with_person = 0; with_person < 2; ++with_person) {
    worlds.push_back(loader_on_ground());
    if (with_person) {
      engine::AgentSpec person;
      person.id = "bystander";
      person.route_m = {{4.0, 0.0}};
      person.keep_clear_m = 0.0;  // does not look up: steps aside only at the last moment
      worlds.back()->add_agent(person);
    }
  }
  double first_contact_s = -1.0;
  std::vector<int> touching;
  for (int k = 0; k < 3000; ++k) {
    for (auto& w : worlds) w->step(forward());
    worlds[1]->agents_touching_machine(touching);
    if (first_contact_s < 0.0 && !touching.empty()) first_contact_s = worlds[1]->time_s();
  }
  std::printf("[ measured ] the machine at half speed reaches a person 4 m ahead at %.2f s\n", first_contact_s);
  EXPECT_GT(first_contact_s, 1.0);
  EXPECT_LT(first_contact_s, 5.5);
  const Eigen::Isometry3d a = worlds[0]->loader().link_pose(0), b = worlds[1]->loader().link_pose(0);
  EXPECT_EQ(a.matrix(), b.matrix()) << "no push from a person: the same motion bit for bit";
  EXPECT_GT((worlds[1]->agents()[0].body.position_m - Eigen::Vector2d(4.0, 0.0)).norm(), 1.0) << "they tried to get away";
}

// A 4 m x 2.2 m bed on a truck that backs in along -x to the loading spot
// (8, 0), cab towards +x, leaves at 500 kg and drives off along +x; returns
// the bed's tray.
// The bed's frame when docked: centre at (8, 0), cab towards +x.
const Eigen::Vector3d kDockedBedOriginM(6.0, -1.1, 1.0);

int add_truck(engine::World& w) {
  engine::TraySpec bed;
  bed.shape.length_m = 4.0;
  bed.shape.width_m = 2.2;
  bed.shape.back_height_m = bed.shape.side_height_back_m = bed.shape.side_height_front_m = bed.shape.front_height_m = 0.5;
  bed.shape.heel_radius_m = 0.0;
  bed.pose.translation() = kDockedBedOriginM;
  const int tray = w.add_tray(bed);
  engine::AgentSpec truck;
  truck.id = "truck";
  truck.kind = engine::AgentKind::kTruck;
  truck.tray = tray;
  truck.speed_m_s = 3.0;
  truck.route_m = {{25.0, 0.0}, {14.0, 0.0}};  // backs in along -x; the spot (8, 0) is appended
  truck.leave_at_kg = 500.0;
  truck.exit_m = {{20.0, 0.0}, {40.0, 0.0}};
  w.add_agent(truck);
  return tray;
}

vehicle::LoaderControls parked() {
  vehicle::LoaderControls brake;
  brake.parking_brake = true;
  return brake;
}

TEST(WorldAgents, ATruckCarriesItsBedToTheSpotAndAwayWithItsLoad) {
  auto w = loader_on_ground();
  w->enable_material(sand().flow, 0.05);
  const int tray = add_truck(*w);
  ASSERT_EQ(w->agent_specs()[0].route_m.back(), Eigen::Vector2d(8.0, 0.0));
  EXPECT_GT((w->tray(tray).pose().translation() - kDockedBedOriginM).norm(), 10.0) << "the bed starts with the truck";
  const vehicle::LoaderControls brake = parked();
  while (w->agents()[0].phase != engine::AgentPhase::kDocked && w->time_s() < 30.0) w->step(brake);
  ASSERT_EQ(w->agents()[0].phase, engine::AgentPhase::kDocked);
  const double dock_error_m = (w->tray(tray).pose().translation() - kDockedBedOriginM).norm();
  std::printf("[ measured ] truck docked after %.1f s, bed %.3f m from its loading pose\n", w->time_s(), dock_error_m);
  EXPECT_LT(dock_error_m, engine::kReachedM);
  // Loaded (put in, as if dumped): it leaves, the load with it.
  terrain::GranularGrid& g = w->tray(tray).grid();
  for (int j = 2; j + 2 < g.ny(); ++j)
    for (int i = 2; i + 2 < g.nx(); ++i) g.set_material_m(i, j, 0.15);
  const double load_kg = w->tray(tray).material_mass_kg();
  ASSERT_GT(load_kg, 500.0);
  for (int k = 0; k < 10000 && w->agents()[0].phase != engine::AgentPhase::kGone; ++k) w->step(brake);
  EXPECT_EQ(w->agents()[0].phase, engine::AgentPhase::kGone);
  std::printf("[ measured ] %.0f kg loaded; %.0f kg in the bed as the truck leaves the site\n", load_kg, w->tray(tray).material_mass_kg());
  EXPECT_GT(w->tray(tray).material_mass_kg(), 0.98 * load_kg) << "driven off smoothly, the load stays in";
}

// The bed's load feels the truck's acceleration (World::set_apparent_gravity,
// on with the fast flows): pulling away at a = 1.5 m/s^2 tilts the load's
// gravity back by beta = atan(a / g) = 8.7 deg, so a ridge standing at its
// stop angle alpha_I slides towards the tailgate; without, it rides
// unchanged. The books stay exact either way. The reference is the closed
// form of a Coulomb heap under the tilt: the ridge's triangle (height H,
// flanks at alpha_I) keeps its front foot and flank and lays its rear flank
// at theta - beta to the bed, its area kept, with theta = alpha_I where a
// flowing flank stops (thesis 4.5); theta = alpha, the repose angle, gives
// the least it could move. The ridge is the material above the 5 cm base,
// half a metre and more from the bed's walls (the closed form is the
// section's; by the walls the cells settle on their own).
double tilted_ridge_shift_m(double ridge_m, double tan_front, double tan_rear) {
  const double area = ridge_m * ridge_m / tan_front;
  const double h = std::sqrt(2.0 * area / (1.0 / tan_front + 1.0 / tan_rear));
  const double front = ridge_m / tan_front, peak = front - h / tan_front, rear = peak - h / tan_rear;
  return (front + peak + rear) / 3.0;
}

TEST(WorldAgents, ATruckPullingAwayShiftsAHeapedLoadBackOnlyWithApparentGravity) {
  constexpr double kBaseM = 0.05, kRidgeM = 0.40, kCrestAtM = 2.0;
  double shift_m[2] = {0.0, 0.0}, at_stop_m = 0.0, at_repose_m = 0.0;
  for (int on = 0; on < 2; ++on) {
    auto w = loader_on_ground();
    w->enable_material(sand().flow, 0.05);
    w->set_apparent_gravity(on != 0);
    const int tray = add_truck(*w);
    while (w->agents()[0].phase != engine::AgentPhase::kDocked && w->time_s() < 30.0) w->step(parked());
    ASSERT_EQ(w->agents()[0].phase, engine::AgentPhase::kDocked);
    // A ridge across the bed's width, its crest 0.4 m above a 5 cm base, its
    // flanks at the stop angle.
    terrain::GranularGrid& g = w->tray(tray).grid();
    const double tan_stop = std::tan(deg_to_rad(sand().flow.stop_angle_deg)), d = g.cell_size_m();
    for (int j = 0; j < g.ny(); ++j)
      for (int i = 0; i < g.nx(); ++i)
        g.set_material_m(i, j, kBaseM + std::max(0.0, kRidgeM - std::abs((i + 0.5) * d - kCrestAtM) * tan_stop));
    auto ridge_centre_m = [&] {
      double m = 0.0, mx = 0.0;
      for (int j = 0; j < g.ny(); ++j)
        for (int i = 0; i < g.nx(); ++i) {
          const double x = (i + 0.5) * d, y = (j + 0.5) * d, above = std::max(0.0, g.material_m(i, j) - kBaseM);
          if (x > 0.5 && x < g.nx() * d - 0.5 && y > 0.5 && y < g.ny() * d - 0.5) m += above, mx += above * x;
        }
      return mx / m;
    };
    // Loaded past 500 kg, the truck leaves at once: the ridge's centre from
    // now (it is symmetric, so its own settling leaves the centre where it
    // is) until 3 s later.
    const double before = ridge_centre_m();
    double peak_m_s2 = 0.0;
    for (int k = 0; k < 1500; ++k) {
      w->step(parked());
      peak_m_s2 = std::max(peak_m_s2, w->tray(tray).frame_acceleration().norm());
    }
    ASSERT_EQ(w->agents()[0].phase, engine::AgentPhase::kLeaving);
    shift_m[on] = ridge_centre_m() - before;
    const engine::SteeringAgent& body = w->agents()[0].body;
    const double beta = std::atan(body.max_force_N / body.mass_kg / kGravity_m_s2);
    const double alpha_i = deg_to_rad(sand().flow.stop_angle_deg), alpha = deg_to_rad(sand().flow.repose_angle_deg);
    at_stop_m = tilted_ridge_shift_m(kRidgeM, std::tan(alpha_i), std::tan(alpha_i - beta));
    at_repose_m = tilted_ridge_shift_m(kRidgeM, std::tan(alpha_i), std::tan(alpha - beta));
    std::printf("[ measured ] apparent gravity %s (peak %.2f m/s^2 filtered): the ridge's centre moved %+.4f m along the bed "
                "(closed form %+.4f m, %+.4f m were its flank to stop at the repose angle)\n",
                on ? "on" : "off", peak_m_s2, shift_m[on], at_stop_m, at_repose_m);
    EXPECT_TRUE(g.ledger().balanced());
  }
  EXPECT_LT(std::abs(shift_m[0]), 0.001) << "without apparent gravity the load rides as it stood";
  EXPECT_NEAR(shift_m[1], at_stop_m, 0.1 * std::abs(at_stop_m)) << "pulling away throws the load towards the tailgate";
}

}  // namespace
}  // namespace skidsim::testing
