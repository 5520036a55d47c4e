// `skidsim check`: validates a loader and prints its figures; bad files exit 2
// naming the file.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

#include "tests/app_support.h"

namespace skidsim::testing {
namespace {

TEST(AppCheck, ShippedLoaderIsValidAndInItsClass) {
  const CommandResult r = run_skidsim("check --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = nlohmann::json::parse(r.output);
  EXPECT_EQ(j["mass_kg"].get<double>(), 2650.0);
  EXPECT_EQ(j["wheels"].get<int>(), 4);
  const double ratio = j["static_tipping_load_kg"].get<double>() / j["mass_kg"].get<double>();
  EXPECT_GT(ratio, 0.45);
  EXPECT_LT(ratio, 0.65);
  EXPECT_NEAR(j["hinge_pin_height_m"].get<double>(), 2.80, 0.01);
  EXPECT_NEAR(j["top_speed_km_h"].get<double>(), 11.0, 1e-9);
  EXPECT_NEAR(j["push_force_kN"].get<double>(), 24.9, 2.5);  // S570 class: 2535 kgf
}

TEST(AppCheck, BrokenLoaderExitsTwoNamingTheFile) {
  const auto dir = std::filesystem::temp_directory_path() / "skidsim_check_test";
  std::filesystem::create_directories(dir);
  const auto params = dir / "bad.params.xml";
  std::ofstream(params) << "<loader_parameters urdf=\"missing.urdf\"/>\n";
  const CommandResult r = run_skidsim("check --loader " + params.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("bad.params.xml:1"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("missing.urdf"), std::string::npos) << r.output;
  std::filesystem::remove_all(dir);
}

// A lift cylinder whose pins are given the same coordinates (the child pin
// on the joint's axis: its length never changes) used to pass with a 0 s
// lift; a URDF mass of 1e308 used to be blamed on the tyres.
TEST(AppCheck, DegenerateCylindersAndHugeMassesExitTwoNamingTheElement) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "skidsim_check_degenerate";
  fs::remove_all(dir);
  fs::copy(fs::path(SKIDSIM_SOURCE_DIR) / "assets" / "loader", dir, fs::copy_options::recursive);
  const auto edit = [&](const std::string& name, const std::string& from, const std::string& to) {
    std::ifstream in(dir / name);
    std::string text((std::istreambuf_iterator<char>(in)), {});
    const std::size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    std::ofstream(dir / name, std::ios::trunc) << text;
  };
  const std::string params = (dir / "skidsteer.params.xml").string();
  edit("skidsteer.params.xml", "parent_pin=\"-0.70 0 -0.20\" child_pin=\"0.1197 0 -0.4563\"",
       "parent_pin=\"0 0 0\" child_pin=\"0 0 0\"");
  CommandResult r = run_skidsim("check --loader " + params);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(params + ":27: <cylinder> cylinder 'lift'"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("lift_time_s"), std::string::npos) << r.output;
  edit("skidsteer.params.xml", "parent_pin=\"0 0 0\" child_pin=\"0 0 0\"",
       "parent_pin=\"-0.70 0 -0.20\" child_pin=\"0.1197 0 -0.4563\"");
  ASSERT_EQ(run_skidsim("check --loader " + params).exit_code, 0);
  edit("skidsteer.urdf", "<mass value=\"1900\"/>", "<mass value=\"1e308\"/>");
  r = run_skidsim("check --loader " + params);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("skidsteer.urdf:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("link 'chassis' <inertial><mass>"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("tyre"), std::string::npos) << r.output;
  fs::remove_all(dir);
}

// `skidsim check EXERCISE`: validates the exercise and its loader without
// running; a broken one exits 2 naming the file, the line and the element.
TEST(AppCheck, ExerciseIsValidatedWithoutRunning) {
  const std::string scenario = std::string(SKIDSIM_SOURCE_DIR) + "/scenarios/pile_to_zone.xml";
  const CommandResult ok = run_skidsim("check --json " + scenario);
  ASSERT_EQ(ok.exit_code, 0) << ok.output;
  const nlohmann::json j = nlohmann::json::parse(ok.output);
  EXPECT_EQ(j["exercise"], "pile-to-zone");
  EXPECT_EQ(j["tasks"][0], "move_material move");
  const auto dir = std::filesystem::temp_directory_path() / "skidsim_check_exercise";
  std::filesystem::create_directories(dir);
  const auto bad = dir / "bad.xml";
  std::ofstream(bad) << "<exercise name=\"x\" version=\"1\" time_limit_s=\"60\">\n"
                        "  <site size_m=\"10 10\"/>\n  <machine position=\"3 30\"/>\n</exercise>\n";
  const CommandResult r = run_skidsim("check " + bad.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("bad.xml:3: <machine>"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("off the"), std::string::npos) << r.output;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace skidsim::testing
