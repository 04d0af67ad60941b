// `pleat info`: the same counts for one motion stored as OBJ+PC2, OBJ+MDD, an OBJ sequence and a glb, and
// one clean error (exit code 2, file and place named) per bad-input case.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "sim_io/gltf_reader.hpp"
#include "sim_io/gltf_writer.hpp"
#include "sim_io/mdd_format.hpp"
#include "sim_io/obj_format.hpp"
#include "sim_io/obj_sequence.hpp"
#include "sim_io/pc2_format.hpp"
#include "sim_io_fixtures.hpp"
#include "test_support.hpp"

namespace pleat {
namespace {

using test::run_pleat;
using test::TempDir;

std::string quoted(const std::filesystem::path& p) {
  std::string q(1, '\'');
  q += p.string();
  q += '\'';
  return q;
}

nlohmann::json info_json(const std::string& args) {
  const auto result = run_pleat("info " + args + " --json");
  EXPECT_EQ(result.exit_code, 0) << result.output;
  return nlohmann::json::parse(result.output);
}

TEST(InfoCommand, SameCountsForEveryFormatOfOneMotion) {
  TempDir dir;
  const MeshSequence sheet = test::folding_sheet(6, 4, 8);
  const auto positions = test::all_positions(sheet);
  std::vector<double> times;
  for (std::size_t i = 0; i < sheet.num_frames(); ++i) times.push_back(sheet.frame_time(i));
  write_obj(dir / "sheet.obj", sheet.topology(), positions[0]);
  write_pc2(dir / "sheet.pc2", positions, 0.0, 1.0);
  write_mdd(dir / "sheet.mdd", positions, times);
  std::filesystem::create_directories(dir / "seq");
  write_obj_sequence((dir / "seq/sheet_%03d.obj").string(), sheet, 1);
  std::vector<std::vector<glm::vec3>> colours(
      sheet.num_frames(), std::vector<glm::vec3>(sheet.topology().num_vertices, glm::vec3(0.8f)));
  std::vector<std::size_t> all(sheet.num_frames());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
  write_shaded_glb(dir / "sheet.glb", sheet, all, colours, colours, 24.0);

  const std::vector<nlohmann::json> reports = {
      info_json(quoted(dir / "sheet.obj") + " --cache " + quoted(dir / "sheet.pc2")),
      info_json(quoted(dir / "sheet.obj") + " --cache " + quoted(dir / "sheet.mdd")),
      info_json(quoted(dir / "seq/sheet_%03d.obj")),
      info_json(quoted(dir / "sheet.glb")),
  };
  for (const auto& r : reports) {
    SCOPED_TRACE(r.dump());
    EXPECT_EQ(r["input_vertices"], 35);
    EXPECT_EQ(r["welded_vertices"], 35);
    EXPECT_EQ(r["welded_duplicates"], 0);
    EXPECT_EQ(r["faces"], 48);
    EXPECT_EQ(r["frames"], 8);
    EXPECT_NEAR(r["frame_rate"].get<double>(), 24.0, 1e-4);
    EXPECT_NEAR(r["duration"].get<double>(), 7.0 / 24.0, 1e-6);
    EXPECT_EQ(r["boundary_loops"], 1);
    EXPECT_EQ(r["non_manifold_edges"], 0);
    EXPECT_EQ(r["degenerate_faces_max"], 0);
    EXPECT_EQ(r["bbox_min"], reports[0]["bbox_min"]);
    EXPECT_EQ(r["bbox_max"], reports[0]["bbox_max"]);
    for (const char* key : {"input_faces", "edges", "boundary_edges", "components", "removed_faces"})
      EXPECT_EQ(r[key], reports[0][key]) << key;
  }
}

TEST(InfoCommand, HumanReadableReportAndIntersectionCheck) {
  TempDir dir;
  const MeshSequence sheet = test::folding_sheet(3, 3, 3);
  write_obj(dir / "s.obj", sheet.topology(), sheet.frame(0).positions);
  write_pc2(dir / "s.pc2", test::all_positions(sheet), 0.0, 1.0);
  const auto result = run_pleat("info " + quoted(dir / "s.obj") + " --cache " + quoted(dir / "s.pc2") +
                                " --check-intersections");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  for (const char* words :
       {"16 welded, 16 input (0 welded duplicates)", "18 triangles", "3 at 24 fps", "boundary loops      1",
        "non-manifold edges  0", "self-intersections  0 of 3 frames intersect"})
    EXPECT_NE(result.output.find(words), std::string::npos) << words << "\n" << result.output;
  const auto json = info_json(quoted(dir / "s.obj") + " --check-intersections");
  EXPECT_EQ(json["self_intersections"]["frames_with_intersections"], 0);
}

TEST(InfoCommand, ReportsSelfIntersectingFrames) {
  // Two triangles piercing each other in frame 1 only.
  TempDir dir;
  test::write_piercing_pair(dir.path());
  const auto json =
      info_json(quoted(dir / "x.obj") + " --cache " + quoted(dir / "x.pc2") + " --check-intersections");
  EXPECT_EQ(json["self_intersections"]["frames_with_intersections"], 1);
  EXPECT_EQ(json["self_intersections"]["max_pairs"], 1);
  EXPECT_EQ(json["self_intersections"]["pairs_per_frame"], nlohmann::json({0, 1}));
}

TEST(InfoCommand, HelpHasAnExample) {
  const auto result = run_pleat("info --help");
  EXPECT_EQ(result.exit_code, 0);
  EXPECT_NE(result.output.find("pleat info cloth.obj --cache cloth.pc2"), std::string::npos) << result.output;
}

// One bad-input case: `pleat info ARGS` exits with 2 and one line naming the file and the place.
class BadInput : public ::testing::Test {
 protected:
  void SetUp() override {
    const MeshSequence sheet = test::folding_sheet(2, 1, 2);
    write_obj(m_dir / "s.obj", sheet.topology(), sheet.frame(0).positions);
    write_pc2(m_dir / "s.pc2", test::all_positions(sheet), 0.0, 1.0);
    write_mdd(m_dir / "s.mdd", test::all_positions(sheet), {0.0, 0.5});
    const std::vector<glm::vec3> white(sheet.topology().num_vertices, glm::vec3(1.0f));
    write_shaded_glb(m_dir / "s.glb", sheet, {0, 1}, {white, white}, {white, white}, 24.0);
  }
  std::filesystem::path path(const std::string& name) const { return m_dir / name; }
  std::string bytes(const std::string& name) const { return test::slurp(m_dir / name); }
  void write(const std::string& name, const std::string& content) const {
    test::write_bytes(m_dir / name, content);
  }
  void expect_error(const std::string& args, const std::filesystem::path& file, const std::string& place,
                    const std::string& words) const {
    const auto result = run_pleat("info " + args);
    EXPECT_EQ(result.exit_code, 2) << result.output;
    EXPECT_NE(
        result.output.find("pleat: error: " + file.string() + (place.empty() ? ": " : ":" + place + ": ")),
        std::string::npos)
        << result.output;
    EXPECT_NE(result.output.find(words), std::string::npos) << result.output;
    EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
  }

