// A checked reader of LCM log files (session.lcmlog): the whole file is
// validated before a byte of it reaches the replay, and nothing of liblcm is
// used to read it. liblcm's reader (lcm/eventlog.c, lcm_eventlog_read_next_event)
// trusts the file: it skips any bytes until it finds a sync word (on
// /dev/zero it never returns), and allocates `length + 1` for a channel or
// data length read from the file (0x7fffffff overflows to a failed calloc,
// then fread into NULL: a segfault in LCM 1.3.1). Here every event is
// checked against the format, and the first fault is an InputError naming
// the file, the byte and the field.
//
// The format (LCM's "log file format", lcm-proj.github.io/lcm/content/log-file-format.html),
// all integers big-endian, one event after another with nothing between:
//   u32 sync word 0xEDA1DA01, i64 event number, i64 timestamp (us),
//   i32 channel length, i32 data length, the channel's bytes, the data.
// Checked: a regular file within kMaxLcmLogBytes (io/input_file.h); at least
// one event; every sync word in place (no resynchronising past garbage);
// channel length 1 to 256 of printable ASCII; data length 0 to what is left
// of the file; event numbers increasing (liblcm's writer numbers events
// 0, 1, 2, ... whatever the caller sets); timestamps non-negative and never
// decreasing (skidsim stamps with simulated time; lcm-logger with the
// receive time); no partial event at the end.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "io/input_file.h"

namespace skidsim::io {

constexpr std::uint32_t kLcmSyncWord = 0xEDA1DA01u;
constexpr int kLcmEventHeaderBytes = 28;  // sync, event number, timestamp, channel length, data length
// liblcm publishes channel names of at most 63 bytes (lcm.h,
// LCM_MAX_CHANNEL_NAME_LENGTH); its log reader takes up to 999 (newer
// eventlog.c). 256 is above anything LCM sends, far below what would hurt.
constexpr int kMaxLcmChannelBytes = 256;

struct LcmLogEvent {
  std::int64_t event_number = 0;
  std::int64_t timestamp_us = 0;
  std::string channel;
  std::uint64_t index = 0;              // 0-based, in file order (the "event N" of messages)
  std::uint64_t offset_bytes = 0;       // where its sync word starts
  std::uint64_t data_offset_bytes = 0;  // where its data starts
  std::vector<std::uint8_t> data;       // the data (only for the channels asked for)
};

struct LcmLog {
  std::string path;
  std::uint64_t size_bytes = 0;
  std::uint64_t event_count = 0;   // every event in the file
  std::vector<LcmLogEvent> kept;   // the events on the channels asked for, in file order
};

// Which events to keep, by channel (the others are checked and skipped:
// a long log's state and terrain messages are never held in memory).
using LcmChannelFilter = std::function<bool(const std::string& channel)>;

// Checks the whole file (see above), then returns the events `keep` wants
// with their data. Throws InputError "PATH: byte N: event K: what" at the
// first fault (the byte is that of the faulty field).
LcmLog read_lcm_log(const std::string& path, const LcmChannelFilter& keep, std::uintmax_t max_bytes = kMaxLcmLogBytes);

// The same checks on bytes in memory; `name` stands for the file in messages.
LcmLog parse_lcm_log(const std::string& bytes, const std::string& name, const LcmChannelFilter& keep);

// "PATH: byte N: event K: " (the prefix of every message about an event).
std::string lcm_log_where(const std::string& path, std::uint64_t byte, std::uint64_t event_index);

}  // namespace skidsim::io
