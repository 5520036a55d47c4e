// Tasks, events and metrics at run time: delivered material stays counted
// once a task is done; an enter_zone event fires on entering, not for
// starting there; a long timed script phase runs its whole duration.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "session/operator_player.h"
#include "session/session_tasks.h"
#include "session/session_world.h"
#include "io/loader_files.h"

namespace skidsim::session {
namespace {

namespace fs = std::filesystem;

struct Scene {
  fs::path dir;
  io::Exercise ex;
  std::unique_ptr<engine::World> world;
  explicit Scene(const std::string& xml) {
    dir = fs::temp_directory_path() / ("skidsim_tasks_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    std::ofstream(dir / "e.xml") << xml;
    ex = io::load_exercise((dir / "e.xml").string());
    world = build_session_world(ex, io::load_loader(ex.machine.loader), io::load_soil_table(io::default_soil_table_path()));
  }
  ~Scene() { fs::remove_all(dir); }
};

const char* kYard = R"(<exercise name="t" version="1" time_limit_s="60">
  <site size_m="20 20">
    <soil id="yard" region="4 4 16 16" cell_m="0.1" depth_m="0.05" type="dry_sand"/>
    <zone id="target" region="12 8 14 12"/>
    <zone id="start" region="1 8 4 12"/>
  </site>
  <machine position="2 10"/>
  <operator source="lcm"/>
  <task id="move" type="move_material" from="yard" to="target" mass_kg="100"/>
  <event when="enter_zone" zone="start" message="back at the start"/>
  <event when="enter_zone" zone="target" message="in the target"/>
</exercise>
)";

TEST(SessionTasks, DeliveredMaterialStaysCountedOnceTheTaskIsDone) {
  Scene s(kYard);
  SessionTasks tasks(s.ex, *s.world);
  tasks.update(*s.world, 0.01);
  EXPECT_FALSE(tasks.all_done());
  s.world->terrain()->add_material_m3(s.world->terrain()->nx() * 3 / 4, s.world->terrain()->ny() / 2, 0.1);  // 160 kg at (13, 10)
  tasks.update(*s.world, 0.01);
  EXPECT_TRUE(tasks.all_done());
  const double moved = tasks.metrics().material_moved_kg;
  EXPECT_NEAR(moved, 160.0, 1.0);
  tasks.update(*s.world, 0.01);
  EXPECT_EQ(tasks.metrics().material_moved_kg, moved) << "delivered material must stay counted";
}

TEST(SessionTasks, EnterZoneFiresOnEnteringNotForStartingThere) {
  Scene s(kYard);
  SessionTasks tasks(s.ex, *s.world);
  tasks.update(*s.world, 0.01);
  for (const SessionEvent& e : tasks.take_events()) EXPECT_NE(e.text, "back at the start") << "it started there";
  EXPECT_EQ(tasks.active_task(), "move");
}

TEST(OperatorPlayer, LongTimedPhaseRunsItsWholeDuration) {
  const fs::path f = fs::temp_directory_path() / ("skidsim_hold_" + std::to_string(::getpid()) + ".xml");
  std::ofstream(f) << "<operator_script name=\"h\">\n  <hold duration_s=\"45\" drive=\"0.2 0.2\"/>\n</operator_script>\n";
  OperatorPlayer p(io::load_operator_script(f.string()));
  skidsim_lcm::state_t s{};
  s.chassis_orientation_wxyz[0] = 1.0;
  for (int k = 0; k <= 4400 && !p.done(); ++k) {
    s.sim_time_s = 0.01 * k;
    EXPECT_EQ(p.step(s).drive_left, 0.2);
  }
  s.sim_time_s = 45.01;
  p.step(s);
  EXPECT_TRUE(p.done());
  EXPECT_TRUE(p.timed_out().empty());
  fs::remove(f);
}

}  // namespace
}  // namespace skidsim::session
