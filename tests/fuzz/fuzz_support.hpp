// Shared by the libFuzzer harnesses (tests/fuzz/): the readers take paths, so each input is written to a file
// in a per-process scratch directory first. A harness lets InputError through (the documented answer to bad
// input) and nothing else: any other exception, a crash, a hang or a sanitizer report is a finding.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace pleat::fuzz {

/// The process's scratch directory (created once).
inline const std::filesystem::path& scratch_directory() {
  static const std::filesystem::path dir = [] {
    auto d = std::filesystem::temp_directory_path() / ("pleat-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

/// Writes `size` bytes to `name` in the scratch directory and returns its path.
inline std::filesystem::path write_input(const std::string& name, const std::uint8_t* data,
                                         std::size_t size) {
  const auto path = scratch_directory() / name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

/// A small valid OBJ (a 3 x 3 grid, 9 vertices) for the point-cache harnesses.
inline const std::filesystem::path& grid_obj() {
  static const std::filesystem::path path = [] {
    const auto p = scratch_directory() / "grid.obj";
    std::ofstream out(p);
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) out << "v " << i << ' ' << j << " 0\n";
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) {
        const int a = 1 + j * 3 + i;
        out << "f " << a << ' ' << a + 1 << ' ' << a + 4 << "\nf " << a << ' ' << a + 4 << ' ' << a + 3
            << '\n';
      }
    return p;
  }();
  return path;
}

}  // namespace pleat::fuzz
