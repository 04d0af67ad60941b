// OBJ reader/writer: the golden quad+pentagon, corner forms, negative indices, round trip, bad input.
#include <gtest/gtest.h>

#include <limits>

#include "sim_io/obj_format.hpp"
#include "sim_io_fixtures.hpp"
#include "static_core/input_error.hpp"
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
  MeshTopology topology{4, {{0, 1, 2}, {0, 2, 3}}};
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
  expect_input_error(f, "v 0 0\n", "line 1", "fewer than 3");
  expect_input_error(f, "v 0 0 0\nv 1 0 0\nf 1 2\n", "line 3", "corners");
  expect_input_error(f, "v 0 0 0\nv 1 0 0\nv 0 1 0\n", "", "empty mesh");
  expect_input_error(f, "", "", "empty mesh");
  EXPECT_THROW(read_obj(dir / "missing.obj"), InputError);
}

}  // namespace
}  // namespace pleat
