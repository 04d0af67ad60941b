// libFuzzer: the MDD point-cache reader, over a valid 9-vertex OBJ.
#include "fuzz/fuzz_sequence_reader.hpp"
#include "fuzz/fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  pleat::fuzz::load_and_read_all(pleat::fuzz::grid_obj(), pleat::fuzz::write_input("input.mdd", data, size));
  return 0;
}
