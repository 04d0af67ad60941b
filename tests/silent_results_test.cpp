// Never a silent zero or a silent default: a plan spacing wider than the cloth, plan values that are not
// values (0, NaN), vertices without a surface, scenes scaled beyond double range, a cloth without area. Each
// is refused with a message naming the option or the input, or written and warned about, on the command line
// and in the library alike.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <regex>
#include <string>
#include <vector>

#include "sim_io/load_sequence.hpp"
#include "sim_io/plan_file.hpp"
#include "sim_io/sequence_plan.hpp"
#include "sim_io/visibility_csv.hpp"
#include "sim_io_fixtures.hpp"
#include "support/input_error.hpp"
#include "test_support.hpp"

namespace pleat {
namespace {

namespace fs = std::filesystem;
using test::run_pleat;

// dir/c.obj + dir/c.pc2, a generated curtain of 6 x 6 vertices over 3 frames; returns the input arguments.
std::string small_curtain(const fs::path& dir) {
  const auto made =
      run_pleat("generate curtain -o " + (dir / "c.obj").string() + " --resolution 6 --frames 3");
  EXPECT_EQ(made.exit_code, 0) << made.output;
  return (dir / "c.obj").string() + " --cache " + (dir / "c.pc2").string();
}

// `pleat visibility INPUT EXTRA -o dir/v.csv`, expected to be refused with exit status 2 and `message`.
void expect_refused(const fs::path& dir, const std::string& input, const std::string& extra,
                    const std::string& message) {
  const auto result = run_pleat("visibility " + input + " " + extra + " -o " + (dir / "v.csv").string());
  EXPECT_EQ(result.exit_code, 2) << extra << "\n" << result.output;
  EXPECT_NE(result.output.find(message), std::string::npos) << extra << "\n" << result.output;
  EXPECT_FALSE(fs::exists(dir / "v.csv")) << extra;
}

TEST(SilentResults, ASpacingWiderThanTheClothIsRefused) {
  test::TempDir dir;
  const std::string input = small_curtain(dir.path());
  expect_refused(dir.path(), input, "--spacing 1e9", "--spacing 1e+09 is wider than the cloth");
  expect_refused(dir.path(), input, "--spacing-edges 1e9", "--spacing-edges 1e+09 (a spacing of");
  // A plan file pinning a spacing of 1e300.
  ASSERT_EQ(run_pleat("visibility " + input + " -q -o " + (dir / "a.csv").string() + " --save-plan " +
                      (dir / "plan.json").string())
                .exit_code,
            0);
  SlicingPlan plan = read_plan_file(dir / "plan.json");
  plan.spacing = 1e300;
  write_plan_file(dir / "wide.json", plan);
  expect_refused(dir.path(), input, "--plan " + (dir / "wide.json").string(),
                 "the spacing 1e+300 of the plan file " + (dir / "wide.json").string() + " is wider");
  // Up to the cloth's extent a plane cuts it: no vertex is left at 0 on both sides.
  const auto fitting = run_pleat("visibility " + input + " -q --spacing 1.5 -o " + (dir / "v.csv").string());
  ASSERT_EQ(fitting.exit_code, 0) << fitting.output;
  double total = 0.0;
  for (const VisibilityRow& row : read_visibility_csv(dir / "v.csv")) total += row.front + row.back;
  EXPECT_GT(total, 0.0);
}

TEST(SilentResults, TheLibraryRefusesAWideSpacingNamingTheKeywordAndTheInput) {
  const MeshSequence sheet = test::folding_sheet(4, 4, 2);
  PlanOptions options;
  options.spacing = 1e9;
  try {
    options.make(sheet);
    FAIL() << "a spacing of 1e9 over a unit sheet was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("spacing=1e+09 is wider than the cloth folding_sheet"),
              std::string::npos)
        << e.what();
  }
  options.spacing = 0.2;
  EXPECT_NO_THROW(options.make(sheet));
}

TEST(SilentResults, ZeroAndNanPlanValuesAreRefusedNotDefaulted) {
  test::TempDir dir;
  const std::string input = small_curtain(dir.path());
  expect_refused(dir.path(), input, "--planes 0", "--planes: must be >= 1, got 0");
  expect_refused(dir.path(), input, "--spacing 0", "--spacing: must be a finite number > 0, got 0");
  expect_refused(dir.path(), input, "--spacing nan", "--spacing: must be a finite number > 0, got nan");
  expect_refused(dir.path(), input, "--spacing -1", "--spacing: must be a finite number > 0, got -1");
  expect_refused(dir.path(), input, "--spacing-edges 0",
                 "--spacing-edges: must be a finite number > 0, got 0");
  expect_refused(dir.path(), input, "--spacing inf", "--spacing: must be a finite number > 0, got inf");
  // The library's check says the same of the same values, under the Python keywords.
  struct Case {
    PlanOptions options;
    std::string message;
  };
  std::vector<Case> cases(4);
  cases[0].options.planes_per_orientation = 0, cases[0].message = "planes: must be >= 1, got 0";
  cases[1].options.spacing = 0.0, cases[1].message = "spacing: must be a finite number > 0, got 0";
  cases[2].options.spacing = std::nan(""), cases[2].message = "spacing: must be a finite number > 0, got nan";
  cases[3].options.spacing_edges = 0.0,
  cases[3].message = "spacing_edges: must be a finite number > 0, got 0";
  for (const Case& c : cases) {
    try {
      c.options.check();
      ADD_FAILURE() << "accepted: " << c.message;
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()), c.message);
    }
    try {
      c.options.check(PlanOptions::Naming::CommandLine);
      ADD_FAILURE() << "accepted: " << c.message;
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()), "--" + std::regex_replace(c.message, std::regex("_"), "-"));
    }
  }
}

