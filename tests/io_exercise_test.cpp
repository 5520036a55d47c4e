// The exercise file (docs/exercises.md): the shipped scenario reads whole; a
// corpus of bad files each gets its error naming the file, the line, the
// element and what was expected.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>
#include <vector>

#include "io/atomic_file.h"
#include "io/exercise.h"
#include "io/loader_files.h"
#include "io/operator_script.h"

namespace skidsim::io {
namespace {

namespace fs = std::filesystem;

std::string scenario(const std::string& name) {
  return (fs::path(default_loader_path()).parent_path().parent_path().parent_path() / "scenarios" / name).string();
}

TEST(ExerciseFile, ShippedPileToZoneReadsWhole) {
  const Exercise e = load_exercise(scenario("pile_to_zone.xml"));
  EXPECT_EQ(e.name, "pile-to-zone");
  EXPECT_EQ(e.time_limit_s, 600.0);
  ASSERT_EQ(e.soils.size(), 1u);
  EXPECT_EQ(e.soils[0].soil, "dry_sand");
  EXPECT_EQ(e.soils[0].cell_m, 0.05);
  ASSERT_EQ(e.soils[0].piles.size(), 1u);
  EXPECT_EQ(e.soils[0].piles[0].height_m, 1.0);
  ASSERT_EQ(e.zones.size(), 1u);
  EXPECT_EQ(e.zones[0].region.min(), Eigen::Vector2d(12.0, 8.5));
  EXPECT_TRUE(fs::exists(e.machine.loader));
  EXPECT_EQ(e.operator_source.kind, OperatorSource::Kind::kLcm);
  EXPECT_EQ(e.operator_source.watchdog_s, 0.2);
  ASSERT_EQ(e.tasks.size(), 1u);
  EXPECT_EQ(e.tasks[0].type, Task::Type::kMoveMaterial);
  EXPECT_EQ(e.tasks[0].mass_kg, 800.0);
  EXPECT_EQ(e.events.size(), 2u);
  EXPECT_EQ(e.scoring.metrics.size(), 3u);
  EXPECT_EQ(e.recording.fps, 10.0);
}

// Each case: a change to the shipped file, and the words its error must
// have (the file and line are checked for all).
struct BadCase {
  std::string from, to;
  std::vector<std::string> words;
};

class BrokenExercise : public ::testing::TestWithParam<BadCase> {};

TEST_P(BrokenExercise, ErrorNamesFileLineElementAndExpectation) {
  std::ifstream in(scenario("pile_to_zone.xml"));
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const BadCase& c = GetParam();
  const std::size_t at = text.find(c.from);
  ASSERT_NE(at, std::string::npos) << c.from;
  text.replace(at, c.from.size(), c.to);
  const fs::path dir = fs::temp_directory_path() / ("skidsim_exercise_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path file = dir / "bad.xml";
  std::ofstream(file, std::ios::trunc) << text;
  try {
    load_exercise(file.string());
    FAIL() << "no error for " << c.to;
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(file.string() + ":"), std::string::npos) << msg;
    for (const std::string& w : c.words) EXPECT_NE(msg.find(w), std::string::npos) << "'" << w << "' not in: " << msg;
  }
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(
    Corpus, BrokenExercise,
    ::testing::Values(
        BadCase{"<zone id", "<zon id", {"<zon>", "unknown element"}},
        BadCase{"cell_m=\"0.05\"", "cell_m=\"0.0001\"", {"<soil>", "cell_m", "out of range"}},
        BadCase{"type=\"dry_sand\"", "type=\"wet_sand\"", {"<soil>", "wet_sand", "not a soil"}},
        BadCase{"type=\"dry_sand\"", "type=\"dry_sand\" model=\"mud\"", {"<soil>", "model", "mud", "expected \"automaton\""}},
        BadCase{"fast_flow=\"on\"", "fast_flow=\"yes\"", {"<soil>", "fast_flow", "yes", "expected \"on\""}},
        BadCase{"to=\"target\"", "to=\"targte\"", {"<task>", "targte", "no <zone>"}},
        BadCase{"mass_kg=\"800\"", "mass_kg=\"lots\"", {"<task>", "mass_kg", "expected a number"}},
        BadCase{"type=\"move_material\"", "type=\"dance\"", {"<task>", "dance", "expected drive_course"}},
        BadCase{"region=\"12 8.5 14.5 11.5\"", "region=\"12 8.5 24.5 11.5\"", {"<zone>", "off the"}},
        BadCase{"region=\"12 8.5 14.5 11.5\"", "region=\"14 8.5 12 11.5\"", {"<zone>", "x0 < x1"}},
        BadCase{"position=\"3 10\"", "position=\"3 10\" colour=\"red\"", {"<machine>", "unknown attribute 'colour'"}},
        BadCase{"<machine position=\"3 10\"", "<machine loader=\"nope.params.xml\" position=\"3 10\"",
                {"<machine>", "nope.params.xml", "no such file"}},
        BadCase{"source=\"lcm\"", "source=\"telepathy\"", {"<operator>", "expected lcm or script"}},
        BadCase{"watchdog_ms=\"200\"", "watchdog_ms=\"nan\"", {"<operator>", "watchdog_ms"}},
        BadCase{"name=\"completion_time_s\"", "name=\"style_points\"", {"<metric>", "style_points", "expected one of"}},
        BadCase{"task=\"move\"", "task=\"mvoe\"", {"<event>", "mvoe", "no <task>"}},
        BadCase{"camera=\"chase\"", "camera=\"drone\"", {"<record>", "drone"}},
        BadCase{"camera=\"chase\"", "camera=\"fixed\" fixed_eye=\"0 0 5\"", {"<record>", "both fixed_eye and fixed_target"}},
        BadCase{"camera=\"chase\"", "camera=\"fixed\" fixed_eye=\"0 0 5\" fixed_target=\"0 0 5\"", {"<record>", "same point"}},
        BadCase{"<pile centre=\"8 10\"", "<pile centre=\"30 10\"", {"<pile>", "outside its soil region"}},
        BadCase{"  <task id=\"move\" type=\"move_material\" from=\"yard\" to=\"target\" mass_kg=\"800\"/>\n"
                "  <event when=\"time\" at_s=\"0\" message=\"Fill the bucket at the pile and dump the sand in the marked "
                "zone.\"/>\n  <event when=\"task_done\" task=\"move\" message=\"Done: 800 kg in the zone.\"/>\n",
                "", {"at least one <task>"}},
        BadCase{"</exercise>", "", {"XML"}},
        BadCase{"    <zone id=\"target\"", "    <soil id=\"yard2\" region=\"1 1 3 3\" cell_m=\"0.05\" depth_m=\"0.1\" type=\"dry_sand\"/>\n    <zone id=\"target\"",
                {"<soil>", "one <soil> per exercise"}},
        BadCase{"  </site>", "    <truck id=\"t\" back_corner=\"18 10\" length_m=\"4\" width_m=\"2\" floor_height_m=\"1\" wall_height_m=\"0.3\"/>\n  </site>",
                {"<truck>", "the truck bed", "off the"}},
        BadCase{"  </site>", "    <box id=\"b\" centre=\"3.5 10 0.5\" size=\"1 1 1\"/>\n  </site>",
                {"<machine>", "within 1 m of box 'b'"}},
        BadCase{"firm_ground=\"true\"", "firm_ground=\"false\"", {"<machine>", "neither firm ground nor soil"}},
        BadCase{"  </site>", "    <agent id=\"w\" kind=\"robot\" route=\"1 1\"/>\n  </site>", {"<agent>", "expected person or truck"}},
        BadCase{"  </site>", "    <agent id=\"w\" kind=\"person\" route=\"1 1\" start_after=\"mvoe\"/>\n  </site>", {"<agent>", "start_after", "no <task>"}},
        BadCase{"  </site>", "    <agent id=\"w\" kind=\"person\" route=\"1 1; 30 1\"/>\n  </site>", {"<agent>", "route", "off the site"}},
        BadCase{"  </site>", "    <agent id=\"w\" kind=\"person\" route=\"1 1; 2\"/>\n  </site>", {"<agent>", "route", "is not a point"}},
        BadCase{"  </site>", "    <agent id=\"w\" kind=\"person\" route=\"1 1\" speed_m_s=\"9\"/>\n  </site>", {"<agent>", "speed_m_s"}},
        BadCase{"  </site>", "    <agent id=\"t\" kind=\"truck\" bed=\"nope\" route=\"30 1\"/>\n  </site>", {"<agent>", "no <truck> with that id"}},
        BadCase{"  </site>",
                "    <truck id=\"b\" back_corner=\"15 2\" length_m=\"2\" width_m=\"1.5\" floor_height_m=\"0.9\" wall_height_m=\"0.3\"/>\n"
                "    <agent id=\"t\" kind=\"truck\" bed=\"b\" route=\"30 1\" leave_at_kg=\"100\"/>\n  </site>",
                {"<agent>", "leave_at_kg", "exit"}},
        // Every number has a range where it enters, not only a finite value.
        BadCase{"position=\"3 10\" yaw_deg=\"0\"", "position=\"3 10\" yaw_deg=\"1e308\"", {"<machine>", "yaw_deg", "out of range"}},
        BadCase{"position=\"3 10\"", "position=\"1e300 10\"", {"<machine>", "position", "out of range"}},
        BadCase{"region=\"12 8.5 14.5 11.5\"", "region=\"-1e308 8.5 14.5 11.5\"", {"<zone>", "region", "out of range"}},
        BadCase{"  </site>", "    <agent id=\"w\" kind=\"person\" route=\"1 1; 1e300 2\"/>\n  </site>", {"<agent>", "route", "is not a point"}},
        BadCase{"pass_score=\"25\"", "pass_score=\"1e300\"", {"<scoring>", "pass_score", "out of range"}},
        // Content where none belongs is refused, not ignored.
        BadCase{"<zone id=\"target\" region=\"12 8.5 14.5 11.5\"/>",
                "<zone id=\"target\" region=\"12 8.5 14.5 11.5\"><zone id=\"inner\" region=\"1 1 2 2\"/></zone>",
                {"<zone>", "unexpected element inside <zone>"}},
        BadCase{"<zone id=\"target\" region=\"12 8.5 14.5 11.5\"/>",
                "<zone id=\"target\" region=\"12 8.5 14.5 11.5\">twelve</zone>", {"<zone>", "unexpected text"}},
        // Not UTF-8, or not text at all.
        BadCase{"name=\"pile-to-zone\"", "name=\"pile-\xff-zone\"", {"invalid UTF-8 at byte"}},
        BadCase{"name=\"pile-to-zone\"", "name=\"pile-\xc0\xaf-zone\"", {"invalid UTF-8"}},
        BadCase{"name=\"pile-to-zone\"", std::string("name=\"pile-\0-zone\"", 18), {"NUL byte"}}));

// What is not a regular file is named as such, never read (a device would
// never end) nor called missing.
TEST(ExerciseFile, NotARegularFileIsNamedAsSuch) {
  const fs::path dir = fs::temp_directory_path() / ("skidsim_notfile_" + std::to_string(::getpid()));
  fs::create_directories(dir / "folder.xml");
  const auto message = [](const std::string& path) {
    try {
      load_exercise(path);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message((dir / "folder.xml").string()).find("is a directory"), std::string::npos);
  EXPECT_NE(message("/dev/zero").find("not a regular file"), std::string::npos);
  EXPECT_NE(message((dir / "absent.xml").string()).find("no such file"), std::string::npos);
  std::ofstream(dir / "empty.xml").flush();
  const std::string empty = message((dir / "empty.xml").string());
  EXPECT_NE(empty.find((dir / "empty.xml").string()), std::string::npos) << empty;
  fs::remove_all(dir);
}

// A phase nested in a phase was ignored: the operator would skip it.
TEST(OperatorScriptFile, APhaseInsideAPhaseIsRefused) {
  const fs::path dir = fs::temp_directory_path() / ("skidsim_script_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path file = dir / "nested.operator.xml";
  std::ofstream(file) << "<operator_script name=\"n\">\n  <hold duration_s=\"1\">\n    <wait duration_s=\"5\"/>\n"
                         "  </hold>\n</operator_script>\n";
  try {
    load_operator_script(file.string());
    ADD_FAILURE() << "a nested phase was accepted";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(file.string() + ":3: <wait>"), std::string::npos) << msg;
    EXPECT_NE(msg.find("inside <hold>"), std::string::npos) << msg;
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace skidsim::io
