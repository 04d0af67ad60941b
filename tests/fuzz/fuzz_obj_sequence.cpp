// libFuzzer: a numbered OBJ sequence — the input is cut at each "\n#frame\n" into up to four files
// f_0000.obj, f_0001.obj, ... of a fresh directory, loaded as a directory of frames.
#include <cstdio>
#include <string_view>

#include "fuzz/fuzz_sequence_reader.hpp"
#include "fuzz/fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto dir = pleat::fuzz::scratch_directory() / "sequence";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  constexpr std::string_view kCut = "\n#frame\n";
  std::size_t begin = 0;
  for (int frame = 0; frame < 4 && begin <= text.size(); ++frame) {
    const std::size_t end = frame == 3 ? text.npos : text.find(kCut, begin);
    const std::string_view part = text.substr(begin, end == text.npos ? text.npos : end - begin);
    char name[32];
    std::snprintf(name, sizeof name, "sequence/f_%04d.obj", frame);
    pleat::fuzz::write_input(name, reinterpret_cast<const std::uint8_t*>(part.data()), part.size());
    if (end == text.npos) break;
    begin = end + kCut.size();
  }
  pleat::fuzz::load_and_read_all(dir);
  return 0;
}
