// libFuzzer: arbitrary bytes as an LCM log, read the way `skidsim run
// --replay` reads one (lcm::LogFile, then control_t on the applied
// channel). Nothing may crash; a decoded control is whole.
#include <string>

#include <lcm/lcm-cpp.hpp>

#include "fuzz/fuzz_support.h"
#include "skidsim_lcm/control_t.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace skidsim;
  const std::string path = fuzz::write_input(fuzz::work_dir() / "session.lcmlog", data, size);
  lcm::LogFile log(path, "r");
  if (!log.good()) return 0;
  int events = 0;
  while (const lcm::LogEvent* e = log.readNextEvent()) {
    if (e->datalen < 0 || ++events > 10000) std::abort();
    if (e->channel != "SKIDSIM_CONTROL_APPLIED") continue;
    skidsim_lcm::control_t m{};
    const int n = m.decode(e->data, 0, e->datalen);
    if (n > e->datalen) std::abort();
  }
  return 0;
}
