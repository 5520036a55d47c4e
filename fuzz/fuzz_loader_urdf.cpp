// libFuzzer: io::load_loader with the shipped parameters naming an arbitrary
// URDF (urdfdom, then the checks of io/loader_files.cpp; meshes resolve
// against the copy of the loader folder).
#include <fstream>
#include <sstream>

#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace skidsim;
  const fuzz::fs::path dir = fuzz::work_dir() / "loader";
  static const std::string params = [&] {
    std::ifstream in(dir / "skidsteer.params.xml");
    std::stringstream s;
    s << in.rdbuf();
    std::string text = s.str();
    const std::string from = "urdf=\"skidsteer.urdf\"";
    const size_t at = text.find(from);
    if (at == std::string::npos) std::abort();
    text.replace(at, from.size(), "urdf=\"fuzz.urdf\"");
    const fuzz::fs::path p = dir / "fuzz_urdf.params.xml";
    std::ofstream(p) << text;
    return p.string();
  }();
  const std::string urdf = fuzz::write_input(dir / "fuzz.urdf", data, size);
  fuzz::expect_load_or_input_error([&] { io::load_loader(params); }, {urdf, params});
  return 0;
}
