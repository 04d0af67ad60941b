// Every input a fuzz harness found a bug with (tests/fuzz/regressions/<harness>/), replayed in the normal
// suite: the engines' cloths through check_engines (both engines with the kinetic invariant checks on, the
// kinetic A equal to the static A, the shading), the readers' files through load_sequence and the cone caches
// through ConeCacheReader (InputError or a valid result, nothing else).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "fuzz/fuzz_cloth.hpp"
#include "fuzz/fuzz_cone_cache_reader.hpp"

namespace pleat {
namespace {

std::vector<std::filesystem::path> regressions(const std::string& harness) {
  std::vector<std::filesystem::path> files;
  const auto dir = std::filesystem::path(PLEAT_SOURCE_DIR) / "tests" / "fuzz" / "regressions" / harness;
  if (std::filesystem::exists(dir))
    for (const auto& entry : std::filesystem::directory_iterator(dir)) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

TEST(FuzzRegressions, EngineInputsRunCleanAndTheEnginesAgree) {
  const auto files = regressions("fuzz_engines");
  ASSERT_FALSE(files.empty());
  for (const auto& file : files) {
    std::ifstream in(file, std::ios::binary);
    const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                          std::istreambuf_iterator<char>());
    const auto cloth = fuzz::decode_cloth(bytes.data(), bytes.size());
    ASSERT_TRUE(cloth.has_value()) << file;
    std::string mismatch;
    EXPECT_NO_THROW(mismatch = fuzz::check_engines(*cloth)) << file;
    EXPECT_EQ(mismatch, "") << file;
  }
}

TEST(FuzzRegressions, ConeCachesFailWithInputErrorOnly) {
  // A piece's direction count was once trusted before the block was checked to hold that many (a 73 GB
  // allocation under the fuzzer).
  const auto files = regressions("fuzz_cone_cache");
  ASSERT_FALSE(files.empty());
  for (const auto& file : files) EXPECT_NO_THROW(fuzz::read_cone_cache_for_grid(file)) << file;
}

}  // namespace
}  // namespace pleat
