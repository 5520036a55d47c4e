// skidsim bench report: the speed-against-error page is written from one
// command, its numbers from that run: every section there, tables with a row
// per rung and finite numbers, a plot per ladder with a point per row.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/app_support.h"

namespace {

namespace fs = std::filesystem;

std::size_t count(const std::string& s, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = s.find(what); at != std::string::npos; at = s.find(what, at + 1)) ++n;
  return n;
}

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The text from the line starting with `heading` to the next heading of the
// same level (or the end).
std::string section(const std::string& md, const std::string& heading) {
  const std::size_t line = md.find("\n" + heading);
  if (line == std::string::npos) return "";
  const std::size_t at = line + 1;
  const std::string level = heading.substr(0, heading.find(' ') + 1);
  const std::size_t end = md.find("\n" + level, at + heading.size());
  return md.substr(at, end == std::string::npos ? std::string::npos : end - at);
}

// The data rows of the Markdown tables in `text`, each split into its cells.
std::vector<std::vector<std::string>> table_rows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  std::string line;
  bool header_next = true;  // the first row of each table is its header
  while (std::getline(in, line)) {
    if (line.rfind("|", 0) != 0) {
      header_next = true;
      continue;
    }
    if (header_next || line.rfind("|---", 0) == 0) {
      header_next = false;
      continue;
    }
    std::vector<std::string> cells;
    std::stringstream cut(line.substr(1));
    for (std::string cell; std::getline(cut, cell, '|');) {
      const std::size_t from = cell.find_first_not_of(' '), to = cell.find_last_not_of(' ');
      cells.push_back(from == std::string::npos ? "" : cell.substr(from, to - from + 1));
    }
    rows.push_back(cells);
  }
  return rows;
}

bool finite_number(const std::string& cell) {
  char* end = nullptr;
  const double v = std::strtod(cell.c_str(), &end);
  return end != cell.c_str() && std::isfinite(v);
}

