// libFuzzer: arbitrary bytes as an LCM log, read the way `skidsim run
// --replay` and `skidsim review` read one: the checked reader
// (io/lcm_log.h; liblcm's reader is not used for input), then control_t on
// the applied channel. The file loads or is refused with an InputError
// naming it; what loads keeps the format's rules (every event within the
// file, channels of 1 to 256 bytes, timestamps never going back), reads the
// same from memory, and a decoded control is whole.
#include <string>

#include "fuzz/fuzz_support.h"
#include "io/lcm_log.h"
#include "skidsim_lcm/control_t.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace skidsim;
  const std::string path = fuzz::write_input(fuzz::work_dir() / "session.lcmlog", data, size);
  const auto keep_all = [](const std::string&) { return true; };
  io::LcmLog log;
  bool loaded = false;
  fuzz::expect_load_or_input_error(
      [&] {
        log = io::read_lcm_log(path, keep_all);
        loaded = true;
      },
      {path});
  // From memory: the same verdict.
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  bool loaded_from_memory = false;
  std::uint64_t events_from_memory = 0;
  try {
    events_from_memory = io::parse_lcm_log(bytes, path, keep_all).event_count;
    loaded_from_memory = true;
  } catch (const io::InputError&) {
  }
  if (loaded != loaded_from_memory || events_from_memory != log.event_count) std::abort();
  if (!loaded) return 0;
  if (log.size_bytes != size || log.kept.size() != log.event_count || log.kept.empty()) std::abort();
  std::int64_t last_time = 0;
  for (const io::LcmLogEvent& e : log.kept) {
    if (e.channel.empty() || e.channel.size() > static_cast<std::size_t>(io::kMaxLcmChannelBytes)) std::abort();
    if (e.data_offset_bytes + e.data.size() > size || e.timestamp_us < last_time) std::abort();
    last_time = e.timestamp_us;
    if (e.channel != "SKIDSIM_CONTROL_APPLIED") continue;
    skidsim_lcm::control_t m{};
    const int n = m.decode(e.data.data(), 0, static_cast<int>(e.data.size()));
    if (n > static_cast<int>(e.data.size())) std::abort();
  }
  return 0;
}
