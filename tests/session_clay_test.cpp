// The clay exercise (scenarios/clay_cut.xml) and the stall measure: thin
// slices off the top of the cohesive bank pass it without a stall; the deep
// script, its edge tipped into the bank's foot, stalls twice (an event each)
// half full and barely into the face; the same deep script in a
// cohesionless sand bank fills its bucket without stalling.
//
// The bucket's forward resistance in the cut is about to change (the
// cutting edge's share of the wedge bound becomes a penetration model), so
// every figure is asserted with room: the measured values are in the
// comments and printed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>

#include "session/session.h"
#include "io/loader_files.h"

namespace skidsim::session {
namespace {

namespace fs = std::filesystem;

std::string source(const std::string& relative) {
  return (fs::path(io::default_loader_path()).parent_path().parent_path().parent_path() / relative).string();
}

constexpr double kBankFaceX_m = 10.0;  // the bank's face in clay_cut.xml: the pit's east edge, 6.5 + 7 / 2 m

// One session played in-process by a script (fast mode), with what the
// report does not keep: per tick, the bucket's load, how far its lip has
// gone east and the chassis speed, and the script's phase.
struct Played {
  nlohmann::json report;
  struct Tick {
    double t_s, bucket_kg, lip_x_m, speed_m_s;
    std::string phase;
  };
  std::vector<Tick> ticks;
  std::vector<double> stall_times_s() const {
    std::vector<double> out;
    for (const auto& e : report["events"])
      if (e["kind"] == "stall") out.push_back(e["time_s"].get<double>());
    return out;
  }
  const Tick& at(double t_s) const {
    return *std::lower_bound(ticks.begin(), ticks.end() - 1, t_s, [](const Tick& k, double t) { return k.t_s < t; });
  }
  // The ticks of the script's first phase of this kind.
  std::vector<Tick> first_phase(const std::string& kind) const {
    std::vector<Tick> out;
    for (const Tick& k : ticks) {
      if (k.phase == kind) out.push_back(k);
      if (!out.empty() && k.phase != kind) break;
    }
    return out;
  }
};

Played play(const std::string& exercise, const std::string& script) {
  const io::SoilTable soils = io::load_soil_table(io::default_soil_table_path());
  const io::Exercise ex = io::load_exercise(exercise);
  Session session(ex, io::load_loader(ex.machine.loader), soils, SessionOptions{});
  ScriptOperator op(io::load_operator_script(script));
  SessionOutput none;
  const DecideControls decide = [&](const skidsim_lcm::state_t& st, long, double t) { return op.decide(st, t); };
  Played out;
  std::string end;
  while ((end = session.tick(false, decide, none)).empty()) {
    const engine::World& w = session.world();
    const terrain::BodyAutomaton& b = *w.bucket_material();
    const Eigen::Vector3d lip = b.pose() * Eigen::Vector3d(b.shape().length_m, 0.5 * b.shape().width_m, 0.0);
    out.ticks.push_back({w.time_s(), b.material_mass_kg(), lip.x(), w.loader().chassis_velocity().head<2>().norm(),
                         op.player().phase_name()});
  }
  session.finish(end, none);
  out.report = session.report(end);
  out.report["timed_out"] = op.player().timed_out();
  return out;
}

// The thin cuts: the bank is taken in two 0.2 m slices off its top; the
// machine cuts at its full speed and never stalls; the task's 500 kg are in
// the zone, without an impact or a tipping scare.
TEST(ClayCut, ThinSlicesOffTheTopPassWithoutAStall) {
  const Played p = play(source("scenarios/clay_cut.xml"), source("scenarios/clay_cut.operator.xml"));
  const nlohmann::json& m = p.report["metrics"];
  EXPECT_EQ(p.report["end_reason"], "tasks_done");
  EXPECT_TRUE(p.report["result"]["passed"].get<bool>()) << p.report["result"].dump();
  EXPECT_TRUE(p.report["timed_out"].empty()) << p.report["timed_out"].dump();
  // 500.9 kg at 66.8 s (the task's mass, reached as the second load lands).
  EXPECT_GE(m["material_moved_kg"].get<double>(), 500.0);
  EXPECT_EQ(m["stall_time_s"].get<double>(), 0.0);  // measured 0: never held up 1 s
  EXPECT_TRUE(p.stall_times_s().empty());
  EXPECT_EQ(m["bucket_impacts"].get<double>(), 0.0) << "peak " << p.report["peak_bucket_acceleration_m_s2"];
  EXPECT_EQ(m["tipping_margin_violations"].get<double>(), 0.0);
  // The margin: while the edge slices (the bucket filling in the advance),
  // the clay barely slows the machine (0.55 m/s of its 0.6 m/s free at this
  // lever, measured); a stall is under 0.05 m/s.
  double slowest = 1e9, fill_kg = 0.0;
  for (std::size_t k = 1; k < p.ticks.size(); ++k)
    if (p.ticks[k].phase == "advance_until_full" && p.ticks[k].bucket_kg > 50.0 && p.ticks[k].bucket_kg < 350.0) {
      slowest = std::min(slowest, p.ticks[k].speed_m_s);
      fill_kg = std::max(fill_kg, p.ticks[k].bucket_kg);
    }
  EXPECT_GT(fill_kg, 300.0) << "the advance must have cut";
  EXPECT_GT(slowest, 0.25) << "the thin slices must come away well short of a stall";
  std::printf("[ measured ] thin slices: %.1f kg moved at %.1f s, score %.1f, stall %.2f s, slowest cut %.2f m/s, "
              "peak bucket %.1f m/s^2\n",
              m["material_moved_kg"].get<double>(), m["completion_time_s"].get<double>(),
              p.report["result"]["score"].get<double>(), m["stall_time_s"].get<double>(), slowest,
              p.report["peak_bucket_acceleration_m_s2"].get<double>());
}

// The deep cut: the edge tipped 12 deg into the bank's foot, the clay's
// standing 1 m face stops the machine half full (346 kg of its 450 kg)
// 0.10 m into the face, the wheels spinning; the script pushes 4 s before
// it curls out. Two attempts, the load tipped in the zone between (the
// machine moves on): two stalls, one event each.
TEST(ClayCut, DeepCutIntoTheBankStalls) {
  const Played p = play(source("scenarios/clay_cut.xml"), source("scenarios/clay_cut.deep.operator.xml"));
  const nlohmann::json& m = p.report["metrics"];
  const std::vector<double> stalls = p.stall_times_s();
  ASSERT_EQ(stalls.size(), 2u) << p.report["events"].dump();
  // 8.06 s measured (each stall from its onset to the script's curl).
  EXPECT_GT(m["stall_time_s"].get<double>(), 6.0);
  EXPECT_FALSE(p.report["result"]["passed"].get<bool>());
  // Where the first stall left the bucket: well short of the 450 kg asked
  // for, its lip hardly into the face.
  const double kg_at_stall = p.at(stalls[0]).bucket_kg;
  double deepest_lip_m = 0.0;
  for (const Played::Tick& k : p.first_phase("advance_until_full")) deepest_lip_m = std::max(deepest_lip_m, k.lip_x_m);
  // 346 kg measured (the edge's bearing, terrain/edge_penetration.h, and the
  // equation's wedge as it fills): far from the 450 kg asked for and the
  // clay's 700 kg heaped.
  EXPECT_LT(kg_at_stall, 400.0);
  EXPECT_LT(deepest_lip_m - kBankFaceX_m, 0.3);
  std::printf("[ measured ] deep cut: stalls at %.2f and %.2f s, stall_time_s %.2f, %.0f kg in the bucket at "
              "the first, lip %.2f m into the face; %.1f kg moved, score %.1f, peak bucket %.1f m/s^2\n",
              stalls[0], stalls[1], m["stall_time_s"].get<double>(), kg_at_stall, deepest_lip_m - kBankFaceX_m,
              m["material_moved_kg"].get<double>(), p.report["result"]["score"].get<double>(),
              p.report["peak_bucket_acceleration_m_s2"].get<double>());
}

// The same deep script in a bank of sand: dry_sand, the table's dry sand
// (no cohesion, and the thesis's wedge for the cut, as the table gives its
// sands). A cohesionless bank cannot stand: it runs on the automaton (the
// slippage model fails a sand slice at phi as the automaton does at repose,
// and its slow creep to rest would cost the test half a minute before the
// session starts) and slumps to its repose angle, so the bucket fills its
// 450 kg without stopping (it stops only heaped, about 650 kg). The stall is
// the clay's. (dem_sand, the earthmoving equation with no cohesion, fills
// its 450 kg without a stall too, but only just: it stops once about full,
// near 450 kg, so it would test the margin of the sand, not the clay.)
TEST(ClayCut, DeepCutIntoSandDoesNotStall) {
  std::ifstream in(source("scenarios/clay_cut.xml"));
  std::stringstream text;
  text << in.rdbuf();
  std::string xml = text.str();
  const std::string clay = "type=\"clayey_soil_38\" model=\"slippage\"";
  ASSERT_NE(xml.find(clay), std::string::npos);
  xml.replace(xml.find(clay), clay.size(), "type=\"dry_sand\"");
  const fs::path dir = fs::temp_directory_path() / ("skidsim_clay_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "sand_cut.xml") << xml;
  const Played p = play((dir / "sand_cut.xml").string(), source("scenarios/clay_cut.deep.operator.xml"));
  fs::remove_all(dir);
  const nlohmann::json& m = p.report["metrics"];
  EXPECT_LT(m["stall_time_s"].get<double>(), 1.0);  // measured 0
  EXPECT_TRUE(p.stall_times_s().empty()) << p.report["events"].dump();
  double first_fill_kg = 0.0;
  for (const Played::Tick& k : p.first_phase("advance_until_full"))
    first_fill_kg = std::max(first_fill_kg, k.bucket_kg);
  EXPECT_GE(first_fill_kg, 450.0) << "the deep cut fills its bucket in sand";
  std::printf("[ measured ] deep cut in sand: stall_time_s %.2f, %.0f kg in the bucket in the cut, %.1f kg moved\n",
              m["stall_time_s"].get<double>(), first_fill_kg, m["material_moved_kg"].get<double>());
}

}  // namespace
}  // namespace skidsim::session
