// Files read as they say: a byte-order mark keeps the first line, a concave polygon is tiled in its plane
// (also through an OBJ sequence), a directory is one regularly numbered sequence or refused, a frame index
// out of range is refused whatever its sign (naming the option given), and an animated occluder is paired
// with the cloth by source frame number or refused with both ranges.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "sim_io/load_sequence.hpp"
#include "sim_io/obj_format.hpp"
#include "sim_io/pc2_format.hpp"
#include "sim_io/scene.hpp"
#include "sim_io/visibility_csv.hpp"
#include "sim_io_fixtures.hpp"
#include "support/input_error.hpp"
#include "test_support.hpp"

namespace pleat {
namespace {

namespace fs = std::filesystem;
using test::run_pleat;

TEST(InputReading, AByteOrderMarkKeepsTheFirstLine) {
  test::TempDir dir;
  const std::string body = "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nf 1 2 3\nf 1 3 4\n";
  test::write_bytes(dir / "plain.obj", body);
  test::write_bytes(dir / "bom.obj", "\xEF\xBB\xBF" + body);
  const ObjMesh plain = read_obj(dir / "plain.obj"), bom = read_obj(dir / "bom.obj");
  EXPECT_EQ(bom.positions, plain.positions);
  EXPECT_EQ(bom.triangles, plain.triangles);
  // With an unused last vertex the dropped line used to go unnoticed: the same CSV either way.
  test::write_bytes(dir / "plain5.obj", body + "v 9 9 9\n");
  test::write_bytes(dir / "bom5.obj", "\xEF\xBB\xBF" + body + "v 9 9 9\n");
  ASSERT_EQ(run_pleat("visibility -q " + (dir / "plain5.obj").string() + " -o " + (dir / "a.csv").string())
                .exit_code,
            0);
  const auto result =
      run_pleat("visibility -q " + (dir / "bom5.obj").string() + " -o " + (dir / "b.csv").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(test::slurp(dir / "b.csv"), test::slurp(dir / "a.csv"));
}

// A flat U-shaped 8-gon in the plane y = `y`, as one OBJ face.
std::string u_obj(double y, double notch = 2.0) {
  std::string text;
  for (const auto& [x, z] : std::vector<std::pair<double, double>>{
           {0, 0}, {0, 3}, {3, 3}, {3, 0}, {2, 0}, {2, notch}, {1, notch}, {1, 0}})
    text += "v " + std::to_string(x) + " " + std::to_string(y) + " " + std::to_string(z) + "\n";
  return text + "f 1 2 3 4 5 6 7 8\n";
}

TEST(InputReading, AConcavePolygonIsTiledInItsPlane) {
  test::TempDir dir;
  test::write_bytes(dir / "u.obj", u_obj(0.0));
  const auto result = run_pleat("visibility " + (dir / "u.obj").string() + " -o " + (dir / "v.csv").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(result.output.find("self-intersects"), std::string::npos) << result.output;
  const std::vector<VisibilityRow> rows = read_visibility_csv(dir / "v.csv");
  ASSERT_EQ(rows.size(), 8u);
  for (const VisibilityRow& row : rows) {
    EXPECT_DOUBLE_EQ(row.front, 1.0) << "vertex " << row.vertex;  // a flat sheet alone sees all the sky
    EXPECT_DOUBLE_EQ(row.back, 1.0) << "vertex " << row.vertex;
  }
  const ObjMesh mesh = read_obj(dir / "u.obj");
  EXPECT_EQ(mesh.num_polygons, 1u);
  EXPECT_EQ(mesh.triangles.size(), 6u);
}

TEST(InputReading, AnObjSequenceSplitsItsPolygonsAsItsFirstFrame) {
  test::TempDir dir;
  fs::create_directories(dir / "seq");
  // The U rises and its notch deepens: every frame is the first's polygon, split as the first is.
  for (int f = 0; f < 3; ++f)
    test::write_bytes(dir / ("seq/u_000" + std::to_string(f) + ".obj"), u_obj(0.5 * f, 2.0 + 0.3 * f));
  const MeshSequence sequence = load_sequence(dir / "seq");
  ASSERT_EQ(sequence.num_frames(), 3u);
  EXPECT_EQ(sequence.input_triangles(), read_obj(dir / "seq/u_0000.obj").triangles);
  const auto result =
      run_pleat("visibility " + (dir / "seq/u_%04d.obj").string() + " -o " + (dir / "v.csv").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  for (const VisibilityRow& row : read_visibility_csv(dir / "v.csv")) {
    EXPECT_DOUBLE_EQ(row.front, 1.0) << "frame " << row.frame << " vertex " << row.vertex;
    EXPECT_DOUBLE_EQ(row.back, 1.0) << "frame " << row.frame << " vertex " << row.vertex;
  }
  // Another polygon in a later frame is refused, naming the file and the face.
  test::write_bytes(dir / "seq/u_0003.obj", u_obj(2.0) + "f 1 2 3\n");
  try {
    const MeshSequence bad = load_sequence(dir / "seq");
    ADD_FAILURE() << "a frame with another face was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), (dir / "seq/u_0003.obj").string());
    EXPECT_NE(std::string(e.what()).find("2 faces instead of 1"), std::string::npos) << e.what();
  }
}

void write_numbered(const fs::path& dir, const std::vector<std::string>& names) {
  fs::create_directories(dir);
  for (const std::string& name : names) test::write_bytes(dir / name, u_obj(0.0));
}

TEST(InputReading, ADirectoryIsOneRegularlyNumberedSequence) {
  test::TempDir dir;
  struct Case {
    std::vector<std::string> names;
    std::string file, message;  // the error's file (relative to its directory) and text
  };
  const std::vector<Case> refused = {
      {{"c_0001.obj", "c_0002.obj", "c_0004.obj"}, "c_0003.obj", "missing frame in the numbered sequence"},
      {{"a_0001.obj", "a_0002.obj", "b_0001.obj", "b_0002.obj"},
       "",
       "not one numbered sequence: a_0001.obj and b_0001.obj differ in more than their frame numbers"},
      {{"a.obj", "b.obj"}, "", "not one numbered sequence: a.obj has no frame number in its name"},
      {{"f_1.obj", "f_01.obj"}, "", "both number frame 1"},
      {{"s_10.obj", "s_12.obj", "s_20.obj"}, "s_14.obj", "(found 10 to 12 every 2, then 20)"},
  };
  int k = 0;
  for (const Case& c : refused) {
    const fs::path sub = dir / ("refused" + std::to_string(k++));
    write_numbered(sub, c.names);
    try {
      load_sequence(sub);
      ADD_FAILURE() << "accepted " << c.names.front() << "...";
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), c.file.empty() ? sub.string() : (sub / c.file).string()) << e.what();
      EXPECT_NE(std::string(e.what()).find(c.message), std::string::npos) << e.what();
    }
    const auto cli = run_pleat("visibility " + sub.string() + " -o " + (dir / "v.csv").string());
    EXPECT_EQ(cli.exit_code, 2) << cli.output;
    EXPECT_FALSE(fs::exists(dir / "v.csv"));
  }
  // Every frame, every other frame, and one file.
  write_numbered(dir / "all", {"f_0009.obj", "f_0010.obj", "f_0011.obj"});
  EXPECT_EQ(load_sequence(dir / "all").num_frames(), 3u);
  write_numbered(dir / "every2", {"take2_f10.obj", "take2_f12.obj", "take2_f14.obj"});
  const MeshSequence every2 = load_sequence(dir / "every2");
  EXPECT_EQ(every2.source_frame(2), 14);
  EXPECT_DOUBLE_EQ(every2.frame_rate(), 12.0);
  write_numbered(dir / "one", {"rest.obj"});
  EXPECT_EQ(load_sequence(dir / "one").num_frames(), 1u);
}

// dir/c.obj + dir/c.pc2, a generated curtain of `frames` frames.
std::string curtain(const fs::path& dir, int frames) {
  const auto made = run_pleat("generate curtain -o " + (dir / "c.obj").string() +
                              " --resolution 6 --frames " + std::to_string(frames));
  EXPECT_EQ(made.exit_code, 0) << made.output;
  return (dir / "c.obj").string() + " --cache " + (dir / "c.pc2").string();
}

TEST(InputReading, AFrameIndexOutOfRangeIsRefusedWhateverItsSign) {
  test::TempDir dir;
  const std::string input = curtain(dir.path(), 4);
  for (const std::string frames : {"-5", "-500", "4", "100"}) {
    const auto result =
        run_pleat("visibility " + input + " --frames " + frames + " -o " + (dir / "v.csv").string());
    EXPECT_EQ(result.exit_code, 2) << frames << "\n" << result.output;
    EXPECT_NE(result.output.find("--frames: frame " + frames + " is out of range: the input has 4 frames"),
              std::string::npos)
        << result.output;
    EXPECT_FALSE(fs::exists(dir / "v.csv"));
  }
  // In range, from either end; a slice is clamped as Python's.
  for (const auto& [frames, first] :
       std::vector<std::pair<std::string, std::size_t>>{{"-4", 0}, {"-1", 3}, {"3", 3}, {"-500:2", 0}}) {
    const auto result =
        run_pleat("visibility -q " + input + " --frames " + frames + " -o " + (dir / "v.csv").string());
    ASSERT_EQ(result.exit_code, 0) << frames << "\n" << result.output;
    EXPECT_EQ(read_visibility_csv(dir / "v.csv").front().frame, first) << frames;
  }
  // compare's option is --frame: its errors say so.
  const auto late =
      run_pleat("compare " + input + " --frame 4 --light sky:1 --paths 4 -o " + (dir / "late.png").string());
  EXPECT_EQ(late.exit_code, 2);
  EXPECT_NE(late.output.find("--frame: frame 4 is out of range"), std::string::npos) << late.output;
  EXPECT_EQ(late.output.find("--frames"), std::string::npos) << late.output;
}

// A square plate (two triangles) over the curtain's box at height y = `heights[i]` in frame i, as
// dir/NAME.obj + dir/NAME.pc2 starting at scene frame `start`.
std::string plate(const fs::path& dir, const std::string& name, const std::vector<double>& heights,
                  double start) {
  const MeshTopology square{.num_vertices = 4, .triangles = {{0, 1, 2}, {0, 2, 3}}};
  std::vector<std::vector<glm::dvec3>> frames;
  for (double y : heights) frames.push_back({{-2, y, -2}, {2, y, -2}, {2, y, 2}, {-2, y, 2}});
  write_obj(dir / (name + ".obj"), square, frames.front());
  write_pc2(dir / (name + ".pc2"), frames, start, 1.0);
  return (dir / (name + ".obj")).string() + ",cache=" + (dir / (name + ".pc2")).string();
}

TEST(InputReading, AnAnimatedOccluderIsPairedBySourceFrame) {
  test::TempDir dir;
  curtain(dir.path(), 4);
  const MeshSequence cloth = load_sequence(dir / "c.obj", dir / "c.pc2");
  write_pc2(dir / "late.pc2", test::all_positions(cloth), 21.0, 1.0);  // the cloth at scene frames 21-24
  const std::string input = (dir / "c.obj").string() + " --cache " + (dir / "late.pc2").string();
  // A plate whose height is a function of the scene frame n, cached over frames 1-40.
  std::vector<double> long_heights, own_heights;
  for (int n = 1; n <= 40; ++n) long_heights.push_back(3.0 + 0.25 * (n % 7));
  for (int n = 21; n <= 24; ++n) own_heights.push_back(3.0 + 0.25 * (n % 7));
  const std::string long_plate = plate(dir.path(), "long", long_heights, 1.0);
  const std::string own_plate = plate(dir.path(), "own", own_heights, 21.0);  // the cloth's frames exactly
  const auto paired = run_pleat("visibility -q " + input + " --occluder " + long_plate + " -o " +
                                (dir / "long.csv").string());
  ASSERT_EQ(paired.exit_code, 0) << paired.output;
  ASSERT_EQ(
      run_pleat("visibility -q " + input + " --occluder " + own_plate + " -o " + (dir / "own.csv").string())
          .exit_code,
      0);
  EXPECT_EQ(test::slurp(dir / "long.csv"), test::slurp(dir / "own.csv"));
  // The library's scene gives frame i the occluder's frame of the same number.
  const MeshSequence late = load_sequence(dir / "c.obj", dir / "late.pc2");
  const Scene scene(late, {parse_occluder_spec(long_plate)}, {});
  for (std::size_t i = 0; i < late.num_frames(); ++i)
    EXPECT_EQ(scene.frame(i).positions.back().y, own_heights[i]) << "frame " << i;
  // An occluder that misses some of the cloth's frames: refused, with both ranges.
  const std::string early_plate = plate(dir.path(), "early", {3.0, 3.1, 3.2, 3.3}, 50.0);
  const auto missing =
      run_pleat("visibility " + input + " --occluder " + early_plate + " -o " + (dir / "v.csv").string());
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_NE(missing.output.find("the animated occluder has no source frame 21 (it holds frames 50 to 53 in 4 "
                                "frames, the cloth frames 21 to 24 in 4)"),
            std::string::npos)
      << missing.output;
  EXPECT_FALSE(fs::exists(dir / "v.csv"));
}

}  // namespace
}  // namespace pleat
