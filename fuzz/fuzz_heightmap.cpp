// libFuzzer: io::read_heightmap on arbitrary bytes. The first byte picks
// which half of the pair the rest replaces: even, the JSON metadata (beside a
// valid 8 x 6 PNG, map.png); odd, the PNG (beside metadata that names it).
// Either way: a map, or an InputError naming one of the two files; never a
// crash, nor an allocation the metadata did not promise.
#include "fuzz/fuzz_support.h"
#include "io/heightmap.h"

namespace {

// A valid pair written once: map.png + valid.json, and the JSON text.
const std::string& valid_json() {
  static const std::string text = [] {
    using namespace skidsim;
    io::Heightmap map;
    map.nx = 8;
    map.ny = 6;
    map.cell_size_m = 0.05;
    map.quantity = "material";
    for (int k = 0; k < map.nx * map.ny; ++k) map.height_m.push_back(0.01 * k);
    io::write_heightmap((fuzz::work_dir() / "map").string(), map);
    std::ifstream in(fuzz::work_dir() / "map.json");
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  }();
  return text;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace skidsim;
  if (size == 0) return 0;
  const std::string json_text = valid_json();
  const fuzz::fs::path dir = fuzz::work_dir();
  if (data[0] % 2 == 0) {
    const std::string json = fuzz::write_input(dir / "fuzzed.json", data + 1, size - 1);
    fuzz::expect_load_or_input_error([&] { io::read_heightmap(json); }, {json, (dir / "map.png").string()});
  } else {
    const std::string png = fuzz::write_input(dir / "fuzzed.png", data + 1, size - 1);
    std::string text = json_text;
    const std::size_t at = text.find("map.png");
    if (at == std::string::npos) std::abort();
    text.replace(at, 7, "fuzzed.png");
    const std::string json = (dir / "fuzzed_png.json").string();
    std::ofstream(json, std::ios::trunc) << text;
    fuzz::expect_load_or_input_error([&] { io::read_heightmap(json); }, {json, png});
  }
  return 0;
}