  TempDir m_dir;
};

TEST_F(BadInput, MissingFile) {
  expect_error(quoted(path("nope.obj")), path("nope.obj"), "", "no such file");
}

TEST_F(BadInput, UnreadableFile) {
  std::filesystem::create_directories(path("dir.pc2"));  // a directory where a cache should be
  expect_error(quoted(path("s.obj")) + " --cache " + quoted(path("dir.pc2")), path("dir.pc2"), "",
               "not a regular file");
}

TEST_F(BadInput, WrongMagicPc2) {
  std::string b = bytes("s.pc2");
  b.replace(0, 5, "POINT");
  b[5] = 'Z';
  write("bad.pc2", b);
  expect_error(quoted(path("s.obj")) + " --cache " + quoted(path("bad.pc2")), path("bad.pc2"), "byte 0",
               "wrong magic");
}

TEST_F(BadInput, WrongMagicGlb) {
  std::string b = bytes("s.glb");
  b[1] = 'X';
  write("bad.glb", b);
  expect_error(quoted(path("bad.glb")), path("bad.glb"), "byte 0", "wrong magic");
}

TEST_F(BadInput, TruncatedPc2) {
  const std::string b = bytes("s.pc2");
  write("short.pc2", b.substr(0, b.size() - 7));
  expect_error(quoted(path("s.obj")) + " --cache " + quoted(path("short.pc2")), path("short.pc2"),
               "byte " + std::to_string(b.size() - 7), "truncated");
}

TEST_F(BadInput, TruncatedMdd) {
  const std::string b = bytes("s.mdd");
  write("short.mdd", b.substr(0, 30));
  expect_error(quoted(path("s.obj")) + " --cache " + quoted(path("short.mdd")), path("short.mdd"), "byte 30",
               "truncated");
}

TEST_F(BadInput, TruncatedGlb) {
  const std::string b = bytes("s.glb");
  write("short.glb", b.substr(0, b.size() / 2));
  expect_error(quoted(path("short.glb")), path("short.glb"), "byte " + std::to_string(b.size() / 2),
               "truncated");
}

TEST_F(BadInput, VertexCountMismatchPc2) {
  write_pc2(path("four.pc2"), {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}}}, 0.0, 1.0);
  expect_error(quoted(path("s.obj")) + " --cache " + quoted(path("four.pc2")), path("four.pc2"), "byte 16",
               "mismatch");
}

