// libFuzzer: io::load_soil_table on arbitrary bytes.
#include "fuzz/fuzz_support.h"
#include "io/soil_table.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace skidsim;
  const std::string path = fuzz::write_input(fuzz::work_dir() / "soils.xml", data, size);
  fuzz::expect_load_or_input_error([&] { io::load_soil_table(path); }, {path});
  return 0;
}
