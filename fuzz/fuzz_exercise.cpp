// libFuzzer: io::load_exercise on arbitrary bytes. Written beside copies of
// the shipped operator scripts and the loader folder, so that a mutant's
// references (script="pile_to_zone.operator.xml",
// loader="loader/skidsteer.params.xml") resolve.
#include "fuzz/fuzz_support.h"
#include "io/exercise.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace skidsim;
  const std::string path = fuzz::write_input(fuzz::work_dir() / "exercise.xml", data, size);
  fuzz::expect_load_or_input_error([&] { io::load_exercise(path); }, {path});
  return 0;
}
