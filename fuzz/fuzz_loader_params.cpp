// libFuzzer: io::load_loader on arbitrary parameter files, beside a copy of
// the shipped URDF and meshes (urdf="skidsteer.urdf" resolves). Errors may
// name the parameters or the URDF they point to.
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace skidsim;
  const std::string path = fuzz::write_input(fuzz::work_dir() / "loader" / "fuzz.params.xml", data, size);
  // The message names the file it is about: these, or the URDF they name.
  fuzz::expect_load_or_input_error([&] { io::load_loader(path); }, {path, ""});
  return 0;
}
