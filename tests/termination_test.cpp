// A run stopped by SIGINT, SIGTERM or SIGHUP (cli/termination.hpp) leaves no temporary file and exits with
// 128 + the signal; a signal ignored at start stays ignored. The real executable on a job long enough to be
// stopped in the middle.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "test_support.hpp"

namespace pleat {
namespace {

using test::names_in;
using test::slurp;

namespace fs = std::filesystem;

// Starts `pleat ARGS` with the three signals at their default action (as a farm's launcher would), stdout to
// /dev/null and stderr to `errors`; `ignore_hangup`: SIGHUP ignored, as under nohup.
pid_t start_pleat(const std::vector<std::string>& args, const fs::path& errors, bool ignore_hangup = false) {
  std::vector<std::string> words = {PLEAT_EXECUTABLE};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& word : words) argv.push_back(word.data());
  argv.push_back(nullptr);
  const std::string error_path = errors.string();
  const pid_t pid = ::fork();
  if (pid == 0) {
    for (int s : {SIGINT, SIGTERM, SIGHUP}) ::signal(s, SIG_DFL);
    if (ignore_hangup) ::signal(SIGHUP, SIG_IGN);
    const int null = ::open("/dev/null", O_WRONLY);
    const int err = ::open(error_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(null, STDOUT_FILENO);
    ::dup2(err, STDERR_FILENO);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  return pid;
}

// Waits until `dir` holds `count` temporary files (the run is computing), at most two minutes.
bool wait_for_temporaries(const fs::path& dir, std::size_t count, pid_t pid) {
  for (int i = 0; i < 12000; ++i) {
    std::size_t found = 0;
    for (const std::string& name : names_in(dir)) found += name.find(".tmp.") != std::string::npos;
    if (found >= count) return true;
    if (::waitpid(pid, nullptr, WNOHANG) != 0) return false;  // ended (or failed) before
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

// dir/c.obj + dir/c.pc2, a job long enough to be stopped in the middle (~3,600 vertices x 60 frames), and the
// arguments of a `pleat visibility` on it writing two outputs into dir/out.
std::vector<std::string> long_job(const fs::path& dir) {
  fs::create_directories(dir / "out");
  const auto made =
      test::run_pleat("generate curtain -o " + (dir / "c.obj").string() + " --resolution 60 --frames 60");
  EXPECT_EQ(made.exit_code, 0) << made.output;
  return {"visibility", (dir / "c.obj").string(),     "--cache", (dir / "c.pc2").string(),
          "-o",         (dir / "out/v.csv").string(), "--cones", (dir / "out/v.cones").string()};
}

TEST(Termination, StoppedRunsLeaveNoTemporaryFiles) {
  test::TempDir dir;
  const std::vector<std::string> args = long_job(dir.path());
  for (const auto& [signal, name] : {std::pair{SIGINT, "SIGINT"}, {SIGTERM, "SIGTERM"}, {SIGHUP, "SIGHUP"}}) {
    SCOPED_TRACE(name);
    const pid_t pid = start_pleat(args, dir / "errors.txt");
    ASSERT_GT(pid, 0);
    ASSERT_TRUE(wait_for_temporaries(dir / "out", 2, pid)) << slurp(dir / "errors.txt");
    ASSERT_EQ(::kill(pid, signal), 0);
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFEXITED(status)) << "ended by signal " << WTERMSIG(status);
    EXPECT_EQ(WEXITSTATUS(status), 128 + signal);
    EXPECT_TRUE(fs::is_empty(dir / "out")) << names_in(dir / "out").front();
    EXPECT_NE(slurp(dir / "errors.txt").find(std::string("stopped by ") + name), std::string::npos)
        << slurp(dir / "errors.txt");
  }
}

TEST(Termination, ASignalIgnoredAtStartStaysIgnored) {
  // As under nohup: SIGHUP does not stop the run; SIGTERM then does, as usual.
  test::TempDir dir;
  const std::vector<std::string> args = long_job(dir.path());
  const pid_t pid = start_pleat(args, dir / "errors.txt", /*ignore_hangup=*/true);
  ASSERT_TRUE(wait_for_temporaries(dir / "out", 2, pid)) << slurp(dir / "errors.txt");
  ASSERT_EQ(::kill(pid, SIGHUP), 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  EXPECT_EQ(::waitpid(pid, nullptr, WNOHANG), 0) << "ended by an ignored SIGHUP";
  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 143);
  EXPECT_TRUE(fs::is_empty(dir / "out"));
}

}  // namespace
}  // namespace pleat
