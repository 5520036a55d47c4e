// End to end: the skidsim command runs the pour job and writes a complete run
// directory; bad input gives a clear message and a non-zero exit.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "io/heightmap.h"
#include "tests/app_support.h"

namespace {

namespace fs = std::filesystem;

using Result = skidsim::testing::CommandResult;

Result run(const std::string& args) { return skidsim::testing::run_skidsim(args); }

TEST(SkidsimPour, WritesARunDirectory) {
  const fs::path dir = fs::temp_directory_path() / "skidsim_pour_e2e";
  fs::remove_all(dir);
  const Result r = run("pour --out " + dir.string() + " --site-m 3 --cell-m 0.05 --pour-s 3 --rate-kg-s 100 --settle-s 20");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json summary = nlohmann::json::parse(std::ifstream(dir / "summary.json"));
  EXPECT_TRUE(summary["result"]["ledger_balanced"].get<bool>());
  EXPECT_TRUE(summary["result"]["at_rest"].get<bool>());
  EXPECT_NEAR(summary["pour"]["poured_kg"].get<double>(), 300.0, 0.01);
  EXPECT_NEAR(summary["result"]["material_in_cells_kg"].get<double>(), summary["pour"]["poured_kg"].get<double>(), 1e-6);
  // A 300 kg pile of dry sand stands at about the stop angle.
  EXPECT_NEAR(summary["result"]["pile_flank_slope_deg"].get<double>(), summary["soil"]["stop_angle_deg"].get<double>(), 2.0);
  const skidsim::io::Heightmap surface = skidsim::io::read_heightmap((dir / "terrain_surface.json").string());
  EXPECT_EQ(surface.nx, 60);
  EXPECT_EQ(surface.quantity, "surface");
  EXPECT_NEAR(*std::max_element(surface.height_m.begin(), surface.height_m.end()),
              summary["result"]["pile_apex_m"].get<double>(), 1e-3);
  EXPECT_TRUE(fs::exists(dir / "terrain_material.png"));
  fs::remove_all(dir);
}

TEST(SkidsimPour, SameJobTwiceGivesIdenticalTerrain) {
  const fs::path a = fs::temp_directory_path() / "skidsim_pour_det_a";
  const fs::path b = fs::temp_directory_path() / "skidsim_pour_det_b";
  for (const auto& d : {a, b}) {
    fs::remove_all(d);
    ASSERT_EQ(run("pour --out " + d.string() + " --site-m 2 --pour-s 2 --settle-s 5").exit_code, 0);
  }
  const auto bytes = [](const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  EXPECT_EQ(bytes(a / "terrain_material.png"), bytes(b / "terrain_material.png"));
  EXPECT_EQ(bytes(a / "terrain_material.json"), bytes(b / "terrain_material.json"));
  fs::remove_all(a);
  fs::remove_all(b);
}

TEST(SkidsimPour, ContinuesFromAnExportedTerrain) {
  // Export a pile, import it as the initial terrain of a second pour: the
  // second run starts from the first's material and adds its own.
  const fs::path first = fs::temp_directory_path() / "skidsim_pour_first";
  const fs::path second = fs::temp_directory_path() / "skidsim_pour_second";
  fs::remove_all(first);
  fs::remove_all(second);
  ASSERT_EQ(run("pour --out " + first.string() + " --site-m 2 --pour-s 2 --settle-s 5").exit_code, 0);
  const Result r = run("pour --out " + second.string() + " --material-map " + (first / "terrain_material.json").string() +
                       " --pour-s 2 --settle-s 5");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto summary_of = [](const fs::path& d) { return nlohmann::json::parse(std::ifstream(d / "summary.json")); };
  const auto a = summary_of(first), b = summary_of(second);
  // The import rounds each cell to half a 16-bit step of the exported map.
  const double step_kg = 0.5 * a["files"]["material_vertical_scale_m"].get<double>() * 0.05 * 0.05 *
                         a["soil"]["bulk_density_kg_m3"].get<double>() * 40 * 40;
  EXPECT_NEAR(b["result"]["material_in_cells_kg"].get<double>(),
              a["result"]["material_in_cells_kg"].get<double>() + b["pour"]["poured_kg"].get<double>(), step_kg);
  EXPECT_GT(b["result"]["pile_apex_m"].get<double>(), a["result"]["pile_apex_m"].get<double>());
  // A surface map is not a material map.
  const Result bad = run("pour --out " + second.string() + " --material-map " + (first / "terrain_surface.json").string());
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("quantity"), std::string::npos) << bad.output;
  fs::remove_all(first);
  fs::remove_all(second);
}

TEST(SkidsimPour, BadInputIsReportedWithANonZeroExit) {
  Result r = run("pour --soil moon_dust --out /tmp/skidsim_never");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("moon_dust"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("dry_sand"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists("/tmp/skidsim_never/summary.json"));

  // Each bad option: a non-zero exit and a message that names the problem.
  struct BadCase {
    const char* args;
    const char* says;
  };
  for (const BadCase& c : {BadCase{"--cell-m -1", "cell-m"},
                           BadCase{"--cell-m 0.001 --site-m 0.1", "sub-steps"},  // sweep would need too many
                           BadCase{"--site-m 0.01", "--site-m"},
                           BadCase{"--site-m 1e6 --cell-m 0.001", "expected 3 to 16384"},
                           BadCase{"--layer-m 1e10", "layer-m"}}) {
    r = run(std::string("pour ") + c.args + " --out /tmp/skidsim_never");
    EXPECT_NE(r.exit_code, 0) << c.args;
    EXPECT_NE(r.output.find(c.says), std::string::npos) << c.args << ": " << r.output;
  }
  EXPECT_FALSE(fs::exists("/tmp/skidsim_never"));

  const fs::path bad = fs::temp_directory_path() / "skidsim_bad_table.xml";
  std::ofstream(bad) << "<soils>\n  <soil id=\"x\">\n    <flow bulk_density_kg_m3=\"-5\"/>\n  </soil>\n</soils>\n";
  r = run("pour --soil-table " + bad.string() + " --out /tmp/skidsim_never");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find(bad.string() + ":2"), std::string::npos) << r.output;
  fs::remove(bad);
}

TEST(SkidsimPour, AFailedRunLeavesThePreviousResultsWhole) {
  const fs::path dir = fs::temp_directory_path() / "skidsim_pour_keep";
  fs::remove_all(dir);
  ASSERT_EQ(run("pour --out " + dir.string() + " --site-m 2 --pour-s 1 --settle-s 2").exit_code, 0);
  const auto before = nlohmann::json::parse(std::ifstream(dir / "summary.json"));
  // Fails part-way through the pour (the column limit), after the run began.
  const Result r = run("pour --out " + dir.string() + " --site-m 2 --rate-kg-s 1e12 --pour-s 1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--rate-kg-s"), std::string::npos) << r.output;
  EXPECT_EQ(nlohmann::json::parse(std::ifstream(dir / "summary.json")), before);
  EXPECT_NO_THROW(skidsim::io::read_heightmap((dir / "terrain_material.json").string()));
  for (const auto& entry : fs::directory_iterator(dir.parent_path()))
    EXPECT_EQ(entry.path().filename().string().find("skidsim_pour_keep."), std::string::npos) << entry.path();
  fs::remove_all(dir);
}

