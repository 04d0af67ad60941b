// libFuzzer: small fuzzed cloths (fuzz_cloth.hpp) through both engines and the shading. A finding is a crash,
// a sanitizer report, any exception (InvariantError is a bug) or the kinetic engine's A differing from the
// static engine's (the product's equality, as the property test states it). Findings go to
// tests/fuzz/regressions/fuzz_engines/, which tests/fuzz_regressions_test.cpp replays in the normal suite.
#include <cstdlib>

#include "fuzz/fuzz_cloth.hpp"
#include "support/input_error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto cloth = pleat::fuzz::decode_cloth(data, size);
  if (!cloth) return 0;
  std::string mismatch;
  try {
    mismatch = pleat::fuzz::check_engines(*cloth);
  } catch (const pleat::InputError&) {  // the documented answer: a cloth too wide for its planes' spacing
    return 0;
  }
  if (!mismatch.empty()) {
    std::fprintf(stderr, "%s\n", mismatch.c_str());
    std::abort();
  }
  return 0;
}
