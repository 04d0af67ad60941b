// libFuzzer: the glTF reader, as .glb when the input starts with the binary magic "glTF", else as .gltf.
#include <cstring>

#include "fuzz/fuzz_sequence_reader.hpp"
#include "fuzz/fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  pleat::fuzz::load_and_read_all(pleat::fuzz::write_input(binary ? "input.glb" : "input.gltf", data, size));
  return 0;
}
