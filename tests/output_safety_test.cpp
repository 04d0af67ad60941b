// Outputs replace only what is theirs: written through symbolic links; a FIFO, device or directory refused
// before any work (exit status 2); `-o -` on standard output; `generate` keeps a cache it was not named; a
// render is all or nothing (its images appear with the glb, or none does). (Stopped runs:
// termination_test.cpp; outputs that are inputs: input_protection_test.cpp.)
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "test_support.hpp"

namespace pleat {
namespace {

using test::names_in;
using test::slurp;

namespace fs = std::filesystem;

// A small generated curtain: dir/c.obj and dir/c.pc2; returns the input arguments for them.
std::string small_curtain(const fs::path& dir) {
  const auto made =
      test::run_pleat("generate curtain -o " + (dir / "c.obj").string() + " --resolution 8 --frames 3");
  EXPECT_EQ(made.exit_code, 0) << made.output;
  return (dir / "c.obj").string() + " --cache " + (dir / "c.pc2").string();
}

TEST(OutputSafety, WritesThroughSymbolicLinks) {
  test::TempDir dir;
  const std::string input = small_curtain(dir.path());
  fs::create_directories(dir / "out");
  fs::create_directories(dir / "real");
  fs::create_symlink("../real/v.csv", dir / "out/v.csv");  // dangling: names the file to create
  fs::create_symlink("../real/c.glb", dir / "out/c.glb");
  ASSERT_EQ(test::run_pleat("visibility " + input + " -o " + (dir / "direct.csv").string()).exit_code, 0);
  for (int run = 0; run < 2; ++run) {  // creates the file, then replaces it
    const auto result = test::run_pleat("visibility " + input + " -o " + (dir / "out/v.csv").string());
    ASSERT_EQ(result.exit_code, 0) << result.output;
  }
  const auto shaded = test::run_pleat("shade " + input + " -o " + (dir / "out/c.glb").string());
  ASSERT_EQ(shaded.exit_code, 0) << shaded.output;
  EXPECT_TRUE(fs::is_symlink(dir / "out/v.csv"));
  EXPECT_TRUE(fs::is_symlink(dir / "out/c.glb"));
  EXPECT_EQ(slurp(dir / "real/v.csv"), slurp(dir / "direct.csv"));
  EXPECT_GT(fs::file_size(dir / "real/c.glb"), 1000u);
  EXPECT_EQ(names_in(dir / "out"), (std::vector<std::string>{"c.glb", "v.csv"}));
  EXPECT_EQ(names_in(dir / "real"), (std::vector<std::string>{"c.glb", "v.csv"}));
}

// System paths are reached through links of the test's own (dir/null.csv -> /dev/null, dir/stdout.csv ->
// /dev/stdout): pleat refuses them as it refuses the paths themselves, and a pleat that did not would replace
// the test's link, not the system's device or link (as root, it can).

TEST(OutputSafety, RefusesFifosDevicesAndDirectoriesBeforeAnyWork) {
  test::TempDir dir;
  const std::string input = small_curtain(dir.path());
  ASSERT_EQ(::mkfifo((dir / "fifo.csv").c_str(), 0644), 0);
  fs::create_directories(dir / "directory.csv");
  fs::create_symlink("fifo.csv", dir / "link.csv");
  fs::create_symlink("/dev/null", dir / "null.csv");
  const std::vector<std::string> before = names_in(dir.path());
  const std::pair<std::string, std::string> targets[] = {{(dir / "fifo.csv").string(), "a FIFO"},
                                                         {(dir / "link.csv").string(), "a FIFO"},
                                                         {(dir / "directory.csv").string(), "a directory"},
                                                         {(dir / "null.csv").string(), "a character device"}};
  for (const auto& [target, kind] : targets) {
    SCOPED_TRACE(target);
    const std::string expected =
        target + ": not a regular file (" + kind + "); pleat writes outputs atomically";
    // The input does not exist: the refusal comes first, before anything is read or computed.
    const auto early = test::run_pleat("visibility " + (dir / "missing.obj").string() + " -o " + target);
    EXPECT_EQ(early.exit_code, 2);
    EXPECT_NE(early.output.find(expected), std::string::npos) << early.output;
    EXPECT_EQ(early.output.find("missing.obj"), std::string::npos) << early.output;
    // Every output option of every subcommand that writes files is checked.
    for (const std::string& args :
         {"visibility " + input + " -o " + (dir / "v.csv").string() + " --stats " + target,
          "visibility " + input + " -o " + (dir / "v.csv").string() + " --cones " + target,
          "shade " + input + " -o " + target, "compare " + input + " --light sky:1 -o " + target}) {
      const auto result = test::run_pleat(args);
      EXPECT_EQ(result.exit_code, 2) << args;
      EXPECT_NE(result.output.find(expected), std::string::npos) << result.output;
    }
  }
  EXPECT_TRUE(fs::is_fifo(dir / "fifo.csv"));
  EXPECT_TRUE(fs::is_symlink(dir / "link.csv"));
  EXPECT_TRUE(fs::is_directory(dir / "directory.csv"));
  EXPECT_TRUE(fs::is_empty(dir / "directory.csv"));
  EXPECT_TRUE(fs::is_symlink(dir / "null.csv"));
  EXPECT_EQ(names_in(dir.path()), before);
  // generate: OUT.obj and the OUT.pc2 beside it; view and --render: directories.
  fs::create_directories(dir / "g.pc2");
  const auto generate = test::run_pleat("generate flag -o " + (dir / "g.obj").string() + " --force");
  EXPECT_EQ(generate.exit_code, 2);
  EXPECT_NE(generate.output.find("g.pc2: not a regular file (a directory)"), std::string::npos)
      << generate.output;
  const auto view =
      test::run_pleat("view " + (dir / "missing.glb").string() + " -o " + (dir / "c.obj").string());
  EXPECT_EQ(view.exit_code, 2);
  EXPECT_NE(view.output.find("c.obj: not a directory"), std::string::npos) << view.output;
}

TEST(OutputSafety, StandardOutputOnAPipeIsRefused) {
  // Run as root, pleat once replaced the system's /dev/stdout symbolic link with a regular file. Here stdout
  // is the pipe run_pleat reads: /dev/stdout leads to a FIFO.
  test::TempDir dir;
  const std::string input = small_curtain(dir.path());
  fs::create_symlink("/dev/stdout", dir / "stdout.csv");
  const auto result = test::run_pleat("visibility " + input + " -o " + (dir / "stdout.csv").string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("stdout.csv: not a regular file (a FIFO)"), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("give -"), std::string::npos) << result.output;
  EXPECT_TRUE(fs::is_symlink(dir / "stdout.csv"));
}

TEST(OutputSafety, DashWritesToStandardOutput) {
  test::TempDir dir;
  const std::string input = small_curtain(dir.path());
  const std::string in_dir = "cd " + dir.path().string() + " && ";
  ASSERT_EQ(test::run_pleat("visibility " + input + " -o " + (dir / "v.csv").string()).exit_code, 0);
  ASSERT_EQ(test::run_pleat("shade " + input + " -o " + (dir / "s.glb").string()).exit_code, 0);
  for (const std::string& command : {"visibility " + input + " -o - > piped.csv 2> err.txt",
                                     "shade " + input + " -o - > piped.glb 2> err.txt"}) {
    const auto result = test::run_command("(" + in_dir + PLEAT_EXECUTABLE + " " + command + ")");
    ASSERT_EQ(result.exit_code, 0) << command << "\n" << slurp(dir / "err.txt");
    EXPECT_NE(slurp(dir / "err.txt").find("wrote -"), std::string::npos) << slurp(dir / "err.txt");
  }
  EXPECT_EQ(slurp(dir / "piped.csv"), slurp(dir / "v.csv"));  // nothing else on stdout
  EXPECT_EQ(slurp(dir / "piped.glb"), slurp(dir / "s.glb"));
  EXPECT_FALSE(fs::exists(dir / "-"));
  // One stream, one output; and not for outputs that need a file.
  const auto two = test::run_pleat("visibility " + input + " -o - --stats -");
  EXPECT_EQ(two.exit_code, 2);
  EXPECT_NE(two.output.find("both stream to standard output"), std::string::npos) << two.output;
  const auto cones =
      test::run_pleat("visibility " + input + " -o " + (dir / "x.csv").string() + " --cones -");
  EXPECT_EQ(cones.exit_code, 2);
  const auto generate = test::run_pleat("generate flag -o -");
  EXPECT_EQ(generate.exit_code, 2);
  EXPECT_FALSE(fs::exists(dir / "x.csv"));
}

TEST(OutputSafety, GenerateKeepsACacheItWasNotNamedUnlessForced) {
  test::TempDir dir;
  const std::string obj = (dir / "x.obj").string();
  { std::ofstream(dir / "x.pc2") << "the user's own file"; }
  const auto refused = test::run_pleat("generate flag -o " + obj + " --resolution 6 --frames 2");
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.output.find("x.pc2: exists"), std::string::npos) << refused.output;
  EXPECT_NE(refused.output.find("--force"), std::string::npos) << refused.output;
  EXPECT_EQ(slurp(dir / "x.pc2"), "the user's own file");
  EXPECT_FALSE(fs::exists(dir / "x.obj"));

