// OBJ reader/writer: the golden quad+pentagon, corner forms, negative indices, round trip, bad input.
#include <gtest/gtest.h>

#include <limits>

#include "sim_io/obj_format.hpp"
#include "sim_io_fixtures.hpp"
#include "support/input_error.hpp"
#include "test_support.hpp"

namespace pleat {
namespace {

using test::TempDir;

TEST(SimIoObj, GoldenQuadAndPentagonAreFanTriangulated) {
  const ObjMesh mesh = read_obj(test::source_dir() / "tests/golden/quad_pentagon.obj");
  ASSERT_EQ(mesh.positions.size(), 7u);
  EXPECT_EQ(mesh.num_polygons, 2u);
  const std::vector<Triangle> expected = {{0, 1, 2}, {0, 2, 3}, {1, 4, 5}, {1, 5, 6}, {1, 6, 2}};
  EXPECT_EQ(mesh.triangles, expected);
  EXPECT_EQ(mesh.positions[5], glm::dvec3(2.5, 0.5, 0.0));
}

TEST(SimIoObj, RoundTripIsExactInDoubles) {
  TempDir dir;
  MeshTopology topology{.num_vertices = 4, .triangles = {{0, 1, 2}, {0, 2, 3}}};
  const std::vector<glm::dvec3> positions = {{0.1, 0.2, 0.3},
                                             {1.0 / 3.0, -2.5e-300, 1e300},
                                             {std::nextafter(1.0, 2.0), -0.0, 123456789.123456789},
                                             {std::numeric_limits<double>::denorm_min(), 7.0, -7.25}};
  write_obj(dir / "a.obj", topology, positions);
  const ObjMesh mesh = read_obj(dir / "a.obj");
  EXPECT_EQ(mesh.positions, positions);
  EXPECT_EQ(mesh.triangles, topology.triangles);
}

TEST(SimIoObj, CornerFormsAndRelativeIndices) {
  TempDir dir;
  test::write_bytes(dir / "a.obj",
                    "v 0 0 0\r\nv 1 0 0 1\nv +1 1 0 0.5 0.5 0.5\nvt 0 0\nvn 0 0 1\n"
                    "f 1/1 2/1/1 3//1\nf -3 -1 -2   # a comment\nusemtl x\nl 1 2\n");
  const ObjMesh mesh = read_obj(dir / "a.obj");
  ASSERT_EQ(mesh.triangles.size(), 2u);
  EXPECT_EQ(mesh.triangles[0], (Triangle{0, 1, 2}));
  EXPECT_EQ(mesh.triangles[1], (Triangle{0, 2, 1}));
}

TEST(SimIoObj, UvsAndNormalsPerCornerBecomeTheSurface) {
  TempDir dir;
  // A quad and a triangle; vertex 1 has two UVs (a seam). The last face names its corners relatively.
  test::write_bytes(dir / "a.obj",
                    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\n"
                    "vt 0 0\nvt 0.5 0\nvt 0.5 1\nvt 0 1\nvt 0.75 0.25 0\nvn 0 0 2\nvn 0 0 1\n"
                    "f 1/1/1 2/2/1 3/3/2 4/4/2\nf -4/-1/-1 -1/-4/-1 -3/-3/-1\n");
  const ObjMesh mesh = read_obj(dir / "a.obj");
  ASSERT_EQ(mesh.triangles.size(), 3u);
  EXPECT_EQ(mesh.corner_texcoords, (std::vector<std::int64_t>{0, 1, 2, 0, 2, 3, 4, 1, 2}));
  EXPECT_EQ(mesh.corner_normals, (std::vector<std::int64_t>{0, 0, 1, 0, 1, 1, 1, 1, 1}));
  const SurfaceAttributes surface = surface_of(mesh);
  ASSERT_EQ(surface.texcoords.size(), 9u);
  EXPECT_EQ(surface.texcoords[6], glm::vec2(0.75f, 0.75f));  // glTF's v runs down: 1 - 0.25
  EXPECT_EQ(surface.normals[0], glm::vec3(0, 0, 2));         // as given
  // A corner without a UV: no UVs at all (but the normals stay).
  test::write_bytes(dir / "b.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2//1 3/1/1\n");
  const SurfaceAttributes partial = surface_of(read_obj(dir / "b.obj"));
  EXPECT_TRUE(partial.texcoords.empty());
  EXPECT_EQ(partial.normals.size(), 3u);
  // The golden file: normals at every corner, UVs at some.
  const SurfaceAttributes golden =
      surface_of(read_obj(test::source_dir() / "tests/golden/quad_pentagon.obj"));
  EXPECT_TRUE(golden.texcoords.empty());
  EXPECT_EQ(golden.normals, std::vector<glm::vec3>(15, glm::vec3(0, 0, 1)));
}

void expect_input_error(const std::filesystem::path& file, const std::string& content,
                        const std::string& place, const std::string& words) {
  test::write_bytes(file, content);
  try {
    read_obj(file);
    FAIL() << "no error for " << content;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), file.string());
    EXPECT_EQ(e.place(), place);
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

TEST(SimIoObj, BadInputNamesFileAndLine) {
  TempDir dir;
  const auto f = dir / "bad.obj";
  expect_input_error(f, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "line 4", "out of range");
  expect_input_error(f, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "line 4", "index 0");
  expect_input_error(f, "v 0 0 0\nf -2 -1 1\n", "line 2", "out of range");
  expect_input_error(f, "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n", "line 2", "non-finite");
  expect_input_error(f, "v 0 0 0\nv 1 inf 0\n", "line 2", "non-finite");
  expect_input_error(f, "v 0 0 x\n", "line 1", "not a number");
  expect_input_error(f, "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/2\n", "line 5",
                     "texture coordinate index 2 out of range");
  expect_input_error(f, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//-2 3//1\nvn 0 0 1\n", "line 4",
                     "relative normal index -2 out of range");
  expect_input_error(f, "vt 0 nan\n", "line 1", "non-finite");
  expect_input_error(f, "vn 0 1\n", "line 1", "fewer than 3");
  expect_input_error(f, "v 0 0\n", "line 1", "fewer than 3");
  expect_input_error(f, "v 0 0 0\nv 1 0 0\nf 1 2\n", "line 3", "corners");
  expect_input_error(f, "v 0 0 0\nv 1 0 0\nv 0 1 0\n", "", "empty mesh");
  expect_input_error(f, "", "", "empty mesh");
  EXPECT_THROW(read_obj(dir / "missing.obj"), InputError);
}

}  // namespace
}  // namespace pleat
