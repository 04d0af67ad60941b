// libFuzzer: the OBJ reader (a mesh, and a mesh as frame 0 of a sequence).
#include "fuzz/fuzz_sequence_reader.hpp"
#include "fuzz/fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  pleat::fuzz::load_and_read_all(pleat::fuzz::write_input("input.obj", data, size));
  return 0;
}