TEST(SilentResults, VerticesNoTriangleUsesHaveNoValueAndAreNamed) {
  test::TempDir dir;
  // A square of two triangles, and vertex 2 (0-based) which no face uses.
  test::write_bytes(dir / "s.obj", "v 0 0 0\nv 1 0 0\nv 5 5 5\nv 1 0 1\nv 0 0 1\nf 1 2 4\nf 1 4 5\n");
  const auto result = run_pleat("visibility " + (dir / "s.obj").string() + " -o " + (dir / "v.csv").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("warning: " + (dir / "s.obj").string() +
                               ": vertex 2 belongs to no triangle: no surface, so no visibility"),
            std::string::npos)
      << result.output;
  EXPECT_NE(test::slurp(dir / "v.csv").find("\n0,2,,,0\n"), std::string::npos) << test::slurp(dir / "v.csv");
  const std::vector<VisibilityRow> rows = read_visibility_csv(dir / "v.csv");
  ASSERT_EQ(rows.size(), 5u);
  for (const VisibilityRow& row : rows) {
    if (row.vertex == 2) {
      EXPECT_TRUE(std::isnan(row.front) && std::isnan(row.back));
    } else {
      EXPECT_DOUBLE_EQ(row.front, 1.0);  // a flat sheet alone sees the whole sky on both sides
      EXPECT_DOUBLE_EQ(row.back, 1.0);
    }
  }
}

// dir/NAME: the curtain's first frame with every coordinate multiplied by `scale`.
fs::path scaled_curtain(const fs::path& dir, const std::string& name, double scale) {
  const MeshSequence curtain = load_sequence(dir / "c.obj");
  std::vector<glm::dvec3> positions = curtain.frame(0).positions;
  for (glm::dvec3& p : positions) p *= scale;
  write_obj(dir / name, curtain.topology(), positions);
  return dir / name;
}

