#include "io/lcm_log.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "io/atomic_file.h"

namespace skidsim::io {
namespace {

// Where the bytes come from: a file (read with pread through a window, so a
// long log's data that is skipped is never copied) or memory.
class Source {
 public:
  virtual ~Source() = default;
  // Copies n bytes at `offset` (within the size checked at the start).
  virtual void read(std::uint64_t offset, std::uint8_t* out, std::size_t n) = 0;
};

class MemorySource : public Source {
 public:
  explicit MemorySource(const std::string& bytes) : bytes_(bytes) {}
  void read(std::uint64_t offset, std::uint8_t* out, std::size_t n) override {
    std::memcpy(out, bytes_.data() + offset, n);
  }

 private:
  const std::string& bytes_;
};

class FileSource : public Source {
 public:
  FileSource(const std::string& path, std::uint64_t size) : path_(path), size_(size) {
    // O_NONBLOCK: were the path swapped for a FIFO since it was checked,
    // open would wait for a writer; fstat below refuses it instead.
    fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd_ < 0) throw InputError("LCM log " + path + ": cannot open: " + std::strerror(errno));
    struct stat st {};
    if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode) || static_cast<std::uint64_t>(st.st_size) != size_) {
      ::close(fd_);
      throw InputError("LCM log " + path + ": the file changed while it was opened (no longer a regular file of " +
                       std::to_string(size_) + " bytes)");
    }
  }
  ~FileSource() override { ::close(fd_); }
  FileSource(const FileSource&) = delete;
  FileSource& operator=(const FileSource&) = delete;

  void read(std::uint64_t offset, std::uint8_t* out, std::size_t n) override {
    if (offset >= window_start_ && offset + n <= window_start_ + window_.size()) {
      std::memcpy(out, window_.data() + (offset - window_start_), n);
      return;
    }
    if (n >= kWindowBytes) {  // large data: straight into place
      read_at(offset, out, n);
      return;
    }
    window_.resize(static_cast<std::size_t>(std::min<std::uint64_t>(kWindowBytes, size_ - offset)));
    read_at(offset, window_.data(), window_.size());
    window_start_ = offset;
    std::memcpy(out, window_.data(), n);
  }

 private:
  static constexpr std::size_t kWindowBytes = 1 << 20;

  void read_at(std::uint64_t offset, std::uint8_t* out, std::size_t n) {
    std::size_t done = 0;
    while (done < n) {
      const ssize_t got = ::pread(fd_, out + done, n - done, static_cast<off_t>(offset + done));
      if (got < 0 && errno == EINTR) continue;
      if (got <= 0)
        throw InputError("LCM log " + path_ + ": byte " + std::to_string(offset + done) + ": " +
                         (got < 0 ? std::string("cannot read: ") + std::strerror(errno)
                                  : "the file ended early (it changed while it was read?)"));
      done += static_cast<std::size_t>(got);
    }
  }

  std::string path_;
  std::uint64_t size_;
  int fd_ = -1;
  std::vector<std::uint8_t> window_;
  std::uint64_t window_start_ = 0;
};

std::uint64_t big_endian(const std::uint8_t* p, int n) {
  std::uint64_t v = 0;
  for (int k = 0; k < n; ++k) v = (v << 8) | p[k];
  return v;
}

std::string hex32(std::uint32_t v) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "0x%08X", v);
  return buf;
}

