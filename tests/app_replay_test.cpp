// End to end: the session log a replay reads (`skidsim run --replay`,
// `skidsim review --fps`) is checked whole before anything runs, and
// belongs to the exercise it was recorded from (session/session_replay.h):
// damaged logs, /dev/zero and logs of another exercise are refused with
// exit 2, naming the byte or both exercises, never crashing or hanging.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "io/lcm_log.h"
#include "tests/app_support.h"

namespace {

namespace fs = std::filesystem;
using skidsim::testing::run_skidsim;

const std::string kScenario = std::string(SKIDSIM_SOURCE_DIR) + "/scenarios/pile_to_zone.xml";
const std::string kScript = std::string(SKIDSIM_SOURCE_DIR) + "/scenarios/pile_to_zone.operator.xml";

std::string slurp_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void put_be32(std::string& bytes, std::size_t at, std::uint32_t v) {
  for (int k = 3; k >= 0; --k, v >>= 8) bytes[at + static_cast<std::size_t>(k)] = static_cast<char>(v & 0xFF);
}

// skidsim with a time limit: a hang is exit 124, not a test that never ends.
skidsim::testing::CommandResult run_skidsim_within(int seconds, const std::string& args) {
  return skidsim::testing::run_command("timeout " + std::to_string(seconds) + " " + std::string(SKIDSIM_BINARY) + " " + args);
}

// A damaged log never reaches liblcm: a channel or data length of
// 0x7fffffff (which crashed LCM 1.3.1's reader inside run --replay and
// review) is refused naming the byte, exit 2, by both; /dev/zero (on which
// LCM's reader never returned) at once.
TEST(SkidsimReplay, ADamagedLogIsRefusedByReplayAndReviewWithoutACrash) {
  const fs::path rec = fs::temp_directory_path() / "skidsim_run_damaged_rec";
  const fs::path out = fs::temp_directory_path() / "skidsim_run_damaged_out";
  fs::remove_all(rec);
  fs::remove_all(out);
  ASSERT_EQ(run_skidsim("run " + kScenario + " --script " + kScript + " --max-s 2 --out " + rec.string()).exit_code, 0);
  const fs::path log_path = rec / "session.lcmlog";
  const std::string good = slurp_bytes(log_path);
  const skidsim::io::LcmLog log = skidsim::io::read_lcm_log(log_path.string(), nullptr);
  ASSERT_GT(log.event_count, 10u);
  // The offsets of the events: the third one's lengths are damaged.
  std::vector<std::size_t> starts;
  for (std::size_t at = 0; at < good.size();) {
    starts.push_back(at);
    const auto be32 = [&](std::size_t k) {
      return static_cast<std::uint32_t>(static_cast<unsigned char>(good[k])) << 24 |
             static_cast<std::uint32_t>(static_cast<unsigned char>(good[k + 1])) << 16 |
             static_cast<std::uint32_t>(static_cast<unsigned char>(good[k + 2])) << 8 | static_cast<unsigned char>(good[k + 3]);
    };
    at += 28 + be32(at + 20) + be32(at + 24);
  }
  for (const int field : {20, 24}) {  // channel length, data length
    std::string bad = good;
    put_be32(bad, starts[2] + field, 0x7fffffff);
    std::ofstream(log_path, std::ios::binary | std::ios::trunc) << bad;
    const std::string expected = log_path.string() + ": byte " + std::to_string(starts[2] + field) + ": event 2: " +
                                 (field == 20 ? "channel length 2147483647, expected 1 to 256 bytes"
                                              : "data length 2147483647 runs past the end of the file");
    const auto replay = run_skidsim_within(120, "run " + kScenario + " --replay " + log_path.string() + " --out " + out.string());
    EXPECT_EQ(replay.exit_code, 2) << replay.output;
    EXPECT_NE(replay.output.find(expected), std::string::npos) << replay.output;
    EXPECT_FALSE(fs::exists(out));
    // review replays the log to render it again: the same refusal, nothing kept.
    const auto review = run_skidsim_within(120, "review " + rec.string() + " --fps 5 --width 160 --height 90 --backend osmesa");
    EXPECT_EQ(review.exit_code, 2) << review.output;
    EXPECT_NE(review.output.find(expected), std::string::npos) << review.output;
    EXPECT_FALSE(fs::exists(rec / "frames_chase_5fps"));
    EXPECT_FALSE(fs::exists(rec / ".review_replay"));
  }
  // /dev/zero, a folder: refused at once.
  const auto start = std::chrono::steady_clock::now();
  const auto zero = run_skidsim_within(60, "run " + kScenario + " --replay /dev/zero --out " + out.string());
  EXPECT_EQ(zero.exit_code, 2) << zero.output;
  EXPECT_NE(zero.output.find("/dev/zero: not a regular file"), std::string::npos) << zero.output;
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(20));
  const auto folder = run_skidsim_within(60, "run " + kScenario + " --replay " + rec.string() + " --out " + out.string());
  EXPECT_EQ(folder.exit_code, 2) << folder.output;
  EXPECT_NE(folder.output.find("is a directory"), std::string::npos) << folder.output;
  // A log cut at an event's boundary (whole events, but not the session's
  // end): refused, not replayed short.
  std::ofstream(log_path, std::ios::binary | std::ios::trunc) << good.substr(0, starts.back());
  const auto cut = run_skidsim_within(120, "run " + kScenario + " --replay " + log_path.string() + " --out " + out.string());
  EXPECT_EQ(cut.exit_code, 2) << cut.output;
  EXPECT_NE(cut.output.find("no 'end' event on SKIDSIM_EVENTS"), std::string::npos) << cut.output;
  EXPECT_FALSE(fs::exists(out));
}