TEST_F(BadInput, VertexCountMismatchMdd) {
  write_mdd(path("four.mdd"), {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}}}, {0.0});
  expect_error(quoted(path("s.obj")) + " --cache " + quoted(path("four.mdd")), path("four.mdd"), "byte 4",
               "mismatch");
}

TEST_F(BadInput, NanInCache) {
  std::string b = bytes("s.pc2");
  const std::size_t at = 32 + 6 * 12 + 2 * 12 + 8;  // frame 1, vertex 2, z
  b[at] = 0, b[at + 1] = 0, b[at + 2] = char(0xc0), b[at + 3] = char(0x7f);
  write("nan.pc2", b);
  expect_error(quoted(path("s.obj")) + " --cache " + quoted(path("nan.pc2")), path("nan.pc2"),
               "frame 1, vertex 2", "non-finite");
}

TEST_F(BadInput, InfInObj) {
  write("inf.obj", "v 0 0 0\nv 1 0 0\nv 0 -inf 0\nf 1 2 3\n");
  expect_error(quoted(path("inf.obj")), path("inf.obj"), "line 3", "non-finite");
}

TEST_F(BadInput, IndexOutOfRange) {
  write("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 3 9\n");
  expect_error(quoted(path("range.obj")), path("range.obj"), "line 5", "out of range");
}

TEST_F(BadInput, EmptyMesh) {
  write("empty.obj", "# nothing here\n");
  expect_error(quoted(path("empty.obj")), path("empty.obj"), "", "empty mesh");
}

TEST_F(BadInput, UnsupportedGltfFeature) {
  write(
      "lines.gltf",
      R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":24,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAA"}],)"
      R"("bufferViews":[{"buffer":0,"byteLength":24}],)"
      R"("accessors":[{"bufferView":0,"componentType":5126,"count":2,"type":"VEC3","min":[0,0,0],"max":[1,0,0]}],)"
      R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"mode":1}]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}]})");
  expect_error(quoted(path("lines.gltf")), path("lines.gltf"), "mesh 0 primitive 0",
               "unsupported glTF feature");
}

}  // namespace
}  // namespace pleat
