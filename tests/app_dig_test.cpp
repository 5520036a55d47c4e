// End to end: `skidsim dig` fills the bucket from a bank, carries the load
// to a truck bed and dumps it there, every gram accounted for; twice, the
// same files; bad options are refused.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "tests/app_support.h"

namespace {

namespace fs = std::filesystem;
using skidsim::testing::run_skidsim;

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(SkidsimDig, FillsCarriesAndDumpsIntoTheTruck) {
  const fs::path dir = fs::temp_directory_path() / "skidsim_dig_e2e";
  fs::remove_all(dir);
  const auto r = run_skidsim("dig --out " + dir.string() + " --cells-per-m 10");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json summary = nlohmann::json::parse(std::ifstream(dir / "summary.json"));
  const nlohmann::json& result = summary["result"];
  EXPECT_TRUE(result["completed"].get<bool>()) << "every phase must reach its goal";
  EXPECT_TRUE(result["timed_out_phases"].empty()) << result["timed_out_phases"].dump();
  EXPECT_TRUE(result["material_conserved_every_step"].get<bool>());
  EXPECT_TRUE(result["machine_finite"].get<bool>());
  EXPECT_FALSE(result["tipped_over"].get<bool>());
  const double heaped = summary["loader"]["bucket_heaped_kg"].get<double>();
  EXPECT_GT(result["bucket_full_kg"].get<double>(), 0.7 * heaped) << "the bucket must fill";
  EXPECT_GT(result["bucket_at_truck_kg"].get<double>(), 0.6 * heaped) << "it must carry its load";
  EXPECT_GT(result["truck_kg"].get<double>(), 0.9 * result["bucket_at_truck_kg"].get<double>())
      << "the load must land in the truck bed";
  EXPECT_LT(result["left_in_bucket_kg"].get<double>(), 5.0);
  for (const char* f : {"phases.csv", "terrain_surface.png", "terrain_surface.json", "truck_material.png"})
    EXPECT_TRUE(fs::exists(dir / f)) << f;
  // Deterministic: the same job again gives the same files.
  const fs::path again = fs::temp_directory_path() / "skidsim_dig_e2e_again";
  fs::remove_all(again);
  ASSERT_EQ(run_skidsim("dig --out " + again.string() + " --cells-per-m 10").exit_code, 0);
  EXPECT_EQ(read(dir / "phases.csv"), read(again / "phases.csv"));
  EXPECT_EQ(read(dir / "terrain_surface.png"), read(again / "terrain_surface.png"));
  EXPECT_EQ(read(dir / "truck_material.png"), read(again / "truck_material.png"));
}

TEST(SkidsimDig, BadOptionsAreRefusedNamingTheOption) {
  const fs::path dir = fs::temp_directory_path() / "skidsim_dig_bad";
  fs::remove_all(dir);
  for (const auto& [args, expected] : {std::pair<std::string, std::string>{"--cells-per-m 5", "--cells-per-m"},
                                       {"--bank-m 0", "--bank-m"},
                                       {"--soil nope", "--soil 'nope'"},
                                       {"--loader /nonexistent.xml", "/nonexistent.xml"}}) {
    const auto r = run_skidsim("dig --out " + dir.string() + " " + args);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.output;
    EXPECT_NE(r.output.find(expected), std::string::npos) << args << ": " << r.output;
    EXPECT_FALSE(fs::exists(dir)) << "a refused job must write nothing";
  }
}

}  // namespace
