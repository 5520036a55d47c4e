// End to end: `skidsim push` pushes a blade through soil and records the
// resistance along the push (thesis fig. 7.12); bad options are refused.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "tests/app_support.h"

namespace {

namespace fs = std::filesystem;
using skidsim::testing::run_skidsim;

TEST(SkidsimPush, RecordsTheResistanceAlongThePush) {
  const fs::path dir = fs::temp_directory_path() / "skidsim_push_e2e";
  fs::remove_all(dir);
  const auto r = run_skidsim("push --out " + dir.string() + " --cells-per-m 10 --distance-m 1.5 --depth-m 0.2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json summary = nlohmann::json::parse(std::ifstream(dir / "summary.json"));
  EXPECT_TRUE(summary["result"]["ledger_balanced"].get<bool>());
  const double flat = summary["reference"]["flat_ground_wedge_N"].get<double>();
  EXPECT_NEAR(summary["result"]["resistance_at_start_N"].get<double>(), flat, 0.05 * flat);
  EXPECT_GT(summary["result"]["resistance_at_end_N"].get<double>(), 2.0 * flat);
  EXPECT_TRUE(fs::exists(dir / "terrain_surface.png"));
  // resistance.csv: a header, then rows every 2 cm of travel.
  std::ifstream csv(dir / "resistance.csv");
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line.rfind("distance_m,resistance_N", 0), 0u);
  std::vector<double> distance;
  while (std::getline(csv, line)) distance.push_back(std::stod(line.substr(0, line.find(','))));
  ASSERT_GE(distance.size(), 70u);
  for (std::size_t k = 1; k < distance.size(); ++k) EXPECT_GT(distance[k], distance[k - 1]);
  EXPECT_NEAR(distance.back(), 1.5, 1e-6);
}

TEST(SkidsimPush, BadOptionsAreRefusedNamingTheOption) {
  const fs::path dir = fs::temp_directory_path() / "skidsim_push_bad";
  fs::remove_all(dir);
  struct Case {
    std::string args, expected;
  };
  for (const Case& c : {Case{"--depth-m 0.5 --layer-m 0.4", "--depth-m"}, Case{"--cells-per-m 0.5", "--cells-per-m"},
                        Case{"--speed-m-s -1", "--speed-m-s"}, Case{"--speed-m-s 1e-9", "--speed-m-s"},
                        Case{"--width-m 1e-300", "--width-m"}, Case{"--cells-per-m abc", "--cells-per-m"},
                        Case{"--depth-m nan", "--depth-m"}, Case{"--soil mud", "mud"}}) {
    const auto r = run_skidsim("push --out " + dir.string() + " " + c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_FALSE(fs::exists(dir)) << c.args;
  }
}

TEST(SkidsimPush, RunDirectoryNamesAreCheckedAndATrailingSlashIsFine) {
  const fs::path dir = fs::temp_directory_path() / "skidsim_push_slash";
  fs::remove_all(dir);
  const auto ok = run_skidsim("push --distance-m 0.1 --cells-per-m 10 --out " + dir.string() + "/");
  ASSERT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_TRUE(fs::exists(dir / "summary.json"));
  for (const std::string out : {"\".\"", "\"\"", "\"..\""}) {
    const auto bad = run_skidsim("push --distance-m 0.1 --out " + out);
    EXPECT_EQ(bad.exit_code, 2) << out << "\n" << bad.output;
    EXPECT_NE(bad.output.find("--out"), std::string::npos) << bad.output;
  }
}

}  // namespace