// A log belongs to its exercise (its SKIDSIM_SESSION header): replayed in
// another exercise, in its own exercise edited since, or with no header (a
// log written before the header was), it is refused naming both.
TEST(SkidsimReplay, ALogIsReplayedOnlyInTheExerciseItWasRecordedFrom) {
  const fs::path rec = fs::temp_directory_path() / "skidsim_run_owner_rec";
  const fs::path out = fs::temp_directory_path() / "skidsim_run_owner_out";
  fs::remove_all(rec);
  fs::remove_all(out);
  ASSERT_EQ(run_skidsim("run " + kScenario + " --script " + kScript + " --max-s 2 --out " + rec.string()).exit_code, 0);
  const std::string log_path = (rec / "session.lcmlog").string();
  // The header: the first event, naming the exercise and its files' hashes.
  const skidsim::io::LcmLog log = skidsim::io::read_lcm_log(log_path, [](const std::string& ch) { return ch == "SKIDSIM_SESSION"; });
  ASSERT_EQ(log.kept.size(), 1u);
  EXPECT_EQ(log.kept[0].index, 0u);
  const nlohmann::json header = nlohmann::json::parse(log.kept[0].data.begin(), log.kept[0].data.end());
  EXPECT_EQ(header["format"], "skidsim-session");
  EXPECT_EQ(header["version"], 1);
  EXPECT_EQ(header["exercise"], "pile-to-zone");
  ASSERT_EQ(header["files"].size(), 4u);
  EXPECT_EQ(header["files"][0]["role"], "exercise");
  EXPECT_EQ(header["files"][0]["file"], "pile_to_zone.xml");
  EXPECT_EQ(header["files"][0]["fnv1a64"].get<std::string>().size(), 16u);

  const std::string grading = std::string(SKIDSIM_SOURCE_DIR) + "/scenarios/grading.xml";
  const auto other = run_skidsim("run " + grading + " --replay " + log_path + " --out " + out.string());
  EXPECT_EQ(other.exit_code, 2) << other.output;
  EXPECT_NE(other.output.find(log_path + " was recorded from exercise 'pile-to-zone' (pile_to_zone.xml, hash " +
                              header["files"][0]["fnv1a64"].get<std::string>() + "), not 'grading' (" + grading + ", hash "),
            std::string::npos)
      << other.output;
  EXPECT_FALSE(fs::exists(out));
  // The same exercise, edited since (a comment added): another file.
  const fs::path edited = rec / "pile_to_zone.xml";
  std::ofstream(edited) << slurp_bytes(kScenario) << "<!-- edited -->\n";
  const auto changed = run_skidsim("run " + edited.string() + " --replay " + log_path + " --out " + out.string());
  EXPECT_EQ(changed.exit_code, 2) << changed.output;
  EXPECT_NE(changed.output.find("the exercise file has changed since the session was recorded"), std::string::npos) << changed.output;
  // A log as written before the header (its events without the first one).
  const std::string bytes = slurp_bytes(log_path);
  const std::size_t header_end = static_cast<std::size_t>(log.kept[0].data_offset_bytes + log.kept[0].data.size());
  std::ofstream(rec / "old.lcmlog", std::ios::binary) << bytes.substr(header_end);
  const auto old = run_skidsim("run " + kScenario + " --replay " + (rec / "old.lcmlog").string() + " --out " + out.string());
  EXPECT_EQ(old.exit_code, 2) << old.output;
  EXPECT_NE(old.output.find("no SKIDSIM_SESSION header as its first event: a log written before skidsim recorded which exercise"),
            std::string::npos)
      << old.output;
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
