// A scripted operator plays pile-to-zone in its world: three times the
// bucket is filled at the pile, carried round it and dumped in the zone;
// every phase reaches its goal; the zone gets the task's 800 kg; the same
// script twice gives the same terrain.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "session/operator_player.h"
#include "session/session_world.h"
#include "io/atomic_file.h"
#include "io/loader_files.h"

namespace skidsim::session {
namespace {

namespace fs = std::filesystem;

std::string source(const std::string& relative) {
  return (fs::path(io::default_loader_path()).parent_path().parent_path().parent_path() / relative).string();
}

struct Played {
  double zone_gain_kg = 0.0;
  std::vector<std::string> timed_out;
  std::vector<std::int64_t> terrain;
  bool done = false;
};

Played play_pile_to_zone() {
  const io::SoilTable soils = io::load_soil_table(io::default_soil_table_path());
  const io::Exercise ex = io::load_exercise(source("scenarios/pile_to_zone.xml"));
  auto w = build_session_world(ex, io::load_loader(ex.machine.loader), soils);
  OperatorPlayer player(io::load_operator_script(source("scenarios/pile_to_zone.operator.xml")));
  const terrain::GranularGrid& g = *w->terrain();
  const auto zone_kg = [&] {
    double kg = 0.0;
    for (int j = 0; j < g.ny(); ++j)
      for (int i = 0; i < g.nx(); ++i)
        if (ex.zones.front().region.contains(g.spec().origin_m + g.cell_size_m() * Eigen::Vector2d(i, j)))
          kg += g.material_mass_kg(i, j);
    return kg;
  };
  const double before = zone_kg();
  for (int s = 0; s < 240 * 500 && !player.done(); ++s) w->step(player.step(machine_state(*w, false)));
  Played out;
  out.done = player.done();
  out.zone_gain_kg = zone_kg() - before;
  out.timed_out = player.timed_out();
  for (int c = 0; c < g.nx() * g.ny(); ++c) out.terrain.push_back(g.loose_quanta(c));
  return out;
}

TEST(SessionOperator, ScriptedPassesMoveTheTasksMassIntoTheZone) {
  const Played a = play_pile_to_zone();
  EXPECT_TRUE(a.done);
  EXPECT_TRUE(a.timed_out.empty()) << a.timed_out.front();
  EXPECT_GT(a.zone_gain_kg, 800.0) << "three passes must put the task's 800 kg in the zone";
  std::printf("[ measured ] three scripted passes: %.0f kg into the zone\n", a.zone_gain_kg);
  const Played b = play_pile_to_zone();
  EXPECT_TRUE(a.terrain == b.terrain) << "the same script must give the same terrain";
}

TEST(OperatorScript, BadScriptsNameFileLineAndElement) {
  const fs::path dir = fs::temp_directory_path() / ("skidsim_script_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  struct Case {
    std::string body, expected;
  };
  for (const Case& c : {Case{"<hold duration_s=\"1\" drive=\"2 0\"/>", "<hold> attribute 'drive'"},
                        Case{"<dig/>", "<dig> unknown element"},
                        Case{"<raise angle_rad=\"5\"/>", "<raise> attribute 'angle_rad' = 5: out of range"},
                        Case{"<drive_to to=\"1\"/>", "expected 2 numbers"},
                        Case{"<advance_until_full lift_rad=\"2\"/>",
                             "<advance_until_full> attribute 'lift_rad' = 2: out of range"},
                        Case{"<advance_until_full pitch_deg=\"-90\"/>", "attribute 'pitch_deg' = -90: out of range"},
                        Case{"", "at least one phase"}}) {
    const fs::path f = dir / "s.xml";
    std::ofstream(f, std::ios::trunc) << "<operator_script name=\"t\">\n  " << c.body << "\n</operator_script>\n";
    try {
      io::load_operator_script(f.string());
      ADD_FAILURE() << "no error for " << c.body;
    } catch (const io::InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(f.string() + ":"), std::string::npos) << msg;
      EXPECT_NE(msg.find(c.expected), std::string::npos) << msg;
    }
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace skidsim::session
