#include "test_support.hpp"

#include <fcntl.h>
#include <rapidcheck.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <glm/geometric.hpp>
#include <iterator>
#include <random>
#include <thread>

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

pid_t start_pleat(const std::vector<std::string>& args, const std::filesystem::path& errors,
                  const StartOptions& options) {
  std::vector<std::string> words = {PLEAT_EXECUTABLE};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& word : words) argv.push_back(word.data());
  argv.push_back(nullptr);
  const std::string error_path = errors.string();
  const pid_t pid = ::fork();
  if (pid == 0) {
    for (int s = 1; s < NSIG; ++s)
      if (s != SIGKILL && s != SIGSTOP) ::signal(s, SIG_DFL);
    if (options.ignore_hangup) ::signal(SIGHUP, SIG_IGN);
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    for (const auto& [resource, limit] : options.limits) ::setrlimit(resource, &limit);
    const int out = options.stdout_fd >= 0 ? options.stdout_fd : ::open("/dev/null", O_WRONLY);
    const int err = ::open(error_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(out, STDOUT_FILENO);
    ::dup2(err, STDERR_FILENO);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  return pid;
}

bool wait_for_temporaries(const std::filesystem::path& dir, std::size_t count, pid_t pid) {
  for (int i = 0; i < 12000; ++i) {
    std::size_t found = 0;
    if (std::filesystem::is_directory(dir))
      for (const std::string& name : names_in(dir)) found += name.find(".tmp.") != std::string::npos;
    if (found >= count) return true;
    if (::waitpid(pid, nullptr, WNOHANG) != 0) return false;  // ended (or failed) before
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

}  // namespace pleat::test