LcmLog parse(Source& src, const std::string& name, std::uint64_t size, const LcmChannelFilter& keep) {
  LcmLog log;
  log.path = name;
  log.size_bytes = size;
  if (size == 0) throw InputError(name + ": byte 0: an empty file, not an LCM log (no events)");
  const std::string of_size = " (the file has " + std::to_string(size) + " bytes)";
  std::uint64_t at = 0, index = 0;
  std::int64_t last_number = 0, last_time = 0;
  std::uint8_t header[kLcmEventHeaderBytes];
  while (at < size) {
    const auto fail = [&](std::uint64_t byte, const std::string& what) {
      throw InputError(lcm_log_where(name, byte, index) + what);
    };
    const std::uint64_t left = size - at;
    // The sync word first (when there are 4 bytes): trailing garbage is
    // named as such, not as a short header.
    const std::size_t have = static_cast<std::size_t>(std::min<std::uint64_t>(left, kLcmEventHeaderBytes));
    src.read(at, header, have);
    if (have >= 4) {
      const auto sync = static_cast<std::uint32_t>(big_endian(header, 4));
      if (sync != kLcmSyncWord)
        fail(at, "sync word " + hex32(sync) + ", expected LCM's " + hex32(kLcmSyncWord) +
                     (index == 0 ? " (not an LCM log)" : " (bytes that are not an event where one should start)"));
    }
    if (left < static_cast<std::uint64_t>(kLcmEventHeaderBytes))
      fail(at, "the file ends " + std::to_string(left) + " bytes into the event's " + std::to_string(kLcmEventHeaderBytes) +
                   "-byte header (sync word, event number, timestamp, channel and data lengths)" + of_size);
    LcmLogEvent e;
    e.index = index;
    e.offset_bytes = at;
    e.event_number = static_cast<std::int64_t>(big_endian(header + 4, 8));
    e.timestamp_us = static_cast<std::int64_t>(big_endian(header + 12, 8));
    const auto channel_bytes = static_cast<std::int32_t>(static_cast<std::uint32_t>(big_endian(header + 20, 4)));
    const auto data_bytes = static_cast<std::int32_t>(static_cast<std::uint32_t>(big_endian(header + 24, 4)));
    if (e.event_number < 0) fail(at + 4, "event number " + std::to_string(e.event_number) + " is negative");
    if (index > 0 && e.event_number <= last_number)
      fail(at + 4, "event number " + std::to_string(e.event_number) + " does not increase (the one before is " +
                       std::to_string(last_number) + ")");
    if (e.timestamp_us < 0) fail(at + 12, "timestamp " + std::to_string(e.timestamp_us) + " us is negative");
    if (index > 0 && e.timestamp_us < last_time)
      fail(at + 12, "timestamp " + std::to_string(e.timestamp_us) + " us is before the one of the event before (" +
                        std::to_string(last_time) + " us)");
    if (channel_bytes < 1 || channel_bytes > kMaxLcmChannelBytes)
      fail(at + 20, "channel length " + std::to_string(channel_bytes) + ", expected 1 to " +
                        std::to_string(kMaxLcmChannelBytes) + " bytes");
    const std::uint64_t channel_at = at + kLcmEventHeaderBytes;
    if (static_cast<std::uint64_t>(channel_bytes) > size - channel_at)
      fail(at + 20, "channel length " + std::to_string(channel_bytes) + " runs past the end of the file" + of_size);
    e.channel.resize(static_cast<std::size_t>(channel_bytes));
    src.read(channel_at, reinterpret_cast<std::uint8_t*>(e.channel.data()), e.channel.size());
    for (std::size_t k = 0; k < e.channel.size(); ++k) {
      const auto c = static_cast<unsigned char>(e.channel[k]);
      if (c < 0x20 || c > 0x7E) {
        char code[8];
        std::snprintf(code, sizeof code, "0x%02X", c);
        fail(channel_at + k, std::string("channel name byte ") + code + " is not printable ASCII");
      }
    }
    if (data_bytes < 0) fail(at + 24, "data length " + std::to_string(data_bytes) + " is negative");
    e.data_offset_bytes = channel_at + static_cast<std::uint64_t>(channel_bytes);
    if (static_cast<std::uint64_t>(data_bytes) > size - e.data_offset_bytes)
      fail(at + 24, "data length " + std::to_string(data_bytes) + " runs past the end of the file" + of_size);
    last_number = e.event_number;
    last_time = e.timestamp_us;
    at = e.data_offset_bytes + static_cast<std::uint64_t>(data_bytes);
    if (keep && keep(e.channel)) {
      e.data.resize(static_cast<std::size_t>(data_bytes));
      if (data_bytes > 0) src.read(e.data_offset_bytes, e.data.data(), e.data.size());
      log.kept.push_back(std::move(e));
    }
    ++index;
  }
  log.event_count = index;
  return log;
}

}  // namespace

std::string lcm_log_where(const std::string& path, std::uint64_t byte, std::uint64_t event_index) {
  return path + ": byte " + std::to_string(byte) + ": event " + std::to_string(event_index) + ": ";
}

LcmLog read_lcm_log(const std::string& path, const LcmChannelFilter& keep, std::uintmax_t max_bytes) {
  const std::uint64_t size = check_input_file(path, max_bytes, "LCM log");
  FileSource src(path, size);
  return parse(src, path, size, keep);
}

LcmLog parse_lcm_log(const std::string& bytes, const std::string& name, const LcmChannelFilter& keep) {
  MemorySource src(bytes);
  return parse(src, name, bytes.size(), keep);
}

}  // namespace skidsim::io
