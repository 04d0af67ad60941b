// Helpers shared by the tests: a fresh temporary directory per test, and running the `pleat` executable.
#pragma once

#include <sys/resource.h>
#include <sys/types.h>

#include <filesystem>
#include <glm/vec3.hpp>
#include <string>
#include <utility>
#include <vector>

namespace pleat::test {

/// The repository root (for data/ and golden files).
std::filesystem::path source_dir();

/// A new empty directory under the system temp dir, removed when the object dies.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return m_path; }
  std::filesystem::path operator/(const std::string& name) const { return m_path / name; }

 private:
  std::filesystem::path m_path;
};

struct CommandResult {
  int exit_code = 0;
  std::string output;  ///< stdout and stderr together
};

/// Inside a rapidcheck property: `bytes` with 1 to 5 random bits flipped (corruption properties).
std::string flip_random_bits(std::string bytes);

/// Inside a rapidcheck property: a unit direction, from integer coordinates in [-1000, 1000] (exact axes and
/// diagonals included; shrinks towards them).
glm::dvec3 gen_unit_direction();

/// Runs `pleat ARGS` (args are passed to the shell as written) and captures its output.
CommandResult run_pleat(const std::string& args);
/// Runs a shell command, stderr merged into the output.
CommandResult run_command(const std::string& shell_command);

/// How start_pleat starts the process.
struct StartOptions {
  bool ignore_hangup = false;                       ///< SIGHUP ignored, as under nohup
  int stdout_fd = -1;                               ///< where stdout goes (else /dev/null)
  std::vector<std::pair<int, rlimit>> limits = {};  ///< setrlimit(resource, limit) in the child
};
/// Starts `pleat ARGS` as a farm's launcher would: every signal at its default action and unblocked, stdout
/// to /dev/null and stderr to the file `errors`. Returns its process id (waitpid it).
pid_t start_pleat(const std::vector<std::string>& args, const std::filesystem::path& errors,
                  const StartOptions& options = {});
/// Waits until `dir` holds `count` temporary files (.NAME.tmp.*: the run is computing), at most two minutes;
/// false when `pid` ended first.
bool wait_for_temporaries(const std::filesystem::path& dir, std::size_t count, pid_t pid);

/// The whole content of a file ("" when it cannot be read).
std::string slurp(const std::filesystem::path& path);
/// The names of the entries of a directory, sorted.
std::vector<std::string> names_in(const std::filesystem::path& directory);

}  // namespace pleat::test
