// pleat visibility: the CSV contract (docs/method.md §12), --frames, --stats, and clean failures with no
// output.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <utility>

#include "sim_io/visibility_csv.hpp"
#include "test_support.hpp"

namespace pleat {
namespace {

using test::slurp;

TEST(VisibilityCommand, WritesOneRowPerFrameAndInputVertexIntoNewDirectories) {
  test::TempDir dir;
  ASSERT_EQ(
      test::run_pleat("generate curtain -o " + (dir / "in/c.obj").string() + " --resolution 9 --frames 4")
          .exit_code,
      0);
  const auto result = test::run_pleat("visibility " + (dir / "in/c.obj").string() + " --cache " +
                                      (dir / "in/c.pc2").string() + " -o " + (dir / "out/v.csv").string() +
                                      " --frames 1:3 --stats " + (dir / "out/s.json").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const auto rows = read_visibility_csv(dir / "out/v.csv");
  ASSERT_EQ(rows.size(), 2u * 81u);
  EXPECT_EQ(rows.front().frame, 1u);
  EXPECT_EQ(rows.back().frame, 2u);
  EXPECT_EQ(rows.back().vertex, 80u);
  for (const auto& r : rows) {
    EXPECT_GE(r.front, 0.0);
    EXPECT_LE(r.front, 1.0);
    EXPECT_GE(r.back, 0.0);
    EXPECT_LE(r.back, 1.0);
  }
  std::ifstream stats(dir / "out/s.json");
  const auto json = nlohmann::json::parse(stats);
  ASSERT_EQ(json["frames"].size(), 2u);
  EXPECT_GT(json["frames"][0]["slice_vertices"].get<int>(), 0);
  EXPECT_EQ(json["frames"][0]["filled_fraction"].size(), 8u);  // the default plan's orientations
}

TEST(VisibilityCommand, SpacingInEdgeLengths) {
  test::TempDir dir;
  ASSERT_EQ(test::run_pleat("generate flag -o " + (dir / "f.obj").string() + " --resolution 12 --frames 2")
                .exit_code,
            0);
  const std::string input =
      (dir / "f.obj").string() + " --cache " + (dir / "f.pc2").string() + " --frames 0:1";
  auto slice_vertices = [&](const std::string& plan) {
    const auto result = test::run_pleat("visibility " + input + " -o " + (dir / "v.csv").string() +
                                        " --stats " + (dir / "s.json").string() + plan);
    EXPECT_EQ(result.exit_code, 0) << result.output;
    std::ifstream stats(dir / "s.json");
    return std::pair{nlohmann::json::parse(stats)["frames"][0]["slice_vertices"].get<int>(), result.output};
  };
  const auto [by_default, default_output] = slice_vertices("");
  const auto [half, half_output] = slice_vertices(" --spacing-edges 0.5");
  const auto [one, one_output] = slice_vertices(" --spacing-edges 1");
  EXPECT_EQ(half, by_default);  // the default is half an edge
  EXPECT_NE(default_output.find("spacing = 0.5 of the average edge length"), std::string::npos)
      << default_output;
  EXPECT_NE(one_output.find("spacing = 1 of the average edge length"), std::string::npos) << one_output;
  EXPECT_LT(one, 0.7 * half);  // about half the planes
  EXPECT_GT(one, 0.3 * half);
  // An absolute spacing and one in edge lengths at once: one clear error, no output.
  const auto both = test::run_pleat("visibility " + input + " -o " + (dir / "both.csv").string() +
                                    " --spacing 0.1 --spacing-edges 1");
  EXPECT_NE(both.exit_code, 0);
  EXPECT_NE(both.output.find("exclude"), std::string::npos) << both.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "both.csv"));
}

TEST(VisibilityCommand, MissingInputFailsCleanlyAndWritesNothing) {
  test::TempDir dir;
  const auto result =
      test::run_pleat("visibility " + (dir / "nope.obj").string() + " -o " + (dir / "v.csv").string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("nope.obj"), std::string::npos) << result.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "v.csv"));
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

/// The lines of a CSV after its header.
std::string csv_rows(const std::filesystem::path& p) {
  const std::string text = slurp(p);
  const std::size_t header_end = text.find('\n');
  return header_end == std::string::npos ? std::string() : text.substr(header_end + 1);
}

