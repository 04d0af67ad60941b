// A run stopped by any signal whose default is to terminate (cli/termination.hpp: SIGINT, SIGTERM, SIGHUP,
// SIGQUIT, SIGPIPE, SIGXCPU, SIGUSR1, ...) leaves no temporary file and exits with 128 + the signal; a signal
// ignored at start stays ignored; a CPU time limit ends the run the same way; the temporaries of a process
// killed outright (SIGKILL) are removed by the next run writing to the same place, never those of a live
// process or of another machine (support/temporary_files.hpp). The real executable on a job long enough to
// be stopped in the middle.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstring>
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
using test::start_pleat;
using test::wait_for_temporaries;

namespace fs = std::filesystem;

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
  const pid_t pid = start_pleat(args, dir / "errors.txt", {.ignore_hangup = true});
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

// Waits for `pid` and returns its wait status.
int wait_for(pid_t pid) {
  int status = 0;
  EXPECT_EQ(::waitpid(pid, &status, 0), pid);
  return status;
}

TEST(Termination, EveryTerminatingSignalLeavesNoTemporaryFiles) {
  // What schedulers send before a kill (SIGUSR1/2, SIGALRM, SIGXCPU), what a user or a tool may send, and a
  // real-time signal: each ends the run with 128 + the signal, the temporaries removed, saying which.
  test::TempDir dir;
  const std::vector<std::string> args = long_job(dir.path());
  const std::pair<int, std::string> signals[] = {
      {SIGQUIT, "SIGQUIT"}, {SIGUSR1, "SIGUSR1"},     {SIGUSR2, "SIGUSR2"}, {SIGALRM, "SIGALRM"},
      {SIGXCPU, "SIGXCPU"}, {SIGVTALRM, "SIGVTALRM"}, {SIGPROF, "SIGPROF"}, {SIGPIPE, "SIGPIPE"},
      {SIGXFSZ, "SIGXFSZ"}, {SIGPOLL, "SIGPOLL"},     {SIGPWR, "SIGPWR"},   {SIGRTMIN + 3, "SIGRTMIN+3"}};
  for (const auto& [signal, name] : signals) {
    SCOPED_TRACE(name);
    const pid_t pid = start_pleat(args, dir / "errors.txt");
    ASSERT_GT(pid, 0);
    ASSERT_TRUE(wait_for_temporaries(dir / "out", 2, pid)) << slurp(dir / "errors.txt");
    ASSERT_EQ(::kill(pid, signal), 0);
    const int status = wait_for(pid);
    ASSERT_TRUE(WIFEXITED(status)) << "ended by signal " << WTERMSIG(status);
    EXPECT_EQ(WEXITSTATUS(status), 128 + signal);
    EXPECT_TRUE(fs::is_empty(dir / "out")) << names_in(dir / "out").front();
    EXPECT_NE(slurp(dir / "errors.txt").find("stopped by " + name), std::string::npos)
        << slurp(dir / "errors.txt");
  }
}

TEST(Termination, APipeClosedByItsReaderLeavesNoTemporaryFiles) {
  // `pleat visibility ... -o - --cones x.cones | head -1`: the CSV streams into a pipe whose reader leaves
  // after one line; the write that follows raises SIGPIPE.
  test::TempDir dir;
  std::vector<std::string> args = long_job(dir.path());
  args[5] = "-";  // -o -
  int pipe_fds[2];
  ASSERT_EQ(::pipe2(pipe_fds, O_CLOEXEC), 0);  // the read end is not inherited
  const pid_t pid = start_pleat(args, dir / "errors.txt", {.stdout_fd = pipe_fds[1]});
  ::close(pipe_fds[1]);
  char header[32] = {};
  ASSERT_GT(::read(pipe_fds[0], header, sizeof header - 1), 0) << slurp(dir / "errors.txt");
  EXPECT_EQ(std::string(header).rfind("frame,vertex", 0), 0u) << header;
  ::close(pipe_fds[0]);
  const int status = wait_for(pid);
  ASSERT_TRUE(WIFEXITED(status)) << "ended by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGPIPE);
  EXPECT_TRUE(fs::is_empty(dir / "out")) << names_in(dir / "out").front();
  EXPECT_NE(slurp(dir / "errors.txt").find("stopped by SIGPIPE"), std::string::npos)
      << slurp(dir / "errors.txt");
}

