// Writes the binary seeds (scripts/fuzz.sh): encoded control_t messages into
// argv[1]; into argv[2] a small session log shaped like skidsim's own
// (session/session_replay.h): its SKIDSIM_SESSION header first, controls on
// SKIDSIM_CONTROL_APPLIED with a state message between, and the "end" event
// last; and a height map's JSON and PNG (each behind the heightmap harness's
// selector byte) into argv[3].
#include <cstdio>
#include <unistd.h>
#include <utility>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "io/heightmap.h"
#include "skidsim_lcm/control_t.hpp"
#include "skidsim_lcm/event_t.hpp"

namespace {

skidsim_lcm::control_t command(int k) {
  skidsim_lcm::control_t c{};
  c.sender_id = 42;
  c.seq = k + 1;
  c.sender_time_us = 10000 * k;
  c.sim_step = 5 * k;
  c.drive_left = 0.5 - 0.1 * k;
  c.drive_right = -0.25 * k;
  c.lift = 0.1;
  c.tilt = -0.2;
  c.throttle = 1.0;
  c.parking_brake = k % 2 == 0;
  return c;
}

std::vector<unsigned char> encoded(const skidsim_lcm::control_t& c) {
  std::vector<unsigned char> b(static_cast<std::size_t>(c.getEncodedSize()));
  c.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: %s CONTROL_SEED_DIR LOG_SEED_DIR HEIGHTMAP_SEED_DIR\n", argv[0]);
    return 2;
  }
  namespace fs = std::filesystem;
  fs::create_directories(argv[1]);
  fs::create_directories(argv[2]);
  fs::create_directories(argv[3]);
  {
    skidsim::io::Heightmap map;
    map.nx = 8;
    map.ny = 6;
    map.cell_size_m = 0.05;
    map.quantity = "material";
    for (int k = 0; k < map.nx * map.ny; ++k) map.height_m.push_back(0.01 * k);
    const fs::path folder = fs::temp_directory_path() / ("skidsim_seed_map_" + std::to_string(::getpid()));
    fs::create_directories(folder);
    const fs::path stem = folder / "map";  // the harness's PNG is map.png too
    skidsim::io::write_heightmap(stem.string(), map);
    for (const auto& [ext, selector] : {std::pair<std::string, char>{".json", 0}, {".png", 1}}) {
      std::ifstream in(stem.string() + ext, std::ios::binary);
      const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      std::ofstream(fs::path(argv[3]) / ("map" + ext), std::ios::binary) << selector << bytes;
    }
    fs::remove_all(folder);
  }
  std::vector<unsigned char> stream;
  for (int k = 0; k < 3; ++k) {
    const std::vector<unsigned char> b = encoded(command(k));
    std::ofstream(fs::path(argv[1]) / ("control_" + std::to_string(k)), std::ios::binary)
        .write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
    stream.insert(stream.end(), b.begin(), b.end());
  }
  std::ofstream(fs::path(argv[1]) / "control_stream", std::ios::binary)
      .write(reinterpret_cast<const char*>(stream.data()), static_cast<std::streamsize>(stream.size()));

  lcm::LogFile log((fs::path(argv[2]) / "session.lcmlog").string(), "w");
  if (!log.good()) return 1;
  const auto write = [&log](const std::string& channel, std::int64_t timestamp_us, std::vector<unsigned char> b) {
    lcm::LogEvent e;
    e.eventnum = 0;  // liblcm numbers them
    e.timestamp = timestamp_us;
    e.channel = channel;
    e.datalen = static_cast<int>(b.size());
    e.data = b.data();
    return log.writeEvent(&e) == 0;
  };
  const std::string header =
      R"({"format":"skidsim-session","version":1,"exercise":"pile-to-zone","files":[)"
      R"({"role":"exercise","file":"pile_to_zone.xml","fnv1a64":"0123456789abcdef"}]})";
  if (!write("SKIDSIM_SESSION", 0, std::vector<unsigned char>(header.begin(), header.end()))) return 1;
  for (int k = 0; k < 5; ++k) {
    const bool state = k == 2;
    if (!write(state ? "SKIDSIM_STATE" : "SKIDSIM_CONTROL_APPLIED", 10000 * k,
               state ? std::vector<unsigned char>(24, 7) : encoded(command(k))))
      return 1;
  }
  skidsim_lcm::event_t end{};
  end.step = 20;
  end.sim_time_s = 0.04;
  end.kind = "end";
  end.text = "session ended: time_limit";
  std::vector<unsigned char> b(static_cast<std::size_t>(end.getEncodedSize()));
  end.encode(b.data(), 0, static_cast<int>(b.size()));
  if (!write("SKIDSIM_EVENTS", 40000, b)) return 1;
  return 0;
}
