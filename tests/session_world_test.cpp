// A session's world from its exercise: what the file says is what gets
// built (the soil site with its pile, the zone's truck-free yard, the
// machine at its start), nothing more (a course on firm ground builds no
// soil); the state message reports the machine.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "common/physical_constants.h"
#include "session/session_world.h"
#include "io/loader_files.h"

namespace skidsim::session {
namespace {

namespace fs = std::filesystem;

const io::SoilTable& soils() {
  static const io::SoilTable t = io::load_soil_table(io::default_soil_table_path());
  return t;
}

std::string source(const std::string& relative) {
  return (fs::path(io::default_loader_path()).parent_path().parent_path().parent_path() / relative).string();
}

TEST(SessionWorld, PileToZoneBuildsItsSoilSiteAndMachine) {
  const io::Exercise ex = io::load_exercise(source("scenarios/pile_to_zone.xml"));
  const vehicle::LoaderDescription loader = io::load_loader(ex.machine.loader);
  auto w = build_session_world(ex, loader, soils());
  ASSERT_NE(w->terrain(), nullptr);
  const terrain::GranularGrid& g = *w->terrain();
  EXPECT_EQ(g.nx(), 240);  // 12 m at 5 cm
  EXPECT_EQ(g.ny(), 240);
  // The layer plus the cone: within the grid's discretisation of the cone.
  const io::SoilSite& s = ex.soils.front();
  const double expected_m3 = s.region.volume() * s.depth_m + kPi * 2.0 * 2.0 * 1.0 / 3.0;
  EXPECT_NEAR(g.total_volume_m3(), expected_m3, 0.01 * expected_m3);
  const Eigen::Vector3d chassis = w->loader().link_pose(0).translation();
  EXPECT_NEAR(chassis.x(), 3.0, 1e-9);
  EXPECT_NEAR(chassis.y(), 10.0, 1e-9);
  ASSERT_NE(w->bucket_material(), nullptr);
  vehicle::LoaderControls c;
  c.parking_brake = true;
  for (int k = 0; k < 500; ++k) w->step(c);
  EXPECT_TRUE(w->events().finite);
  const skidsim_lcm::state_t st = machine_state(*w, true);
  EXPECT_EQ(st.step, 500);
  EXPECT_NEAR(st.sim_time_s, 1.0, 1e-12);
  EXPECT_EQ(st.num_wheels, 4);
  EXPECT_EQ(st.wheel_slip.size(), 4u);
  EXPECT_NEAR(st.chassis_position_m[0], 3.0, 0.01);
  EXPECT_GT(st.tipping_margin, 0.2) << "parked, the rear axle carries its share";
  EXPECT_TRUE(st.controls_neutral);
}

TEST(SessionWorld, CourseOnFirmGroundBuildsNoSoilAndItsTruckAndBoxes) {
  const fs::path dir = fs::temp_directory_path() / ("skidsim_session_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path file = dir / "course.xml";
  std::ofstream(file) << R"(<exercise name="course" version="1" time_limit_s="120">
  <site size_m="30 20">
    <box id="cone1" centre="10 5 0.25" size="0.5 0.5 0.5"/>
    <truck id="truck" back_corner="20 8" yaw_deg="90" length_m="3" width_m="2.2" floor_height_m="1.0" wall_height_m="0.4"/>
  </site>
  <machine position="2 10" yaw_deg="30"/>
  <operator source="lcm"/>
  <task id="course" type="drive_course"><gate region="8 8 9 12"/><gate region="15 8 16 12"/></task>
</exercise>
)";
  const io::Exercise ex = io::load_exercise(file.string());
  const vehicle::LoaderDescription loader = io::load_loader(ex.machine.loader);
  auto w = build_session_world(ex, loader, soils());
  EXPECT_EQ(w->terrain(), nullptr) << "no soil where the exercise has none";
  ASSERT_EQ(w->tray_count(), 1);
  EXPECT_NEAR(w->tray(0).pose().translation().z(), 1.0, 1e-12);
  const Eigen::Matrix3d r = w->loader().link_pose(0).linear();
  EXPECT_NEAR(std::atan2(r(1, 0), r(0, 0)), 30.0 * kPi / 180.0, 1e-9);
  fs::remove_all(dir);
}

// A soil site selects its ground model: in stiff sandy loam (c = 9.65 kPa)
// the slippage model keeps a 0.6 m trench's walls standing (Culmann's
// critical height is 4.2 m), while the automaton, which has no cohesion,
// slumps them to its repose angle.
TEST(SessionWorld, SoilSiteSelectsItsGroundModel) {
  const fs::path dir = fs::temp_directory_path() / ("skidsim_model_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const auto trench_fill_m3 = [&](const std::string& model_attribute) {
    const fs::path file = dir / "trench.xml";
    std::ofstream(file) << R"(<exercise name="trench" version="1" time_limit_s="60">
  <site size_m="12 10">
    <soil id="ground" region="4 2 10 8" cell_m="0.05" depth_m="0.8" type="sandy_loam_23" )"
                        << model_attribute << R"(>
      <trench from="5 5" to="9 5" width_m="1.0" depth_m="0.6"/>
    </soil>
  </site>
  <machine position="1.5 5" yaw_deg="0"/>
  <operator source="lcm"/>
  <task id="park" type="drive_course"><gate region="2 4 3 6"/></task>
</exercise>
)";
    const io::Exercise ex = io::load_exercise(file.string());
    auto w = build_session_world(ex, io::load_loader(ex.machine.loader), soils());
    const terrain::GranularGrid& g = *w->terrain();
    const auto in_trench = [&]() {
      double m3 = 0.0;
      for (int j = 0; j < g.ny(); ++j)
        for (int i = 0; i < g.nx(); ++i) {
          const Eigen::Vector2d p = g.spec().origin_m + g.cell_size_m() * Eigen::Vector2d(i, j);
          if (p.x() > 5.2 && p.x() < 8.8 && std::abs(p.y() - 5.0) < 0.45) m3 += g.material_m(i, j) - 0.2;
        }
      return m3 * g.cell_size_m() * g.cell_size_m();
    };
    // (The world is built settled: the automaton's walls have slumped.)
    vehicle::LoaderControls c;
    c.parking_brake = true;
    for (int k = 0; k < 1000; ++k) w->step(c);
    EXPECT_TRUE(g.ledger().balanced());
    return std::make_pair(g.ground_model(), in_trench());
  };
  const auto [slip_model, slip_fill] = trench_fill_m3("model=\"slippage\"");
  const auto [ca_model, ca_fill] = trench_fill_m3("");
  EXPECT_EQ(slip_model, terrain::GroundModel::kSlippage);
  EXPECT_EQ(ca_model, terrain::GroundModel::kAutomaton);
  EXPECT_LT(std::abs(slip_fill), 1e-6) << "the walls stand";
  EXPECT_GT(ca_fill, 0.1) << "the walls slump into the trench";
  fs::remove_all(dir);
}

}  // namespace
}  // namespace skidsim::session