TEST(SilentResults, ScenesBeyondDoubleRangeAreRefusedNamingTheInput) {
  test::TempDir dir;
  small_curtain(dir.path());
  for (double scale : {1e-300, 1e-40}) {
    const fs::path tiny = scaled_curtain(dir.path(), "tiny.obj", scale);
    const auto result = run_pleat("visibility " + tiny.string() + " -o " + (dir / "v.csv").string());
    EXPECT_EQ(result.exit_code, 2) << result.output;
    EXPECT_NE(result.output.find("pleat: error: " + tiny.string() + ": the mesh spans only"),
              std::string::npos)
        << result.output;
    EXPECT_FALSE(fs::exists(dir / "v.csv"));
  }
  for (double scale : {1e100, 1e200}) {
    const fs::path huge = scaled_curtain(dir.path(), "huge.obj", scale);
    const auto result = run_pleat("visibility " + huge.string() + " -o " + (dir / "v.csv").string());
    EXPECT_EQ(result.exit_code, 2) << result.output;
    EXPECT_NE(result.output.find("pleat: error: " + huge.string() + ":frame 0, vertex 0: coordinate"),
              std::string::npos)
        << result.output;
    EXPECT_EQ(result.output.find("cover_with_planes"), std::string::npos) << result.output;
  }
  // Within the range the unit does not matter: scaled by 2^-83 or 2^40 (about 1e-25, 1e12; exactly, as a
  // power of two), the same values bit for bit.
  const auto reference = run_pleat("visibility " + scaled_curtain(dir.path(), "one.obj", 1.0).string() +
                                   " -q -o " + (dir / "one.csv").string());
  ASSERT_EQ(reference.exit_code, 0) << reference.output;
  for (int exponent : {-83, 40}) {
    const auto result =
        run_pleat("visibility " + scaled_curtain(dir.path(), "s.obj", std::ldexp(1.0, exponent)).string() +
                  " -q -o " + (dir / "s.csv").string());
    ASSERT_EQ(result.exit_code, 0) << result.output;
    EXPECT_EQ(test::slurp(dir / "s.csv"), test::slurp(dir / "one.csv")) << "2^" << exponent;
  }
}

TEST(SilentResults, TheLibraryRefusesCoordinatesBeyondItsRange) {
  const MeshTopology triangle{.num_vertices = 3, .triangles = {{0, 1, 2}}};
  const auto sequence = [&](double scale) {
    std::vector<std::vector<glm::dvec3>> frames = {{{0, 0, 0}, {scale, 0, 0}, {0, 0, scale}}};
    return MeshSequence("arrays", triangle.triangles, 3, make_memory_source(std::move(frames), {0.0}));
  };
  EXPECT_NO_THROW(sequence(1e12));
  EXPECT_NO_THROW(sequence(1e-25));
  try {
    sequence(1e100);
    ADD_FAILURE() << "1e100 accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "arrays");
    EXPECT_EQ(e.place(), "frame 0, vertex 1");
  }
  try {
    sequence(1e-300);
    ADD_FAILURE() << "1e-300 accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "arrays");
    EXPECT_NE(std::string(e.what()).find("the mesh spans only 1e-300"), std::string::npos) << e.what();
  }
}

TEST(SilentResults, ACollinearTriangleIsWarnedAbout) {
  test::TempDir dir;
  test::write_bytes(dir / "line.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
  const auto alone =
      run_pleat("visibility " + (dir / "line.obj").string() + " -o " + (dir / "v.csv").string());
  ASSERT_EQ(alone.exit_code, 0) << alone.output;
  EXPECT_NE(
      alone.output.find("warning: " + (dir / "line.obj").string() +
                        ": frame 0: every triangle is degenerate (collinear corners: no area, they block "
                        "nothing; the cloth has no surface"),
      std::string::npos)
      << alone.output;
  // One of several: counted.
  test::write_bytes(dir / "some.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n");
  const auto some =
      run_pleat("visibility " + (dir / "some.obj").string() + " -o " + (dir / "w.csv").string());
  ASSERT_EQ(some.exit_code, 0) << some.output;
  EXPECT_NE(some.output.find("frame 0: 1 of 2 triangles are degenerate"), std::string::npos) << some.output;
  // A clean cloth: no warning.
  const std::string input = small_curtain(dir.path());
  const auto clean = run_pleat("visibility " + input + " -o " + (dir / "x.csv").string());
  ASSERT_EQ(clean.exit_code, 0);
  EXPECT_EQ(clean.output.find("warning"), std::string::npos) << clean.output;
}

}  // namespace
}  // namespace pleat
