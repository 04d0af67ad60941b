// libFuzzer: the cone cache reader (shading/cone_cache.hpp), both encodings (fuzz_cone_cache_reader.hpp).
#include "fuzz/fuzz_cone_cache_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  pleat::fuzz::read_cone_cache_for_grid(pleat::fuzz::write_input("input.cones", data, size));
  return 0;
}
