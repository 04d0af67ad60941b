// A predictable command line (issue 38): exit status 0 / 1 / 2 on every subcommand, written in every --help;
// a misspelt option or subcommand gets the nearest name; --version; the global options -q, --progress and
// --threads before or after the subcommand; `visibility` warns when the first frame self-intersects.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "sim_io/obj_format.hpp"
#include "sim_io/pc2_format.hpp"
#include "sim_io_fixtures.hpp"
#include "test_support.hpp"

namespace pleat {
namespace {

using test::slurp;

namespace fs = std::filesystem;
using test::run_pleat;

// Runs `pleat ARGS` with its stderr into `errors` (the result's output is its stdout).
test::CommandResult run_pleat_split(const std::string& args, const fs::path& errors) {
  return test::run_command(std::string("(") + PLEAT_EXECUTABLE + " " + args + " 2> " + errors.string() + ")");
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// dir/c.obj + dir/c.pc2, a small generated curtain; returns the input arguments.
std::string small_curtain(const fs::path& dir, int frames = 3) {
  const auto made = run_pleat("generate curtain -o " + (dir / "c.obj").string() +
                              " --resolution 8 --frames " + std::to_string(frames));
  EXPECT_EQ(made.exit_code, 0) << made.output;
  return (dir / "c.obj").string() + " --cache " + (dir / "c.pc2").string();
}

TEST(CommandLine, ExitStatusOfEverySubcommand) {
  test::TempDir dir;
  const std::string input = small_curtain(dir.path());
  { std::ofstream(dir / "file.txt") << "a file where a directory is needed"; }
  const std::string under_a_file = (dir / "file.txt").string() + "/sub/";
  ASSERT_EQ(run_pleat("shade " + input + " -o " + (dir / "c.glb").string()).exit_code, 0);
  struct Case {
    std::string args;
    int status;
  };
  const std::string missing = (dir / "missing.obj").string();
  const std::vector<Case> cases = {
      // 0: success (and --help)
      {"info " + input, 0},
      {"visibility " + input + " -o " + (dir / "v.csv").string(), 0},
      {"compare " + input + " --light sky:1 --paths 8 -o " + (dir / "p.png").string(), 0},
      {"view " + (dir / "c.glb").string() + " -o " + (dir / "page").string(), 0},
      {"generate flag -o " + (dir / "g.obj").string() + " --resolution 4 --frames 2", 0},
      {"shade --help", 0},
      // 2: usage errors
      {"", 2},
      {"info " + input + " --no-such-option", 2},
      {"generate flag", 2},  // -o missing
      {"generate blanket -o " + (dir / "b.obj").string(), 2},
      {"visibility " + input + " -o " + (dir / "v.csv").string() + " --frames 9:12", 2},
      {"visibility " + input + " -o " + (dir / "v.csv").string() + " --threads many", 2},
      {"shade " + input + " -o " + (dir / "s.glb").string() + " --light nonsense:1", 2},
      {"compare " + input + " -o " + (dir / "p.png").string(), 2},  // no light
      {"view " + (dir / "c.glb").string(), 2},
      // 2: bad input
      {"info " + missing, 2},
      {"visibility " + missing + " -o " + (dir / "v.csv").string(), 2},
      {"shade " + missing + " -o " + (dir / "s.glb").string(), 2},
      {"compare " + missing + " --light sky:1 -o " + (dir / "p.png").string(), 2},
      {"view " + (dir / "c.obj").string() + " -o " + (dir / "page").string(), 2},
      // 1: runtime failures (an output directory cannot be made under a regular file)
      {"visibility " + input + " -o " + under_a_file + "v.csv", 1},
      {"shade " + input + " -o " + under_a_file + "s.glb", 1},
      {"compare " + input + " --light sky:1 --paths 8 -o " + under_a_file + "p.png", 1},
      {"generate flag -o " + under_a_file + "g.obj", 1},
      {"view " + (dir / "c.glb").string() + " -o " + under_a_file + "page", 1},
  };
  for (const Case& c : cases) {
    const auto result = run_pleat(c.args);
    EXPECT_EQ(result.exit_code, c.status) << "pleat " << c.args << "\n" << result.output;
    if (c.status != 0) {
      EXPECT_NE(result.output.find("pleat: error: "), std::string::npos) << result.output;
    }
  }
  // Written in every subcommand's help, and the main one's.
  for (const std::string command : {"", "info", "generate", "visibility", "shade", "compare", "view"}) {
    const auto help = run_pleat(command + " --help");
    EXPECT_EQ(help.exit_code, 0);
    EXPECT_NE(
        help.output.find("Exit status: 0 success; 1 runtime failure (I/O, out of memory, internal error); 2"),
        std::string::npos)
        << command << "\n"
        << help.output;
    EXPECT_NE(help.output.find("A symbolic link is written through"), std::string::npos) << help.output;
  }
}

TEST(CommandLine, MisspeltNamesGetTheNearestOne) {
  test::TempDir dir;
  const std::string input = small_curtain(dir.path());
  const std::string output = " -o " + (dir / "v.csv").string();
  struct Case {
    std::string args, suggestion;
  };
  const std::vector<Case> cases = {
      {"visibility " + input + output + " --spcing 0.1", "  --spcing: did you mean --spacing?\n"},
      {"visibility " + input + output + " --spacing-egdes=1",
       "  --spacing-egdes: did you mean --spacing-edges?\n"},
      {"visibility " + input + " --ouptut " + (dir / "v.csv").string(),
       "  --ouptut: did you mean --output?\n"},
      {"visibility " + input + output + " --thread 2", "  --thread: did you mean --threads?\n"},  // global
      {"--progres lines visibility " + input + output, "  --progres: did you mean --progress?\n"},
      {"shade " + input + " -o " + (dir / "s.glb").string() + " --ligth sky:1",
       "  --ligth: did you mean --light?\n"},
      {"visibilty " + input + output, "  visibilty: did you mean `pleat visibility`?\n"},
  };
  for (const Case& c : cases) {
    const auto result = run_pleat(c.args);
    EXPECT_EQ(result.exit_code, 2) << c.args;
    EXPECT_NE(result.output.find(c.suggestion), std::string::npos) << c.args << "\n" << result.output;
    EXPECT_NE(result.output.find(" --help` for the options."), std::string::npos) << result.output;
  }
  const auto far = run_pleat("visibility " + input + output + " --zzzzzz");
  EXPECT_EQ(far.exit_code, 2);
  EXPECT_NE(far.output.find("unexpected argument(s): --zzzzzz"), std::string::npos) << far.output;
  EXPECT_EQ(far.output.find("did you mean"), std::string::npos) << far.output;
  EXPECT_FALSE(fs::exists(dir / "v.csv"));
}

TEST(CommandLine, Version) {
  for (const std::string args : {"--version", "visibility --version", "generate --version"}) {
    const auto result = run_pleat(args);
    EXPECT_EQ(result.exit_code, 0) << args;
    EXPECT_TRUE(std::regex_match(result.output, std::regex("pleat [0-9]+\\.[0-9]+\\.[0-9]+\n")))
        << result.output;
  }
}

TEST(CommandLine, GlobalOptionsBeforeOrAfterTheSubcommand) {
  test::TempDir dir;
  const std::string input = small_curtain(dir.path());
  const auto plain = run_pleat("visibility " + input + " -o " + (dir / "plain.csv").string());
  ASSERT_EQ(plain.exit_code, 0) << plain.output;
  EXPECT_NE(plain.output.find("wrote "), std::string::npos) << plain.output;
  for (const std::string& args :
       {"-q --threads 1 visibility " + input + " -o " + (dir / "a.csv").string(),
        "visibility " + input + " -o " + (dir / "b.csv").string() + " --threads 1 -q",
        "--quiet visibility " + input + " --threads=1 -o " + (dir / "c.csv").string()}) {
    const auto result = run_pleat(args);
    ASSERT_EQ(result.exit_code, 0) << args << "\n" << result.output;
    EXPECT_EQ(result.output, "") << args;  // -q: nothing on stdout or stderr
  }
  EXPECT_EQ(slurp(dir / "a.csv"), slurp(dir / "plain.csv"));  // one thread, the same bytes
  EXPECT_EQ(slurp(dir / "b.csv"), slurp(dir / "plain.csv"));
  EXPECT_EQ(slurp(dir / "c.csv"), slurp(dir / "plain.csv"));
  // -q on the other subcommands too.
  for (const std::string& args :
       {"generate flag -q -o " + (dir / "f.obj").string() + " --resolution 4 --frames 2",
        "shade " + input + " -q -o " + (dir / "s.glb").string(),
        "compare " + input + " -q --light sky:1 --paths 8 -o " + (dir / "p.png").string()}) {
    const auto result = run_pleat(args);
    EXPECT_EQ(result.exit_code, 0) << args << "\n" << result.output;
    EXPECT_EQ(result.output, "") << args;
  }
}

TEST(CommandLine, ProgressLinesForLogs) {
  test::TempDir dir;
  const std::string input = small_curtain(dir.path(), 40);
  const std::string output = " -o " + (dir / "v.csv").string();
  const auto lines = run_pleat_split("visibility " + input + output + " --progress lines", dir / "err.txt");
  ASSERT_EQ(lines.exit_code, 0) << lines.output << slurp(dir / "err.txt");
  const std::regex line(
      "pleat: visibility ([0-9]+)/40 frames ([0-9]+\\.[0-9])% [0-9]+\\.[0-9]+ frames/s eta [0-9]+ s");
  const std::vector<std::string> printed = lines_of(slurp(dir / "err.txt"));
  ASSERT_GE(printed.size(), 2u) << slurp(dir / "err.txt");
  EXPECT_LE(printed.size(), 21u);  // at most one per 5% (and per 10 s)
  std::size_t last = 0;
  for (const std::string& text : printed) {
    std::smatch m;
    ASSERT_TRUE(std::regex_match(text, m, line)) << text;
    EXPECT_GT(std::stoul(m[1]), last) << text;
    last = std::stoul(m[1]);
  }
  EXPECT_EQ(last, 40u);
  EXPECT_NE(printed.back().find(" 100.0% "), std::string::npos);
  // auto (stderr is not a terminal here), none, and -q: no progress; -q with --progress: progress only.
  for (const std::string extra : {"", " --progress none", " --progress auto", " -q"}) {
    const auto result = run_pleat_split("visibility " + input + output + extra, dir / "err.txt");
    EXPECT_EQ(result.exit_code, 0);
    EXPECT_EQ(slurp(dir / "err.txt"), "") << extra;
  }
  const auto quiet_lines = run_pleat("-q --progress lines generate flag -o " + (dir / "f.obj").string() +
                                     " --resolution 4 --frames 20");
  EXPECT_EQ(quiet_lines.exit_code, 0);
  EXPECT_EQ(quiet_lines.output.find("wrote"), std::string::npos) << quiet_lines.output;
  EXPECT_NE(quiet_lines.output.find("pleat: generate 20/20 frames 100.0% "), std::string::npos)
      << quiet_lines.output;
}

TEST(CommandLine, VisibilityWarnsWhenTheFirstFrameSelfIntersects) {
  // Two triangles piercing each other in frame 1 only.
  test::TempDir dir;
  test::write_piercing_pair(dir.path());
  const std::string input =
      (dir / "x.obj").string() + " --cache " + (dir / "x.pc2").string() + " -o " + (dir / "v.csv").string();
  const std::string warning = "pleat: warning: frame 1 self-intersects (1 face pair)";
  for (const std::string extra : {"", " -q"}) {  // a warning stays with -q
    const auto result = run_pleat("visibility " + input + " --frames 1:2" + extra);
    EXPECT_EQ(result.exit_code, 0) << result.output;
    EXPECT_NE(result.output.find(warning), std::string::npos) << result.output;
    EXPECT_TRUE(fs::exists(dir / "v.csv"));
  }
  const auto clean = run_pleat("visibility " + input + " --frames 0:2");  // only the first frame is checked
  EXPECT_EQ(clean.exit_code, 0) << clean.output;
  EXPECT_EQ(clean.output.find("warning: frame"), std::string::npos) << clean.output;
}

}  // namespace
}  // namespace pleat
