// The checked LCM log reader (io/lcm_log.h): a log written by liblcm reads
// back whole; every kind of damage (a bad sync word, channel and data
// lengths past the file or LCM's limits, a header or data cut at any byte,
// trailing garbage, event numbers or timestamps going back) and every file
// that is not a log (/dev/zero, a folder, an empty file) is an InputError
// naming the file and the byte, never a crash, a hang or a short read.
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "io/atomic_file.h"
#include "io/lcm_log.h"

namespace skidsim::io {
namespace {

namespace fs = std::filesystem;

struct Written {
  std::string channel;
  std::int64_t timestamp_us;
  std::string data;
};

const std::vector<Written> kEvents = {{"SKIDSIM_SESSION", 0, "{\"format\":\"skidsim-session\"}"},
                                      {"SKIDSIM_CONTROL_APPLIED", 0, std::string(81, '\x01')},
                                      {"SKIDSIM_STATE", 0, std::string(277, '\x7f')},
                                      {"SKIDSIM_CONTROL_APPLIED", 10000, std::string(81, '\x02')},
                                      {"SKIDSIM_EVENTS", 10000, ""},
                                      {"SKIDSIM_CONTROL_APPLIED", 20000, std::string(81, '\x03')}};

class LcmLogTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("skidsim_lcm_log_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // The events above, written by liblcm's own writer (lcm::LogFile).
  std::string write_with_lcm(const std::vector<Written>& events, const std::string& name = "session.lcmlog") {
    const std::string path = (dir_ / name).string();
    lcm::LogFile log(path, "w");
    EXPECT_TRUE(log.good());
    for (const Written& w : events) {
      lcm::LogEvent e;
      e.eventnum = 0;  // liblcm numbers them itself
      e.timestamp = w.timestamp_us;
      e.channel = w.channel;
      e.datalen = static_cast<std::int32_t>(w.data.size());
      e.data = const_cast<char*>(w.data.data());
      EXPECT_EQ(log.writeEvent(&e), 0);
    }
    return path;
  }
  std::string bytes_of(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  std::string put(const std::string& bytes, const std::string& name = "damaged.lcmlog") {
    const std::string path = (dir_ / name).string();
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
    return path;
  }
  // The message of the InputError read_lcm_log throws (a test failure if none).
  std::string error_of(const std::string& path, std::uintmax_t max_bytes = kMaxLcmLogBytes) {
    try {
      read_lcm_log(path, [](const std::string&) { return true; }, max_bytes);
    } catch (const InputError& e) {
      return e.what();
    }
    ADD_FAILURE() << path << " was read without an error";
    return "";
  }

  fs::path dir_;
};

// Big-endian fields written over a log's bytes.
void put_be(std::string& bytes, std::size_t at, std::uint64_t v, int n) {
  for (int k = n - 1; k >= 0; --k, v >>= 8) bytes[at + static_cast<std::size_t>(k)] = static_cast<char>(v & 0xFF);
}

// Where each event starts in a log of kEvents.
std::vector<std::size_t> starts_of(const std::vector<Written>& events) {
  std::vector<std::size_t> starts;
  std::size_t at = 0;
  for (const Written& w : events) {
    starts.push_back(at);
    at += kLcmEventHeaderBytes + w.channel.size() + w.data.size();
  }
  starts.push_back(at);  // the end
  return starts;
}

TEST_F(LcmLogTest, ALogWrittenByLcmReadsBackWhole) {
  const std::string path = write_with_lcm(kEvents);
  const std::vector<std::size_t> starts = starts_of(kEvents);
  const LcmLog log = read_lcm_log(path, [](const std::string&) { return true; });
  EXPECT_EQ(log.path, path);
  EXPECT_EQ(log.size_bytes, starts.back());
  EXPECT_EQ(log.event_count, kEvents.size());
  ASSERT_EQ(log.kept.size(), kEvents.size());
  for (std::size_t k = 0; k < kEvents.size(); ++k) {
    const LcmLogEvent& e = log.kept[k];
    EXPECT_EQ(e.index, k);
    EXPECT_EQ(e.event_number, static_cast<std::int64_t>(k)) << "liblcm numbers events 0, 1, 2, ...";
    EXPECT_EQ(e.timestamp_us, kEvents[k].timestamp_us);
    EXPECT_EQ(e.channel, kEvents[k].channel);
    EXPECT_EQ(std::string(e.data.begin(), e.data.end()), kEvents[k].data);
    EXPECT_EQ(e.offset_bytes, starts[k]);
    EXPECT_EQ(e.data_offset_bytes, starts[k] + kLcmEventHeaderBytes + kEvents[k].channel.size());
  }
  // Only the channels asked for are kept (the rest checked and skipped).
  const LcmLog applied = read_lcm_log(path, [](const std::string& ch) { return ch == "SKIDSIM_CONTROL_APPLIED"; });
  EXPECT_EQ(applied.event_count, kEvents.size());
  ASSERT_EQ(applied.kept.size(), 3u);
  EXPECT_EQ(applied.kept[2].index, 5u);
  EXPECT_EQ(applied.kept[2].data, std::vector<std::uint8_t>(81, 3));
  // The same from memory.
  const LcmLog in_memory = parse_lcm_log(bytes_of(path), "memory", [](const std::string&) { return true; });
  ASSERT_EQ(in_memory.kept.size(), kEvents.size());
  EXPECT_EQ(in_memory.kept[2].data, log.kept[2].data);
  // Data over the reader's 1 MiB window comes back whole too.
  const std::string big(3 << 20, 'x');
  const LcmLog large = read_lcm_log(write_with_lcm({{"A", 0, "a"}, {"BIG", 1, big}, {"C", 2, "c"}}, "big.lcmlog"),
                                    [](const std::string&) { return true; });
  ASSERT_EQ(large.kept.size(), 3u);
  EXPECT_EQ(std::string(large.kept[1].data.begin(), large.kept[1].data.end()), big);
  EXPECT_EQ(large.kept[2].channel, "C");
}

TEST_F(LcmLogTest, ABadSyncWordIsNamedAtItsByte) {
  const std::string good = bytes_of(write_with_lcm(kEvents));
  const std::vector<std::size_t> starts = starts_of(kEvents);
  std::string bad = good;
  bad[0] = 'X';
  EXPECT_NE(error_of(put(bad)).find("damaged.lcmlog: byte 0: event 0: sync word 0x58A1DA01, expected LCM's 0xEDA1DA01 (not an LCM log)"),
            std::string::npos)
      << error_of(put(bad));
  bad = good;
  bad[starts[3] + 2] = 0;
  const std::string msg = error_of(put(bad));
  EXPECT_NE(msg.find("byte " + std::to_string(starts[3]) + ": event 3: sync word 0xEDA10001"), std::string::npos) << msg;
}

TEST_F(LcmLogTest, ChannelLengthsOutsideOneTo256AreRefused) {
  const std::string good = bytes_of(write_with_lcm(kEvents));
  const std::vector<std::size_t> starts = starts_of(kEvents);
  for (const std::int64_t length : {0x7fffffffLL, 0LL, -1LL, 257LL, 100000LL}) {
    std::string bad = good;
    put_be(bad, starts[1] + 20, static_cast<std::uint32_t>(length), 4);
    const std::string msg = error_of(put(bad));
    EXPECT_NE(msg.find("byte " + std::to_string(starts[1] + 20) + ": event 1: channel length " + std::to_string(static_cast<std::int32_t>(length)) +
                       ", expected 1 to 256 bytes"),
              std::string::npos)
        << msg;
  }
  // Within the limit but past the end of the file.
  std::string cut = good.substr(0, starts[1] + 28 + 5);
  put_be(cut, starts[1] + 20, 200, 4);
  const std::string msg = error_of(put(cut));
  EXPECT_NE(msg.find("byte " + std::to_string(starts[1] + 20) + ": event 1: channel length 200 runs past the end of the file"),
            std::string::npos)
      << msg;
  // A channel name of other than printable ASCII.
  std::string bad = good;
  bad[starts[2] + 28 + 3] = '\n';
  const std::string ctl = error_of(put(bad));
  EXPECT_NE(ctl.find("byte " + std::to_string(starts[2] + 28 + 3) + ": event 2: channel name byte 0x0A is not printable ASCII"),
            std::string::npos)
      << ctl;
}

TEST_F(LcmLogTest, DataLengthsPastTheFileOrNegativeAreRefused) {
  const std::string good = bytes_of(write_with_lcm(kEvents));
  const std::vector<std::size_t> starts = starts_of(kEvents);
  std::string bad = good;
  put_be(bad, starts[4] + 24, 0x7fffffff, 4);
  std::string msg = error_of(put(bad));
  EXPECT_NE(msg.find("damaged.lcmlog: byte " + std::to_string(starts[4] + 24) +
                     ": event 4: data length 2147483647 runs past the end of the file (the file has " +
                     std::to_string(good.size()) + " bytes)"),
            std::string::npos)
      << msg;
  bad = good;
  put_be(bad, starts[0] + 24, 0xffffffff, 4);
  msg = error_of(put(bad));
  EXPECT_NE(msg.find("byte 24: event 0: data length -1 is negative"), std::string::npos) << msg;
  // One byte more than there is.
  bad = good;
  put_be(bad, starts[5] + 24, 82, 4);
  msg = error_of(put(bad));
  EXPECT_NE(msg.find("byte " + std::to_string(starts[5] + 24) + ": event 5: data length 82 runs past the end"), std::string::npos) << msg;
}

// A one-event log cut at every byte of its header and channel: each an
// InputError naming the byte (the header's start, or the channel length
// that runs past the end), never a short read taken as a whole log.
TEST_F(LcmLogTest, AOneEventLogCutAtEveryByteNamesTheByte) {
  const std::vector<Written> one = {{"SKIDSIM_CONTROL_APPLIED", 0, std::string(81, '\x01')}};
  const std::string good = bytes_of(write_with_lcm(one));
  ASSERT_EQ(good.size(), 28u + 23u + 81u);
  for (std::size_t at = 0; at < good.size(); ++at) {
    const std::string msg = error_of(put(good.substr(0, at)));
    std::string expected;
    if (at == 0) {
      expected = "damaged.lcmlog: byte 0: an empty file, not an LCM log (no events)";
    } else if (at < 28) {
      expected = "damaged.lcmlog: byte 0: event 0: the file ends " + std::to_string(at) + " bytes into the event's 28-byte header";
    } else if (at < 28 + 23) {
      expected = "damaged.lcmlog: byte 20: event 0: channel length 23 runs past the end of the file (the file has " +
                 std::to_string(at) + " bytes)";
    } else {
      expected = "damaged.lcmlog: byte 24: event 0: data length 81 runs past the end of the file (the file has " +
                 std::to_string(at) + " bytes)";
    }
    EXPECT_NE(msg.find(expected), std::string::npos) << "cut at " << at << ": " << msg;
  }
  EXPECT_EQ(read_lcm_log(put(good), nullptr).event_count, 1u);
}

TEST_F(LcmLogTest, TruncatedDataAndTrailingGarbageAreRefused) {
  const std::string good = bytes_of(write_with_lcm(kEvents));
  const std::vector<std::size_t> starts = starts_of(kEvents);
  std::string msg = error_of(put(good.substr(0, good.size() - 1)));
  EXPECT_NE(msg.find("byte " + std::to_string(starts[5] + 24) + ": event 5: data length 81 runs past the end"), std::string::npos)
      << msg;
  // Bytes after the last event: named as not an event (4 bytes or more),
  // or as a partial header.
  msg = error_of(put(good + "garbage!"));
  EXPECT_NE(msg.find("byte " + std::to_string(good.size()) + ": event 6: sync word 0x67617262, expected LCM's 0xEDA1DA01 "
                     "(bytes that are not an event where one should start)"),
            std::string::npos)
      << msg;
  msg = error_of(put(good + std::string("\xED\xA1\xDA", 3)));
  EXPECT_NE(msg.find("byte " + std::to_string(good.size()) + ": event 6: the file ends 3 bytes into the event's 28-byte header"),
            std::string::npos)
      << msg;
  // A whole header and nothing after it.
  std::string header = good.substr(starts[1], 28);
  put_be(header, 4, 6, 8);       // the next event number
  put_be(header, 12, 30000, 8);  // and a later time
  msg = error_of(put(good + header));
  EXPECT_NE(msg.find("byte " + std::to_string(good.size() + 20) + ": event 6: channel length 23 runs past the end"), std::string::npos)
      << msg;
}

TEST_F(LcmLogTest, EventNumbersMustIncreaseAndTimestampsNeverGoBack) {
  const std::string good = bytes_of(write_with_lcm(kEvents));
  const std::vector<std::size_t> starts = starts_of(kEvents);
  std::string bad = good;
  put_be(bad, starts[3] + 4, 2, 8);  // the number of the event before
  std::string msg = error_of(put(bad));
  EXPECT_NE(msg.find("byte " + std::to_string(starts[3] + 4) + ": event 3: event number 2 does not increase (the one before is 2)"),
            std::string::npos)
      << msg;
  bad = good;
  put_be(bad, starts[0] + 4, static_cast<std::uint64_t>(-5), 8);
  msg = error_of(put(bad));
  EXPECT_NE(msg.find("byte 4: event 0: event number -5 is negative"), std::string::npos) << msg;
  bad = good;
  put_be(bad, starts[4] + 12, 9999, 8);  // before event 3's 10000 us
  msg = error_of(put(bad));
  EXPECT_NE(msg.find("byte " + std::to_string(starts[4] + 12) + ": event 4: timestamp 9999 us is before the one of the event before (10000 us)"),
            std::string::npos)
      << msg;
  bad = good;
  put_be(bad, starts[0] + 12, static_cast<std::uint64_t>(-1), 8);
  msg = error_of(put(bad));
  EXPECT_NE(msg.find("byte 12: event 0: timestamp -1 us is negative"), std::string::npos) << msg;
  // Gaps in the numbering are allowed (lcm-logger's own logs keep its count).
  bad = good;
  put_be(bad, starts[5] + 4, 1000, 8);
  EXPECT_EQ(read_lcm_log(put(bad), nullptr).event_count, kEvents.size());
}

TEST_F(LcmLogTest, WhatIsNotALogFileIsRefusedAtOnce) {
  EXPECT_NE(error_of("/dev/zero").find("LCM log /dev/zero: not a regular file"), std::string::npos);
  EXPECT_NE(error_of(dir_.string()).find("is a directory"), std::string::npos);
  EXPECT_NE(error_of((dir_ / "none.lcmlog").string()).find("none.lcmlog: no such file"), std::string::npos);
  EXPECT_NE(error_of(put("", "empty.lcmlog")).find("empty.lcmlog: byte 0: an empty file, not an LCM log"), std::string::npos);
  EXPECT_NE(error_of(put("not a log at all, just words", "words.lcmlog")).find("words.lcmlog: byte 0: event 0: sync word 0x6E6F7420"),
            std::string::npos);
  // Over the size cap: refused before it is read.
  const std::string path = write_with_lcm(kEvents);
  EXPECT_NE(error_of(path, 100).find("more than the 100 a file of this kind may have"), std::string::npos) << error_of(path, 100);
  // From memory, the same checks.
  try {
    parse_lcm_log(std::string(30, '\0'), "zeros", nullptr);
    ADD_FAILURE() << "zeros read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("zeros: byte 0: event 0: sync word 0x00000000"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace skidsim::io