  const auto forced = test::run_pleat("generate flag -o " + obj + " --resolution 6 --frames 2 --force");
  ASSERT_EQ(forced.exit_code, 0) << forced.output;
  EXPECT_NE(slurp(dir / "x.pc2").substr(0, 11), "the user's ");
  // The OBJ the user named is replaced as any output is (here with the cache gone).
  fs::remove(dir / "x.pc2");
  { std::ofstream(dir / "x.obj") << "old"; }
  ASSERT_EQ(test::run_pleat("generate flag -o " + obj + " --resolution 6 --frames 2").exit_code, 0);
  EXPECT_NE(slurp(dir / "x.obj"), "old");
  EXPECT_TRUE(fs::exists(dir / "x.pc2"));
}

// Every file under `dir` (recursively, hidden ones included) and its bytes.
std::map<std::string, std::string> contents(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(dir))
    files[fs::relative(entry.path(), dir).string()] = entry.is_regular_file() ? slurp(entry.path()) : "<dir>";
  return files;
}

// A shade job long enough to stop in the middle, rendering small images: the arguments, with `light`.
std::vector<std::string> render_job(const fs::path& dir, const std::string& light) {
  return {"shade",    (dir / "c.obj").string(),
          "--cache",  (dir / "c.pc2").string(),
          "-o",       (dir / "out.glb").string(),
          "--render", (dir / "renders").string(),
          "--width",  "64",
          "--height", "48",
          "--light",  light};
}

