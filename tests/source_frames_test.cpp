// Source frame numbers (MeshSequence::source_frame, docs/method.md §12): the PC2 start frame and sample
// rate, the numbers in an OBJ sequence's file names, MDD and glTF times x the scene rate; carried into the
// visibility CSV's source_frame column, `pleat shade --render` file names and the glb's frame times, while
// --frames keeps selecting by 0-based index.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "sim_io/load_sequence.hpp"
#include "sim_io/mdd_format.hpp"
#include "sim_io/mesh_sequence.hpp"
#include "sim_io/obj_format.hpp"
#include "sim_io/pc2_format.hpp"
#include "sim_io/visibility_csv.hpp"
#include "sim_io_fixtures.hpp"
#include "support/input_error.hpp"

namespace pleat {
namespace {

const MeshTopology kQuad{4, {{0, 1, 2}, {0, 2, 3}}};

/// Frame k of a folding quad: its last corner lifts by 0.1 k.
std::vector<glm::dvec3> quad(int k) { return {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0.1 * k}}; }

std::vector<std::int64_t> source_frames(const MeshSequence& s) {
  std::vector<std::int64_t> out;
  for (std::size_t i = 0; i < s.num_frames(); ++i) out.push_back(s.source_frame(i));
  return out;
}

TEST(SourceFrames, ComeFromEveryFormat) {
  test::TempDir dir;
  write_obj(dir / "q.obj", kQuad, quad(0));
  write_pc2(dir / "a.pc2", {quad(0), quad(1), quad(2)}, 12.0, 1.0);
  EXPECT_EQ(source_frames(load_sequence(dir / "q.obj", dir / "a.pc2")),
            (std::vector<std::int64_t>{12, 13, 14}));
  write_pc2(dir / "b.pc2", {quad(0), quad(1), quad(2)}, -3.0, 2.0);  // every other scene frame
  EXPECT_EQ(source_frames(load_sequence(dir / "q.obj", dir / "b.pc2")),
            (std::vector<std::int64_t>{-3, -1, 1}));
  write_mdd(dir / "c.mdd", {quad(0), quad(1)}, {0.5, 0.75});  // 24 fps: scene frames 12 and 18
  EXPECT_EQ(source_frames(load_sequence(dir / "q.obj", dir / "c.mdd")), (std::vector<std::int64_t>{12, 18}));
  LoadOptions at_30;
  at_30.scene_fps = 30.0;
  EXPECT_EQ(source_frames(load_sequence(dir / "q.obj", dir / "c.mdd", at_30)),
            (std::vector<std::int64_t>{15, 23}));
  // A single .obj: frame 0.
  EXPECT_EQ(source_frames(load_sequence(dir / "q.obj")), (std::vector<std::int64_t>{0}));
}

TEST(SourceFrames, AreTheNumbersInAnObjSequencesNames) {
  test::TempDir dir;
  std::filesystem::create_directories(dir / "seq");
  for (int n : {12, 13, 14}) write_obj(dir / ("seq/frame_00" + std::to_string(n) + ".obj"), kQuad, quad(n));
  const MeshSequence pattern = load_sequence((dir / "seq/frame_%04d.obj").string());
  EXPECT_EQ(source_frames(pattern), (std::vector<std::int64_t>{12, 13, 14}));
  EXPECT_DOUBLE_EQ(pattern.frame_time(0), 12.0 / kDefaultSceneFps);
  EXPECT_DOUBLE_EQ(pattern.frame_rate(), kDefaultSceneFps);
  // A directory may hold every other frame (exported every 2): they stay the frames' numbers.
  std::filesystem::create_directories(dir / "every2");
  for (int n : {10, 12, 14}) write_obj(dir / ("every2/take2_f" + std::to_string(n) + ".obj"), kQuad, quad(n));
  EXPECT_EQ(source_frames(load_sequence(dir / "every2")), (std::vector<std::int64_t>{10, 12, 14}));
  // A single file needs no number: frame 0.
  std::filesystem::create_directories(dir / "named");
  write_obj(dir / "named/rest.obj", kQuad, quad(1));
  EXPECT_EQ(source_frames(load_sequence(dir / "named")), (std::vector<std::int64_t>{0}));
}

TEST(SourceFrames, NameTheCsvRowsRendersAndGlbFramesWhileFramesSelectsByIndex) {
  test::TempDir dir;
  ASSERT_EQ(test::run_pleat("generate flag -o " + (dir / "f.obj").string() + " --resolution 7 --frames 4")
                .exit_code,
            0);
  // The flag's frames again, as a PC2 cache starting at scene frame 101.
  const MeshSequence flag = load_sequence(dir / "f.obj", dir / "f.pc2");
  write_pc2(dir / "late.pc2", test::all_positions(flag), 101.0, 1.0);
  const std::string input = (dir / "f.obj").string() + " --cache " + (dir / "late.pc2").string();

  const auto v = test::run_pleat("visibility " + input + " --frames 1:3 -o " + (dir / "v.csv").string());
  ASSERT_EQ(v.exit_code, 0) << v.output;
  const auto rows = read_visibility_csv(dir / "v.csv");
  ASSERT_EQ(rows.size(), 2u * 49u);
  EXPECT_EQ(rows.front().frame, 1u);
  EXPECT_EQ(rows.front().source_frame, 102);
  EXPECT_EQ(rows.back().frame, 2u);
  EXPECT_EQ(rows.back().source_frame, 103);
  EXPECT_NE(test::run_pleat("visibility --help").output.find("not source frame numbers"), std::string::npos);

  const auto s =
      test::run_pleat("shade " + input + " -q -o " + (dir / "s.glb").string() +
                      " --render-every 2 --width 32 --height 24 --render " + (dir / "png").string());
  ASSERT_EQ(s.exit_code, 0) << s.output;
  EXPECT_EQ(test::names_in(dir / "png"), (std::vector<std::string>{"frame_0102.png", "frame_0104.png"}));
  // The glb plays frame i at source frame / fps and reads back with the same numbers.
  const MeshSequence glb = load_sequence(dir / "s.glb");
  EXPECT_EQ(source_frames(glb), (std::vector<std::int64_t>{101, 102, 103, 104}));
  EXPECT_NEAR(glb.frame_time(0), 101.0 / kDefaultSceneFps, 1e-5);
}

TEST(SourceFrames, TheCsvColumnRoundTripsAndIsRequired) {
  test::TempDir dir;
  {
    VisibilityCsvWriter csv(dir / "v.csv", {0, 0});
    csv.add_frame(0, -7, {0.25}, {0.5});
    csv.add_frame(1, 4000000000, {1.0}, {0.0});
    csv.commit();
  }
  EXPECT_EQ(test::slurp(dir / "v.csv"),
            "frame,vertex,front,back,source_frame\n0,0,0.25,0.5,-7\n0,1,0.25,0.5,-7\n1,0,1,0,4000000000\n"
            "1,1,1,0,4000000000\n");
  const auto rows = read_visibility_csv(dir / "v.csv");
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[1].source_frame, -7);
  EXPECT_EQ(rows[3].source_frame, 4000000000);
  test::write_bytes(dir / "old.csv", "frame,vertex,front,back\n0,0,0.5,0.5\n");
  EXPECT_THROW(read_visibility_csv(dir / "old.csv"), InputError);
  test::write_bytes(dir / "short.csv", "frame,vertex,front,back,source_frame\n0,0,0.5,0.5\n");
  try {
    read_visibility_csv(dir / "short.csv");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.place(), "line 2");
  }
}

}  // namespace
}  // namespace pleat
