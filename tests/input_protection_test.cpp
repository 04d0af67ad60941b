// No output is ever one of the run's inputs (cli/output_paths.hpp): an output path that names an input, as
// given, through a symbolic link (of the file or of a directory on the way) or through a hard link, is
// refused before any work with exit status 2 and a message naming both; the input is left byte for byte as it
// was.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace pleat {
namespace {

using test::slurp;
namespace fs = std::filesystem;

struct Case {
  std::string args;    // the pleat command line
  std::string output;  // the option and output path the message names
  std::string input;   // the option and input path the message names
  fs::path guarded;    // the input that must stay as it was
};

class InputProtection : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto made = test::run_pleat("generate curtain -o " + path("d.obj") + " --resolution 8 --frames 3");
    ASSERT_EQ(made.exit_code, 0) << made.output;
    std::ofstream(dir / "p.obj") << "v -5 -1 -5\nv 5 -1 -5\nv 5 -1 5\nv -5 -1 5\nf 1 2 3 4\n";
    const auto plan = test::run_pleat("visibility " + cloth() + " -o " + path("v0.csv") + " --save-plan " +
                                      path("plan.json"));
    ASSERT_EQ(plan.exit_code, 0) << plan.output;
    const auto glb = test::run_pleat("shade " + cloth() + " -o " + path("cloth.glb"));
    ASSERT_EQ(glb.exit_code, 0) << glb.output;
  }
  std::string path(const std::string& name) const { return (dir / name).string(); }
  std::string cloth() const { return path("d.obj") + " --cache " + path("d.pc2"); }

  // Runs the case: refused with exit status 2 before any work, the message naming both files, the input
  // unchanged, and the run's other outputs not written.
  void expect_refused(const Case& c, const fs::path& never_written) {
    SCOPED_TRACE(c.args);
    const std::string before = slurp(c.guarded);
    ASSERT_FALSE(before.empty());
    const auto run = test::run_pleat(c.args);
    EXPECT_EQ(run.exit_code, 2) << run.output;
    EXPECT_NE(run.output.find("pleat never writes over its inputs"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find(c.output), std::string::npos) << run.output;
    EXPECT_NE(run.output.find(c.input), std::string::npos) << run.output;
    EXPECT_EQ(run.output.find("wrote"), std::string::npos) << run.output;
    EXPECT_TRUE(slurp(c.guarded) == before) << c.guarded << " was changed";
    EXPECT_FALSE(fs::exists(never_written)) << never_written;
  }

  test::TempDir dir;
};

TEST_F(InputProtection, AnOutputNamedAsAnInputIsRefused) {
  const fs::path csv = dir / "v.csv";
  const std::string visibility = "visibility " + cloth() + " -o " + csv.string();
  expect_refused({visibility + " --save-plan " + path("d.pc2"), "--save-plan " + path("d.pc2"), "(--cache",
                  dir / "d.pc2"},
                 csv);
  expect_refused(
      {"visibility " + cloth() + " -o " + path("d.obj"), "-o " + path("d.obj"), "(INPUT", dir / "d.obj"},
      dir / "never");
  expect_refused(
      {visibility + " --cones " + path("d.pc2"), "--cones " + path("d.pc2"), "(--cache", dir / "d.pc2"}, csv);
  expect_refused({visibility + " --stats " + path("p.obj") + " --occluder " + path("p.obj"),
                  "--stats " + path("p.obj"), "(--occluder", dir / "p.obj"},
                 csv);
  expect_refused({visibility + " --timings " + path("plan.json") + " --plan " + path("plan.json"),
                  "--timings " + path("plan.json"), "(--plan", dir / "plan.json"},
                 csv);
  expect_refused({"shade " + path("cloth.glb") + " -o " + path("cloth.glb"), "-o " + path("cloth.glb"),
                  "(INPUT", dir / "cloth.glb"},
                 dir / "never");
  expect_refused({"compare " + cloth() + " --light sky:1 -o " + path("d.pc2"), "-o " + path("d.pc2"),
                  "(--cache", dir / "d.pc2"},
                 dir / "never");
}

TEST_F(InputProtection, ThroughSymbolicAndHardLinks) {
  fs::create_symlink(dir / "d.pc2", dir / "link.cones");
  fs::create_hard_link(dir / "d.pc2", dir / "hard.json");
  fs::create_directories(dir / "sub");
  fs::create_directory_symlink(dir.path(), dir / "sub/alias");  // a directory link on the way
  const fs::path csv = dir / "v.csv";
  const std::string visibility = "visibility " + cloth() + " -o " + csv.string();
  expect_refused(
      {visibility + " --cones " + path("link.cones"), "--cones " + path("link.cones"),
       "is the input " + path("d.pc2") + " (--cache, the same file under another name)", dir / "d.pc2"},
      csv);
  expect_refused(
      {visibility + " --stats " + path("hard.json"), "--stats " + path("hard.json"),
       "is the input " + path("d.pc2") + " (--cache, the same file under another name)", dir / "d.pc2"},
      csv);
  expect_refused({"visibility " + cloth() + " -o " + path("sub/alias/d.obj"), "-o " + path("sub/alias/d.obj"),
                  "is the input " + path("d.obj"), dir / "d.obj"},
                 dir / "never");
  EXPECT_TRUE(fs::is_symlink(dir / "link.cones"));
}

TEST_F(InputProtection, FilesOfSequencesLightsAndRenderDirectories) {
  // A frame of a numbered OBJ sequence.
  fs::create_directories(dir / "seq");
  for (const char* name : {"f_0000.obj", "f_0001.obj", "f_0002.obj"})
    fs::copy_file(dir / "d.obj", dir / "seq" / name);
  expect_refused({"visibility " + path("seq/f_%04d.obj") + " -o " + path("seq/f_0001.obj"),
                  "-o " + path("seq/f_0001.obj"), "(INPUT", dir / "seq/f_0001.obj"},
                 dir / "never");
  // An environment map, as the output and as an image the render directory would replace.
  fs::copy_file(test::source_dir() / "data/envmaps/sky_sun.hdr", dir / "sky.hdr");
  expect_refused({"shade " + cloth() + " --light env:" + path("sky.hdr") + " -o " + path("sky.hdr"),
                  "-o " + path("sky.hdr"), "(--light env:", dir / "sky.hdr"},
                 dir / "never");
  fs::create_directories(dir / "renders");
  fs::copy_file(dir / "sky.hdr", dir / "renders/frame_0001.png");  // any bytes: it is read as the map
  const auto render = test::run_pleat("shade " + cloth() + " --light env:" + path("renders/frame_0001.png") +
                                      " -o " + path("s.glb") + " --render " + path("renders"));
  EXPECT_EQ(render.exit_code, 2) << render.output;
  EXPECT_NE(render.output.find("--render " + path("renders") + " would write frame_0001.png"),
            std::string::npos)
      << render.output;
  EXPECT_TRUE(slurp(dir / "renders/frame_0001.png") == slurp(dir / "sky.hdr"));
  EXPECT_FALSE(fs::exists(dir / "s.glb"));
}

TEST_F(InputProtection, OutputsBesideTheInputsAreWritten) {
  // The check refuses only what is an input: other names in the same directories are written as before.
  const auto run =
      test::run_pleat("visibility " + cloth() + " -o " + path("v.csv") + " --cones " + path("d.cones") +
                      " --save-plan " + path("plan2.json") + " --plan " + path("plan.json"));
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(fs::exists(dir / "v.csv"));
  EXPECT_TRUE(fs::exists(dir / "d.cones"));
}

}  // namespace
}  // namespace pleat