TEST(Termination, ACpuTimeLimitEndsTheRunCleanly) {
  // A batch system's CPU limit: soft below hard (SIGXCPU at the soft limit), and `ulimit -t N`, soft and
  // hard equal (the kernel's SIGKILL, which pleat forestalls by lowering its soft limit).
  test::TempDir dir;
  const std::vector<std::string> args = long_job(dir.path());
  for (const rlimit cpu : {rlimit{1, 3}, rlimit{2, 2}}) {
    SCOPED_TRACE("soft " + std::to_string(cpu.rlim_cur) + ", hard " + std::to_string(cpu.rlim_max));
    const pid_t pid = start_pleat(args, dir / "errors.txt", {.limits = {{RLIMIT_CPU, cpu}}});
    const int status = wait_for(pid);
    ASSERT_TRUE(WIFEXITED(status)) << "ended by signal " << WTERMSIG(status);
    EXPECT_EQ(WEXITSTATUS(status), 128 + SIGXCPU);
    EXPECT_TRUE(fs::is_empty(dir / "out")) << names_in(dir / "out").front();
    EXPECT_NE(slurp(dir / "errors.txt").find("stopped by SIGXCPU (the CPU time limit was reached"),
              std::string::npos)
        << slurp(dir / "errors.txt");
  }
}

// This machine's name as pleat writes it in temporary names (support/temporary_files.hpp).
std::string host_tag() {
  char name[256] = {};
  ::gethostname(name, sizeof name - 1);
  std::string tag(name, std::min<std::size_t>(std::strlen(name), 64));
  for (char& c : tag)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_')) c = '_';
  return tag;
}

// A process id that was used and is free again.
pid_t dead_pid() {
  const pid_t pid = ::fork();
  if (pid == 0) ::_exit(0);
  ::waitpid(pid, nullptr, 0);
  return pid;
}

TEST(Termination, TemporariesOfKilledRunsAreRemovedByTheNextRunNeverThoseOfLiveOnes) {
  test::TempDir dir;
  std::vector<std::string> args = long_job(dir.path());
  const std::string checkpoint = (dir / "ck").string();
  for (const std::string& extra :
       {std::string("--checkpoint"), checkpoint, std::string("--chunks"), std::string("3")})
    args.push_back(extra);
  const pid_t killed = start_pleat(args, dir / "errors.txt");
  ASSERT_TRUE(wait_for_temporaries(dir / "out", 2, killed)) << slurp(dir / "errors.txt");
  ASSERT_TRUE(wait_for_temporaries(dir / "ck", 1, killed)) << slurp(dir / "errors.txt");
  ASSERT_EQ(::kill(killed, SIGKILL), 0);  // an out-of-memory kill, a lost node: no handler runs
  wait_for(killed);
  std::vector<std::string> left;
  for (const fs::path& where : {dir / "out", dir / "ck"})
    for (const std::string& name : names_in(where))
      if (name.find(".tmp.") != std::string::npos) left.push_back(name);
  ASSERT_GE(left.size(), 3u);
  // Beside them: a live process's (this test's), another machine's, a dead process's of another target in
  // the checkpoint (removed: the directory is pleat's), and a file that is not a temporary.
  const std::string host = host_tag();
  const std::vector<std::string> kept = {".v.csv.tmp." + host + "." + std::to_string(::getpid()) + ".0",
                                         ".v.csv.tmp.another-node.1." + std::to_string(dead_pid()) + ".0",
                                         ".v.csv.tmp", ".notes.tmp.txt"};
  for (const std::string& name : kept) std::ofstream(dir / "out" / name) << "x";
  const std::string dead = ".old.pleatchunk.tmp." + host + "." + std::to_string(dead_pid()) + ".7";
  std::ofstream(dir / "ck" / dead) << "x";
  // The next run writing the same outputs (a shorter range: the point is where it writes).
  args.push_back("--frames");
  args.push_back("0:2");
  const pid_t next = start_pleat(args, dir / "errors.txt");
  const int status = wait_for(next);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << slurp(dir / "errors.txt");
  for (const std::string& name : left) {
    EXPECT_FALSE(fs::exists(dir / "out" / name)) << name;
    EXPECT_FALSE(fs::exists(dir / "ck" / name)) << name;
  }
  EXPECT_FALSE(fs::exists(dir / "ck" / dead));
  for (const std::string& name : kept) EXPECT_TRUE(fs::exists(dir / "out" / name)) << name;
  EXPECT_TRUE(fs::exists(dir / "out/v.csv"));
}

}  // namespace
}  // namespace pleat
