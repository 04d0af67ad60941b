#include "test_support.hpp"

#include <rapidcheck.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdio>
#include <fstream>
#include <glm/geometric.hpp>
#include <iterator>
#include <random>

namespace pleat::test {

std::filesystem::path source_dir() { return PLEAT_SOURCE_DIR; }

TempDir::TempDir() {
  static std::atomic<int> counter{0};
  m_path = std::filesystem::temp_directory_path() /
           ("pleat_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  std::filesystem::remove_all(m_path);
  std::filesystem::create_directories(m_path);
}

TempDir::~TempDir() {
  std::error_code ec;
  std::filesystem::remove_all(m_path, ec);
}

std::string flip_random_bits(std::string bytes) {
  const auto flips = *rc::gen::inRange(1, 6);
  for (int k = 0; k < flips; ++k) {
    const auto at = *rc::gen::inRange<std::size_t>(0, bytes.size());
    bytes[at] = char(bytes[at] ^ (1 << *rc::gen::inRange(0, 8)));
  }
  return bytes;
}

glm::dvec3 gen_unit_direction() {
  while (true) {
    const glm::dvec3 d(*rc::gen::inRange(-1000, 1001), *rc::gen::inRange(-1000, 1001),
                       *rc::gen::inRange(-1000, 1001));
    if (glm::length(d) > 100) return glm::normalize(d);
  }
}

CommandResult run_pleat(const std::string& args) {
  return run_command(std::string(PLEAT_EXECUTABLE) + " " + args);
}

CommandResult run_command(const std::string& shell_command) {
  const std::string command = shell_command + " 2>&1";
  CommandResult result;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return {-1, "popen failed"};
  std::array<char, 4096> buffer{};
  std::size_t n = 0;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) result.output.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::vector<std::string> names_in(const std::filesystem::path& directory) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(directory))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace pleat::test
