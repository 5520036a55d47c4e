// libFuzzer: io::load_operator_script on arbitrary bytes.
#include "fuzz/fuzz_support.h"
#include "io/operator_script.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace skidsim;
  const std::string path = fuzz::write_input(fuzz::work_dir() / "script.operator.xml", data, size);
  fuzz::expect_load_or_input_error([&] { io::load_operator_script(path); }, {path});
  return 0;
}