class RenderCommit : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto made =
        test::run_pleat("generate curtain -o " + (dir / "c.obj").string() + " --resolution 40 --frames 60");
    ASSERT_EQ(made.exit_code, 0) << made.output;
    // The first render, whose files a failed second one must leave as they are.
    const pid_t first = test::start_pleat(render_job(dir.path(), "sky:0.3"), dir / "errors.txt");
    int status = 0;
    ASSERT_EQ(::waitpid(first, &status, 0), first);
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << slurp(dir / "errors.txt");
    before = contents(dir / "renders");
    glb = slurp(dir / "out.glb");
    ASSERT_EQ(before.size(), 60u);
  }
  void expect_unchanged() {
    EXPECT_TRUE(contents(dir / "renders") == before) << "the render directory changed";
    EXPECT_TRUE(slurp(dir / "out.glb") == glb) << "out.glb changed";
    for (const std::string& name : names_in(dir.path()))
      EXPECT_EQ(name.find(".tmp."), std::string::npos) << name;
  }
  test::TempDir dir;
  std::map<std::string, std::string> before;
  std::string glb;
};

TEST_F(RenderCommit, AStoppedRenderLeavesTheOldImagesAndGlb) {
  const pid_t pid = test::start_pleat(render_job(dir.path(), "sky:1.5"), dir / "errors.txt");
  // Until images are staged (a hidden directory in the render directory with files in it).
  bool staged = false;
  for (int i = 0; i < 12000 && !staged; ++i) {
    for (const auto& entry : fs::directory_iterator(dir / "renders"))
      if (entry.is_directory() && entry.path().filename().string().rfind(".pleat-staged.tmp.", 0) == 0)
        staged = !fs::is_empty(entry.path());
    if (!staged) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_TRUE(staged) << slurp(dir / "errors.txt");
  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status)) << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 143);
  expect_unchanged();
}

TEST_F(RenderCommit, AFullDiskWhileWritingTheGlbLeavesTheOldImages) {
  // A file size limit the small images fit under and the glb does not: the glb fails ("file too large"), and
  // no image appears.
  const rlimit limit{1 << 20, 1 << 20};
  const pid_t pid = test::start_pleat(render_job(dir.path(), "sky:1.5"), dir / "errors.txt",
                                      {.limits = {{RLIMIT_FSIZE, limit}}});
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status)) << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 1);
  EXPECT_NE(slurp(dir / "errors.txt").find("out.glb: cannot write: file too large"), std::string::npos)
      << slurp(dir / "errors.txt");
  expect_unchanged();
}

TEST_F(RenderCommit, ACompleteRenderReplacesTheImagesWithTheGlb) {
  const pid_t pid = test::start_pleat(render_job(dir.path(), "sky:1.5"), dir / "errors.txt");
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << slurp(dir / "errors.txt");
  const auto after = contents(dir / "renders");
  ASSERT_EQ(after.size(), before.size());
  for (const auto& [name, bytes] : after) EXPECT_NE(bytes, before.at(name)) << name;
  EXPECT_NE(slurp(dir / "out.glb"), glb);
}

}  // namespace
}  // namespace pleat
