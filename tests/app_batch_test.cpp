// skidsim batch: sessions from a list run side by side, each a process of
// its own into its own run directory; the same session gives the same
// final state alone or in a batch; one entry alone (a cluster array task);
// bad lists refused naming file and line, nothing run.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "tests/app_support.h"

namespace {

namespace fs = std::filesystem;
using skidsim::testing::run_skidsim;

const std::string kSrc = SKIDSIM_SOURCE_DIR;

TEST(SkidsimBatch, RunsTheListSideBySideAndSumsUp) {
  const fs::path dir = fs::temp_directory_path() / "skidsim_batch";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "list.txt") << "# three sessions\n"
                                  << kSrc << "/scenarios/driving_course.xml --script " << kSrc << "/scenarios/driving_course.operator.xml\n\n"
                                  << kSrc << "/scenarios/pile_to_zone.xml --script " << kSrc
                                  << "/scenarios/pile_to_zone.operator.xml --max-s 8  # a piece of it\n"
                                  << kSrc << "/scenarios/grading.xml --script " << kSrc << "/scenarios/grading.operator.xml\n";
  const auto r = run_skidsim("batch " + (dir / "list.txt").string() + " --jobs 2 --out " + (dir / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json batch = nlohmann::json::parse(std::ifstream(dir / "out" / "batch.json"));
  ASSERT_EQ(batch["sessions"].size(), 3u);
  EXPECT_EQ(batch["jobs"], 2);
  EXPECT_EQ(batch["sessions"][0]["run_dir"], "001_driving_course");
  EXPECT_TRUE(batch["sessions"][0]["passed"].get<bool>());
  EXPECT_EQ(batch["sessions"][1]["line"], 4);
  EXPECT_FALSE(batch["sessions"][1]["passed"].get<bool>()) << "8 s is not the whole task";
  EXPECT_TRUE(batch["sessions"][2]["passed"].get<bool>());
  for (const auto& s : batch["sessions"]) {
    EXPECT_EQ(s["exit_code"], 0);
    EXPECT_TRUE(fs::exists(dir / "out" / s["run_dir"].get<std::string>() / "report.json"));
  }
  // The same session alone: the same final state.
  const auto alone = run_skidsim("run " + kSrc + "/scenarios/pile_to_zone.xml --script " + kSrc +
                                 "/scenarios/pile_to_zone.operator.xml --max-s 8 --out " + (dir / "alone").string());
  ASSERT_EQ(alone.exit_code, 0) << alone.output;
  const nlohmann::json report = nlohmann::json::parse(std::ifstream(dir / "alone" / "report.json"));
  EXPECT_EQ(batch["sessions"][1]["final_state_hash"], report["final_state_hash"]);
  // One entry alone, as a cluster's array task runs it.
  const auto one = run_skidsim("batch " + (dir / "list.txt").string() + " --index 3 --out " + (dir / "array").string());
  ASSERT_EQ(one.exit_code, 0) << one.output;
  EXPECT_TRUE(fs::exists(dir / "array" / "003_grading" / "report.json"));
  EXPECT_FALSE(fs::exists(dir / "array" / "001_driving_course"));
  EXPECT_TRUE(fs::exists(dir / "array" / "batch_3.json"));
}

TEST(SkidsimBatch, BadListsAreRefusedNamingTheLine) {
  const fs::path dir = fs::temp_directory_path() / "skidsim_batch_bad";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string good = kSrc + "/scenarios/grading.xml --script " + kSrc + "/scenarios/grading.operator.xml";
  const std::pair<std::string, std::string> cases[] = {
      {good + "\n" + kSrc + "/scenarios/nope.xml --script x\n", "list.txt:2: "},
      {good + " --out elsewhere\n", "the batch sets"},
      {kSrc + "/scenarios/grading.xml\n", "needs --script or --replay"},
      {"# nothing\n", "no sessions"},
      // Its words become arguments and go into batch.json: text only.
      {good + "\n# caf\xe9\n", "list.txt:2: invalid UTF-8"},
      {good + "\n" + std::string("x\0y", 3) + "\n", "list.txt:2: a NUL byte"},
  };
  for (const auto& [text, expected] : cases) {
    std::ofstream(dir / "list.txt") << text;
    const auto r = run_skidsim("batch " + (dir / "list.txt").string() + " --out " + (dir / "out").string());
    EXPECT_EQ(r.exit_code, 2) << text << r.output;
    EXPECT_NE(r.output.find(expected), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "out")) << "nothing run";
  }
  std::ofstream(dir / "list.txt") << good << "\n";
  EXPECT_EQ(run_skidsim("batch " + (dir / "list.txt").string() + " --index 2 --out " + (dir / "out").string()).exit_code, 2);
  // Read as a checked file: a folder or a device is no list.
  for (const std::string& list : {dir.string(), std::string("/dev/zero")}) {
    const auto r = run_skidsim("batch " + list + " --out " + (dir / "out").string());
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("batch list " + list), std::string::npos) << r.output;
  }
}

}  // namespace