TEST(SkidsimBenchReport, WritesThePageAndItsPlots) {
  const fs::path dir = fs::temp_directory_path() / "skidsim_perf_report";
  fs::remove_all(dir);
  const auto r = skidsim::testing::run_skidsim("bench report --quick --out " + (dir / "perf.md").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string md = read(dir / "perf.md");
  EXPECT_NE(md.find("# Speed against error"), std::string::npos);
  EXPECT_EQ(md.find("Not in this page yet"), std::string::npos);

  // Every ladder: a table (or two) with a row per rung (two in a quick run),
  // the error and the cost finite numbers, a reading of the trend with the
  // measured order, and a plot with a point per row.
  struct Ladder {
    const char* heading;
    std::size_t tables;
    std::vector<const char*> svgs;
    const char* tables_end = nullptr;  // where the section's other tables start
  };
  const std::vector<Ladder> ladders = {
      {"## Repose cone", 2, {"perf_repose_slope.svg", "perf_repose_roundness.svg"}},
      {"## Blade push", 1, {"perf_push.svg"}},
      {"## BCRE diffusion", 2, {"perf_bcre_cells.svg", "perf_bcre_substeps.svg"}},
      {"## Plate sinkage", 1, {"perf_plate_sinkage.svg"}},
      {"## Wheels on soft soil", 1, {"perf_wheel_error.svg"}, "At the finest rung"},
      {"## Pressure under a pile", 1, {"perf_pile_load.svg"}},
  };
  for (const Ladder& l : ladders) {
    const std::string s = section(md, l.heading);
    ASSERT_FALSE(s.empty()) << l.heading;
    const auto rows = table_rows(l.tables_end ? s.substr(0, s.find(l.tables_end)) : s);
    EXPECT_EQ(rows.size(), 2 * l.tables) << l.heading << ": two rungs per table";
    for (const auto& row : rows) {
      ASSERT_GE(row.size(), 3u) << l.heading;
      EXPECT_TRUE(finite_number(row[1])) << l.heading << ": error '" << row[1] << "'";
      EXPECT_TRUE(finite_number(row[2])) << l.heading << ": cost '" << row[2] << "'";
      EXPECT_GT(std::strtod(row[2].c_str(), nullptr), 0.0) << l.heading << ": a cost was measured";
    }
    EXPECT_NE(s.find("Reading it:"), std::string::npos) << l.heading;
    EXPECT_NE(s.find("order"), std::string::npos) << l.heading << ": the observed order, from the numbers";
    for (const char* svg : l.svgs) {
      EXPECT_NE(s.find(svg), std::string::npos) << svg;
      EXPECT_EQ(count(read(dir / svg), "<circle"), 2u) << svg << ": a point per rung";
    }
  }
  // The digging forces against the stored DEM runs (dem/blade/results): a
  // row per DEM case (one in a quick run) with the DEM's N, the equation's
  // and skidsim's measured mean, and a point per push on the plot.
  {
    const std::string s = section(md, "## Digging forces against the DEM reference");
    ASSERT_FALSE(s.empty());
    const auto rows = table_rows(s);
    ASSERT_EQ(rows.size(), 1u);
    ASSERT_GE(rows[0].size(), 4u);
    EXPECT_TRUE(finite_number(rows[0][2])) << "equation '" << rows[0][2] << "'";
    EXPECT_GT(std::strtod(rows[0][3].c_str(), nullptr), 0.0) << "skidsim's mean '" << rows[0][3] << "'";
    EXPECT_EQ(count(read(dir / "perf_digging_dem.svg"), "<circle"), 1u);
  }
  // The wheels against the stored DEM runs (dem/wheel/results): a row per
  // run with the DEM's, the closed form's and skidsim's z / D, DP / W and
  // T / (W r), one rung in a quick run, its point on the plot, and the
  // pull, torque and sinkage curves.
  {
    const std::string s = section(md, "## Wheels against the DEM reference");
    ASSERT_FALSE(s.empty());
    const auto rows = table_rows(s);
    ASSERT_EQ(rows.size(), 7u) << "six runs and one rung";
    for (std::size_t k = 0; k < 6; ++k) {
      ASSERT_EQ(rows[k].size(), 4u);
      EXPECT_TRUE(finite_number(rows[k][3])) << "skidsim '" << rows[k][3] << "'";
    }
    EXPECT_GT(std::strtod(rows[6][2].c_str(), nullptr), 0.0) << "a cost was measured";
    EXPECT_EQ(count(read(dir / "perf_wheel_dem_error.svg"), "<circle"), 1u);
    for (const char* svg : {"perf_wheel_dem_pull.svg", "perf_wheel_dem_torque.svg", "perf_wheel_dem_sinkage.svg"})
      EXPECT_NE(s.find(svg), std::string::npos) << svg;
  }
  // The collapsing columns against the stored DEM runs (dem/collapse/results):
  // a row per DEM column with its run-out and height and the automaton's at
  // 10 cm (a quick run), a row per fed heap run with the slopes, a row per
  // aspect ratio against the published run-out law (three soils with the
  // fast flow and alone), a row per tube and material of the friction study
  // (the DEM's and the model's), one rung whose books stayed exact, its
  // point on the error plot and the three curves.
  {
    const std::string s = section(md, "## Collapsing columns against the DEM reference");
    ASSERT_FALSE(s.empty());
    const auto rows = table_rows(s);
    ASSERT_GE(rows.size(), 2u);
    const std::size_t columns = rows.size() - 1;
    std::size_t heap_rows = 0, law_rows = 0, friction_rows = 0;
    for (std::size_t k = 0; k < columns; ++k) {
      if (rows[k].size() == 8u) {  // a, the published run-out, three soils at 10 cm, the same three alone
        ++law_rows;
        for (std::size_t c = 0; c < 8; ++c)
          EXPECT_GT(std::strtod(rows[k][c].c_str(), nullptr), 0.0) << "published law '" << rows[k][c] << "'";
        continue;
      }
      if (rows[k].size() == 5u) {  // the friction study: rolling friction, column, repose, DEM, the model at 10 cm
        ++friction_rows;
        for (std::size_t c : {0u, 2u, 3u, 4u})
          EXPECT_GT(std::strtod(rows[k][c].c_str(), nullptr), 0.0) << "friction study '" << rows[k][c] << "'";
        continue;
      }
      if (rows[k].size() == 4u) {  // the fed heap: Q, the DEM's slope, the automaton's and with the fast flow at 10 cm
        ++heap_rows;
        for (std::size_t c : {0u, 1u, 2u, 3u})
          EXPECT_GT(std::strtod(rows[k][c].c_str(), nullptr), 0.0) << "fed heap '" << rows[k][c] << "'";
        continue;
      }
      ASSERT_EQ(rows[k].size(), 3u) << "column, DEM, automaton at 10 cm";
      EXPECT_GT(std::strtod(rows[k][1].c_str(), nullptr), 0.0) << "DEM run-out '" << rows[k][1] << "'";
      EXPECT_GT(std::strtod(rows[k][2].c_str(), nullptr), 0.0) << "skidsim's run-out '" << rows[k][2] << "'";
    }
    EXPECT_EQ(heap_rows, 7u) << "a row per DEM fed heap run (dem/calibration/results/fed_heap_summary.csv)";
    EXPECT_EQ(law_rows, 4u) << "a row per aspect ratio, 0.5 to 4";
    EXPECT_EQ(friction_rows, 9u) << "a row per tube (a = 0.5, 1, 2) and material (rolling friction 0.3, 0.6, 0.15)";
    EXPECT_GT(std::strtod(rows[columns][2].c_str(), nullptr), 0.0) << "a cost was measured";
    EXPECT_NE(rows[columns][3].find("books exact"), std::string::npos) << rows[columns][3];
    EXPECT_EQ(count(read(dir / "perf_collapse_error.svg"), "<circle"), 1u);
    for (const char* svg : {"perf_collapse_runout.svg", "perf_collapse_height.svg", "perf_collapse_front.svg"})
      EXPECT_NE(s.find(svg), std::string::npos) << svg;
  }
  // The numbers are measured: the coarse cone's flank is off alpha_I by what
  // the run found, the plate sinks to Bekker's depth within 2 %.
  EXPECT_NE(md.find("flank 30."), std::string::npos);
  for (const auto& row : table_rows(section(md, "## Plate sinkage"))) EXPECT_LT(std::strtod(row[1].c_str(), nullptr), 2.0);

  // The thesis's tables beside today's benchmarks: rows with both figures.
  const std::string thesis = section(md, "## The thesis's speed tables, today");
  for (const char* table : {"### Table 7.1", "### Table 7.4"}) {
    const auto rows = table_rows(section(thesis, table));
    EXPECT_EQ(rows.size(), 2u) << table;
    for (const auto& row : rows) {
      EXPECT_TRUE(finite_number(row[1])) << table << ": thesis";
      EXPECT_TRUE(finite_number(row[2])) << table << ": today '" << row[2] << "'";
      EXPECT_GT(std::strtod(row[2].c_str(), nullptr), 0.0) << table;
    }
  }
  const auto push_rows = table_rows(section(thesis, "### Table 7.5"));
  EXPECT_EQ(push_rows.size(), 2u);
  for (const auto& row : push_rows)
    for (std::size_t k = 1; k < row.size(); ++k) EXPECT_EQ(row[k].find("not run"), std::string::npos) << row[k];

  // Whole sessions: a real-time factor per cell size, and table 9.3 with
  // today's figure where the quick run has one.
  const std::string sessions = section(md, "## Whole sessions");
  const auto session_rows = table_rows(sessions.substr(0, sessions.find("### Table 9.3")));
  ASSERT_EQ(session_rows.size(), 2u);
  EXPECT_EQ(session_rows[0][0], "20 cm");
  EXPECT_EQ(session_rows[1][0], "10 cm");
  for (const auto& row : session_rows) {
    EXPECT_TRUE(finite_number(row[1])) << row[1];
    EXPECT_GT(std::strtod(row[1].c_str(), nullptr), 0.0);
  }
  const auto table93 = table_rows(section(sessions, "### Table 9.3"));
  EXPECT_EQ(table93.size(), 6u) << "the thesis's six densities";
  int measured = 0;
  for (const auto& row : table93) measured += finite_number(row[3]) ? 1 : 0;
  EXPECT_EQ(measured, 2) << "5 and 10 cells/m, from the sessions above";

  // Level of detail: both corner sites and the terrain at rest measured.
  const auto lod = table_rows(section(md, "## Level of detail"));
  ASSERT_EQ(lod.size(), 3u);
  for (const auto& row : lod) EXPECT_TRUE(finite_number(row[2].substr(0, row[2].find(' ')))) << row[2];
  EXPECT_NE(section(md, "## Level of detail").find("Measured: the 100 m site's step costs"), std::string::npos);

  // Both ground models on the same cases, from the run: the column in each
  // model at both rungs, the cohesive cut (the slippage model keeps the low
  // cut: nothing slides past its foot), the critical height's ladder, and
  // the bound study finding the first unstable Courant number above 1/2.
  const std::string models = section(md, "## Two ground models");
  ASSERT_FALSE(models.empty());
  const auto column = table_rows(section(models, "### A dry-sand column"));
  ASSERT_EQ(column.size(), 4u);
  for (const auto& row : column) {
    ASSERT_EQ(row.size(), 9u);
    const double flank = std::strtod(row[5].c_str(), nullptr);
    EXPECT_NEAR(flank, row[0] == "slippage" ? 33.0 : 30.0, 1.0) << row[0] << " " << row[1];
    EXPECT_TRUE(finite_number(row[8]));
  }
  const auto cut = table_rows(section(models, "### A vertical cut"));
  ASSERT_EQ(cut.size(), 8u) << "four cuts, then the critical height at four cell sizes";
  EXPECT_EQ(cut[2][0], "slippage");
  EXPECT_EQ(std::strtod(cut[2][3].c_str(), nullptr), 0.0) << "the low cut stands";
  EXPECT_GT(std::strtod(cut[0][3].c_str(), nullptr), 0.0) << "the automaton slumps it";
  EXPECT_GT(std::strtod(cut[4][1].c_str(), nullptr), std::strtod(cut[7][1].c_str(), nullptr))
      << "the critical height's error falls as the cells shrink";
  EXPECT_EQ(table_rows(section(models, "### The slippage model's stability bound")).size(), 5u);
  EXPECT_NE(models.find("above the enforced bound"), std::string::npos);
  EXPECT_EQ(count(read(dir / "perf_ground_models_column.svg"), "<circle"), 4u);
}

}  // namespace
