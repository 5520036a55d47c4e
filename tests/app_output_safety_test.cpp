// End to end: what a run writes never destroys what skidsim did not create;
// every signal that ends a session keeps its report; lockstep takes only the
// answer for the tick it waits for.
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "skidsim_lcm/control_t.hpp"
#include "skidsim_lcm/state_t.hpp"
#include "tests/app_support.h"

namespace {

namespace fs = std::filesystem;
using skidsim::testing::run_skidsim;

const std::string kScenario = std::string(SKIDSIM_SOURCE_DIR) + "/scenarios/pile_to_zone.xml";
const std::string kScript = std::string(SKIDSIM_SOURCE_DIR) + "/scenarios/pile_to_zone.operator.xml";

std::string read(const fs::path& p) {
  std::ifstream in(p);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// --out naming a user's file or folder: refused before any work, untouched,
// for every job that writes a run directory.
TEST(OutputSafety, OutNeverReplacesAFileOrAForeignFolder) {
  const fs::path root = fs::temp_directory_path() / "skidsim_out_safety";
  fs::remove_all(root);
  fs::create_directories(root / "thesis");
  std::ofstream(root / "thesis" / "chapter1.tex") << "years of work";
  std::ofstream(root / "notes.txt") << "keep me";
  const std::string jobs[] = {"run " + kScenario + " --script " + kScript + " --max-s 0.1",
                              "pour --site-m 2 --pour-s 0.1 --settle-s 0.1", "push --distance-m 0.1"};
  for (const std::string& job : jobs)
    for (const char* target : {"thesis", "notes.txt"}) {
      const auto r = run_skidsim(job + " --out " + (root / target).string());
      EXPECT_EQ(r.exit_code, 2) << job << " --out " << target << ": " << r.output;
      EXPECT_NE(r.output.find(target), std::string::npos) << r.output;
      EXPECT_EQ(read(root / "thesis" / "chapter1.tex"), "years of work");
      EXPECT_EQ(read(root / "notes.txt"), "keep me");
    }
  int entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(root)) ++entries;
  EXPECT_EQ(entries, 2) << "no staging folder left beside them";
  // A run directory skidsim wrote is its own to replace.
  ASSERT_EQ(run_skidsim("pour --site-m 2 --pour-s 0.1 --settle-s 0.1 --out " + (root / "run").string()).exit_code, 0);
  EXPECT_TRUE(fs::exists(root / "run" / ".skidsim-run"));
  EXPECT_EQ(run_skidsim("pour --site-m 2 --pour-s 0.1 --settle-s 0.1 --out " + (root / "run").string()).exit_code, 0);
  fs::remove_all(root);
}

// Ctrl-C, SIGTERM, SIGHUP (terminal closed) and SIGQUIT all end the session
// at the next tick with its report and log written.
class EndingSignal : public ::testing::TestWithParam<const char*> {};

TEST_P(EndingSignal, EndsTheSessionWithItsReport) {
  const fs::path dir = fs::temp_directory_path() / (std::string("skidsim_signal_") + GetParam());
  fs::remove_all(dir);
  const std::string cmd = "sh -c '" + std::string(SKIDSIM_BINARY) + " run " + kScenario + " --script " + kScript +
                          " --mode realtime --out " + dir.string() + " > /dev/null 2>&1 & pid=$!; sleep 2; kill -" +
                          GetParam() + " $pid; wait $pid'";
  EXPECT_EQ(std::system(cmd.c_str()), 0);
  const nlohmann::json report = nlohmann::json::parse(std::ifstream(dir / "report.json"));
  EXPECT_EQ(report["end_reason"], "interrupted");
  EXPECT_GT(report["performance"]["simulated_s"].get<double>(), 0.5);
  EXPECT_TRUE(fs::exists(dir / "session.lcmlog"));
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(Signals, EndingSignal, ::testing::Values("INT", "TERM", "HUP", "QUIT"));

// One command stamped for a far-future tick, then silence: lockstep must not
// take it for every tick to come. It is rejected, and the session ends as
// operator_gone instead of running to its limit with nobody at the controls.
TEST(OutputSafety, LockstepRejectsAFarFutureTickAndEndsWhenNobodyAnswers) {
  const std::string url = "udpm://239.255.76.67:7689?ttl=0";
  const fs::path dir = fs::temp_directory_path() / "skidsim_lockstep_future";
  fs::remove_all(dir);
  const std::string run = std::string(SKIDSIM_BINARY) + " run " + kScenario + " --mode lockstep --session future --lcm '" + url +
                          "' --out " + dir.string() + " > " + (dir.string() + ".out") + " 2>&1; echo $? > " +
                          dir.string() + ".rc";
  fs::remove(dir.string() + ".rc");
  ASSERT_EQ(std::system(("(" + run + ") &").c_str()), 0);
  lcm::LCM lcm(url);
  ASSERT_TRUE(lcm.good());
  bool answered = false;
  struct Handler {
    lcm::LCM* lcm;
    bool* answered;
    void on_state(const lcm::ReceiveBuffer*, const std::string&, const skidsim_lcm::state_t* s) {
      if (*answered) return;
      skidsim_lcm::control_t c{};
      c.sender_id = 77;
      c.seq = 1;
      c.sim_step = s->step + 1000000000;  // far in the future
      c.drive_left = c.drive_right = 1.0;
      c.throttle = 1.0;
      lcm->publish("SKIDSIM_CONTROL@future", &c);
      *answered = true;
    }
  } handler{&lcm, &answered};
  lcm.subscribe("SKIDSIM_STATE@future", &Handler::on_state, &handler);
  const auto start = std::chrono::steady_clock::now();
  while (!answered && std::chrono::steady_clock::now() - start < std::chrono::seconds(30)) lcm.handleTimeout(100);
  ASSERT_TRUE(answered) << "the session published no state";
  while (!fs::exists(dir.string() + ".rc") && std::chrono::steady_clock::now() - start < std::chrono::seconds(120))
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  ASSERT_TRUE(fs::exists(dir.string() + ".rc")) << "the session did not end";
  EXPECT_EQ(read(dir.string() + ".rc"), "0\n") << read(dir.string() + ".out");
  const nlohmann::json report = nlohmann::json::parse(std::ifstream(dir / "report.json"));
  EXPECT_EQ(report["end_reason"], "operator_gone");
  EXPECT_GE(report["controls"]["rejected_tick"].get<int>(), 1);
  EXPECT_EQ(report["controls"]["accepted"], 0);
  EXPECT_LT(report["performance"]["simulated_s"].get<double>(), 1.0);
  fs::remove_all(dir);
  fs::remove(dir.string() + ".rc");
  fs::remove(dir.string() + ".out");
}

TEST(OutputSafety, MaxSZeroIsRefusedNotReadAsNoLimit) {
  const fs::path dir = fs::temp_directory_path() / "skidsim_max_s_zero";
  fs::remove_all(dir);
  const auto r = run_skidsim("run " + kScenario + " --script " + kScript + " --max-s 0 --out " + dir.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--max-s"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir));
}

}  // namespace