TEST(SkidsimPour, OutOfRangeHeightMapsNameTheFile) {
  const fs::path dir = fs::temp_directory_path() / "skidsim_pour_hm";
  fs::remove_all(dir);
  ASSERT_EQ(run("pour --out " + dir.string() + " --site-m 1 --pour-s 1 --settle-s 1").exit_code, 0);
  nlohmann::json meta = nlohmann::json::parse(std::ifstream(dir / "terrain_material.json"));
  meta["z_offset_m"] = 1e10;
  meta["image"] = (dir / "terrain_material.png").string();
  const fs::path deep = fs::temp_directory_path() / "skidsim_deep_material.json";
  std::ofstream(deep) << meta.dump();
  const Result r = run("pour --out " + (dir / "again").string() + " --material-map " + deep.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find(deep.string()), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("material depth"), std::string::npos) << r.output;
  fs::remove(deep);
  fs::remove_all(dir);
}

// Every field of an imported height map is checked where it enters: a cell
// of 1e308 m once gave NaN masses and a "balanced" ledger; a side past the
// site cap, or a PNG header that disagrees with the metadata, is refused
// before anything is allocated for it.
TEST(SkidsimPour, HeightMapFieldsOutOfRangeAreRefusedNamingTheField) {
  const fs::path dir = fs::temp_directory_path() / "skidsim_pour_fields";
  fs::remove_all(dir);
  ASSERT_EQ(run("pour --out " + dir.string() + " --site-m 1 --pour-s 1 --settle-s 1").exit_code, 0);
  const nlohmann::json good = nlohmann::json::parse(std::ifstream(dir / "terrain_material.json"));
  struct BadField {
    const char* field;
    nlohmann::json value;
    const char* says;
  };
  for (const BadField& c : {BadField{"cell_size_m", 1e308, "out of range"}, BadField{"cell_size_m", "NaN", "expected a number"},
                            BadField{"nx", 20000, "16384"}, BadField{"origin_m", {0.0, -1e308}, "out of range"},
                            BadField{"vertical_scale_m", 1e308, "out of range"}}) {
    nlohmann::json meta = good;
    meta[c.field] = c.value;
    meta["image"] = (dir / "terrain_material.png").string();
    const fs::path bad = dir / "bad_material.json";
    std::ofstream(bad, std::ios::trunc) << meta.dump();
    const Result r = run("pour --out " + (dir / "again").string() + " --material-map " + bad.string());
    EXPECT_EQ(r.exit_code, 2) << c.field << ": " << r.output;
    EXPECT_NE(r.output.find(bad.string() + ": field '" + c.field + "'"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(c.says), std::string::npos) << r.output;
  }
  EXPECT_FALSE(fs::exists(dir / "again"));
  fs::remove_all(dir);
}

TEST(SkidsimCommand, HelpListsTheSubcommands) {
  const Result r = run("--help");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* sub : {"pour", "bench", "soils"}) EXPECT_NE(r.output.find(sub), std::string::npos) << r.output;
}

TEST(SkidsimCommand, BenchRunsAndSpeaksJson) {
  const Result r = run("bench --json --filter 'BM_AllActiveSweep/30$' --min-time 0.01");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto start = r.output.find('{');
  ASSERT_NE(start, std::string::npos) << r.output;
  const nlohmann::json j = nlohmann::json::parse(r.output.substr(start));
  ASSERT_EQ(j["benchmarks"].size(), 1u);
  EXPECT_GT(j["benchmarks"][0]["per_cell"].get<double>(), 0.0);
}

}  // namespace
