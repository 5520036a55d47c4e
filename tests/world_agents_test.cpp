// Agents in the world (issue 9): a person is a body the machine meets but
// does not push (the contact is reported, the machine's motion is that of
// a world without the person); a truck carries its bed, with what is in
// it, from its route to the loading spot and away once loaded.
#include <gtest/gtest.h>

#include "engine/world.h"
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

TEST(WorldAgents, ATruckCarriesItsBedToTheSpotAndAwayWithItsLoad) {
  auto w = loader_on_ground();
  w->enable_material(sand().flow, 0.05);
  engine::TraySpec bed;
  bed.shape.length_m = 4.0;
  bed.shape.width_m = 2.2;
  bed.shape.back_height_m = bed.shape.side_height_back_m = bed.shape.side_height_front_m = bed.shape.front_height_m = 0.5;
  bed.shape.heel_radius_m = 0.0;
  bed.pose.translation() = Eigen::Vector3d(6.0, -1.1, 1.0);  // docked: bed centre at (8, 0), cab towards +x
  const int tray = w->add_tray(bed);
  engine::AgentSpec truck;
  truck.id = "truck";
  truck.kind = engine::AgentKind::kTruck;
  truck.tray = tray;
  truck.speed_m_s = 3.0;
  truck.route_m = {{25.0, 0.0}, {14.0, 0.0}};  // backs in along -x; the spot (8, 0) is appended
  truck.leave_at_kg = 500.0;
  truck.exit_m = {{20.0, 0.0}, {40.0, 0.0}};
  w->add_agent(truck);
  ASSERT_EQ(w->agent_specs()[0].route_m.back(), Eigen::Vector2d(8.0, 0.0));
  EXPECT_GT((w->tray(tray).pose().translation() - bed.pose.translation()).norm(), 10.0) << "the bed starts with the truck";
  vehicle::LoaderControls brake;
  brake.parking_brake = true;
  while (w->agents()[0].phase != engine::AgentPhase::kDocked && w->time_s() < 30.0) w->step(brake);
  ASSERT_EQ(w->agents()[0].phase, engine::AgentPhase::kDocked);
  const double dock_error_m = (w->tray(tray).pose().translation() - bed.pose.translation()).norm();
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

}  // namespace
}  // namespace skidsim::testing