/// A farm splits a shot by --frames: the pieces concatenate to the full run's bytes, with either engine,
/// any chunking, and a plan pinned in a file; `shade` renders a frame the same from any range.
TEST(VisibilityCommand, ASplitShotConcatenatesToTheFullRunsBytes) {
  test::TempDir dir;
  ASSERT_EQ(test::run_pleat("generate flag -o " + (dir / "f.obj").string() + " --resolution 11 --frames 9")
                .exit_code,
            0);
  const std::string input = (dir / "f.obj").string() + " --cache " + (dir / "f.pc2").string();
  auto visibility = [&](const std::string& name, const std::string& options) {
    const auto result =
        test::run_pleat("visibility " + input + " -o " + (dir / name).string() + " " + options);
    EXPECT_EQ(result.exit_code, 0) << result.output;
    return csv_rows(dir / name);
  };
  const std::string full = visibility("full.csv", "--save-plan " + (dir / "plan.json").string());
  ASSERT_GT(full.size(), 9u * 121u * 10u);
  for (const std::string engine : {"kinetic", "static"}) {
    const std::string pieces = visibility("a.csv", "--frames 0:3 --engine " + engine) +
                               visibility("b.csv", "--frames 3:4 --engine " + engine) +
                               visibility("c.csv", "--frames 4: --chunks 2 --engine " + engine);
    EXPECT_TRUE(pieces == full) << engine << ": the pieces differ from the full run";
  }
  EXPECT_TRUE(visibility("chunked.csv", "--chunks 4") == full);
  // A pinned plan, read back, cuts with the same planes.
  const std::string last_two = full.substr(full.find("\n7,") + 1);
  EXPECT_TRUE(visibility("pinned.csv", "--frames 7: --plan " + (dir / "plan.json").string()) == last_two);
  // --plan replaces every placement option: together they are a usage error.
  const auto both = test::run_pleat("visibility " + input + " -o " + (dir / "both.csv").string() +
                                    " --plan " + (dir / "plan.json").string() + " --orientations 12");
  EXPECT_NE(both.exit_code, 0);
  EXPECT_FALSE(std::filesystem::exists(dir / "both.csv"));

  // shade: frame 6 rendered in a run of the whole shot and in a run of its last three frames.
  for (const std::string range : {"0:9", "6:9"}) {
    const auto shaded =
        test::run_pleat("shade " + input + " -o " + (dir / ("s" + range.substr(0, 1) + ".glb")).string() +
                        " -q --frames " + range + " --render-every 3 --width 48 --height 36 --render " +
                        (dir / ("r" + range.substr(0, 1))).string());
    ASSERT_EQ(shaded.exit_code, 0) << shaded.output;
  }
  const std::string image = slurp(dir / "r0" / "frame_0006.png");
  EXPECT_GT(image.size(), 100u);
  EXPECT_TRUE(image == slurp(dir / "r6" / "frame_0006.png"));
}

/// The bundled pile in its scene: --ground y=0 darkens the side lying on the ground (the cloth alone sees sky
/// through the floor); the drape's turning table as an animated --occluder; a bad occluder is one clear
/// error naming its file, exit 2, no output.
TEST(VisibilityCommand, OccludersAndTheGroundBlockTheSky) {
  test::TempDir dir;
  const std::string data = std::string(PLEAT_SOURCE_DIR) + "/data/";
  const std::string pile =
      data + "pile/pile.obj --cache " + data + "pile/pile.pc2 --frames -1: --engine static";
  auto mean_back = [&](const std::string& csv) {
    double sum = 0.0;
    const auto rows = read_visibility_csv(dir / csv);
    for (const auto& r : rows) sum += std::min(r.front, r.back);
    return sum / double(rows.size());
  };
  ASSERT_EQ(test::run_pleat("visibility " + pile + " -o " + (dir / "alone.csv").string()).exit_code, 0);
  const auto grounded =
      test::run_pleat("visibility " + pile + " --ground y=0 -o " + (dir / "ground.csv").string());
  ASSERT_EQ(grounded.exit_code, 0) << grounded.output;
  EXPECT_GT(mean_back("alone.csv"), 0.2);    // the down side sees the sky through the floor
  EXPECT_LT(mean_back("ground.csv"), 0.01);  // with the ground it sees (almost) nothing
  const std::string drape = data + "drape/drape.obj --cache " + data + "drape/drape.pc2 --frames 30:32";
  const std::string table = " --occluder " + data + "drape/drape_colliders.obj,cache=" + data +
                            "drape/drape_colliders.pc2 --ground y=0";
  const auto on_table = test::run_pleat("visibility " + drape + table + " -o " + (dir / "t.csv").string());
  ASSERT_EQ(on_table.exit_code, 0) << on_table.output;
  ASSERT_EQ(test::run_pleat("visibility " + drape + " -o " + (dir / "f.csv").string()).exit_code, 0);
  EXPECT_LT(mean_back("t.csv"), mean_back("f.csv") - 0.05);
  // An animated occluder that misses the cloth's first frames (the plies' colliders, scene frames 31-110,
  // against the pile's 21-100): one error naming it and both ranges, exit 2, nothing written.
  const auto wrong = test::run_pleat("visibility " + pile + " --occluder " + data +
                                     "layered/layered_colliders.obj,cache=" + data +
                                     "layered/layered_colliders.pc2 -o " + (dir / "w.csv").string());
  EXPECT_EQ(wrong.exit_code, 2);
  EXPECT_NE(wrong.output.find("layered_colliders.pc2"), std::string::npos) << wrong.output;
  EXPECT_NE(
      wrong.output.find("no source frame 21 (it holds frames 31 to 110 in 80 frames, the cloth frames 21 to "
                        "100 in 80)"),
      std::string::npos)
      << wrong.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "w.csv"));
  const auto bad = test::run_pleat("visibility " + pile + " --ground up=0 -o " + (dir / "b.csv").string());
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("AXIS=VALUE"), std::string::npos) << bad.output;
}

/// `pleat visibility` on the bundled sequence `name` (data/NAME/NAME.obj and .pc2) over `frames`: with the
/// kinetic engine (the default; `kinetic_extra` options added) into dir/k.csv, with the static one into
/// dir/s.csv.
std::pair<test::CommandResult, test::CommandResult> run_both_engines(const std::string& name,
                                                                     const std::string& frames,
                                                                     const std::filesystem::path& dir,
                                                                     const std::string& kinetic_extra = "") {
  const std::string data = std::string(PLEAT_SOURCE_DIR) + "/data/" + name + "/" + name;
  const std::string input = data + ".obj --cache " + data + ".pc2 --frames " + frames;
  return {test::run_pleat("visibility " + input + " -o " + (dir / "k.csv").string() + kinetic_extra),
          test::run_pleat("visibility " + input + " -o " + (dir / "s.csv").string() + " --engine static")};
}

/// The acceptance check on the bundled real sequence: the kinetic engine (the default) and the
/// static one write the same CSV, byte for byte (the first 12 frames here; all 100 in the closing note).
TEST(VisibilityCommand, KineticAndStaticEnginesWriteTheSameCsvOnTheBundledDrape) {
  test::TempDir dir;
  const auto [kinetic, fixed] = run_both_engines(
      "drape", "0:12", dir.path(),
      " --stats " + (dir / "k.json").string() + " --timings " + (dir / "k_timings.json").string());
  ASSERT_EQ(kinetic.exit_code, 0) << kinetic.output;
  ASSERT_EQ(fixed.exit_code, 0) << fixed.output;
  const std::string k = slurp(dir / "k.csv"), s = slurp(dir / "s.csv");
  EXPECT_GT(k.size(), 12u * 3111u * 10u);
  EXPECT_TRUE(k == s) << "the kinetic and static CSVs differ";
  // How the run went is in --timings (per-frame kinetic counters); --stats holds what the frames determine.
  const std::string stats = slurp(dir / "k_timings.json");
  EXPECT_EQ(slurp(dir / "k.json").find("\"seconds\""), std::string::npos);
  EXPECT_NE(stats.find("\"kinetic\""), std::string::npos);
  EXPECT_NE(stats.find("\"certificates_failed\""), std::string::npos);
  EXPECT_NE(stats.find("\"slices_rebuilt\""), std::string::npos);
}

TEST(VisibilityCommand, KineticAndStaticEnginesWriteTheSameCsvOnTheLayeredPlies) {
  // Three components lying millimetres apart: nested chains and holes in every slice, kept alive by the
  // kinetic engine while the plies slide over each other (the last frames, where they land in a heap).
  test::TempDir dir;
  const auto [kinetic, fixed] = run_both_engines("layered", "-8:", dir.path());
  ASSERT_EQ(kinetic.exit_code, 0) << kinetic.output;
  ASSERT_EQ(fixed.exit_code, 0) << fixed.output;
  const std::string k = slurp(dir / "k.csv"), s = slurp(dir / "s.csv");
  EXPECT_GT(k.size(), 8u * 4107u * 10u);
  EXPECT_TRUE(k == s) << "the kinetic and static CSVs differ";
}

}  // namespace
}  // namespace pleat
