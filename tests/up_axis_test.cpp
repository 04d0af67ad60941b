// sim_io/up_axis.hpp: the turns that stand an input up in glTF's +Y (proper rotations taking the up axis to
// +y, exact on bounds) and how `pleat shade --up` chooses the up: as told, from the ground's side, from the
// way the cloth falls, with a warning when told otherwise than the ground or the fall say.
#include "sim_io/up_axis.hpp"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <stdexcept>
#include <vector>

namespace pleat {
namespace {

/// A 2 x 2 quad sheet over z = height - drop * frame, at x, y in [0, 1] (Z-up: it falls along -z).
MeshSequence falling_sheet(double height, double drop) {
  MeshTopology topology;
  topology.num_vertices = 4;
  topology.triangles = {{0, 1, 2}, {0, 2, 3}};
  std::vector<Frame> frames;
  for (int f = 0; f < 3; ++f) {
    Frame frame;
    frame.time = f / 24.0;
    const double z = height - drop * f;
    frame.positions = {{0, 0, z}, {1, 0, z}, {1, 1, z}, {0, 1, z}};
    frames.push_back(frame);
  }
  return MeshSequence("sheet", std::move(topology), std::move(frames));
}

TEST(UpAxis, TurnsTakeTheUpAxisToYAndAreRotations) {
  for (int axis = 0; axis < 3; ++axis)
    for (int sign : {1, -1}) {
      const AxisTurn turn = turn_to_y_up(axis, sign);
      glm::vec3 up(0.0f);
      up[axis] = float(sign);
      EXPECT_EQ(turn(up), glm::vec3(0, 1, 0)) << axis << " " << sign;
      // Proper: the turned x and y cross into the turned z (windings and sides are kept).
      EXPECT_EQ(glm::cross(turn({1, 0, 0}), turn({0, 1, 0})), turn({0, 0, 1})) << axis << " " << sign;
      glm::vec3 lo(-1.0f, 2.0f, -3.0f), hi(4.0f, 5.0f, 6.0f);
      const glm::vec3 a = turn(lo), b = turn(hi);
      turn.bounds(lo, hi);
      EXPECT_EQ(lo, glm::min(a, b));
      EXPECT_EQ(hi, glm::max(a, b));
    }
  // Blender's: Z-up (x, y, z) is glTF's (x, z, -y).
  EXPECT_EQ(turn_to_y_up(2, 1)(glm::vec3(1, 2, 3)), glm::vec3(1, 3, -2));
  EXPECT_TRUE(turn_to_y_up(1, 1).identity());
}

TEST(UpAxis, AutoTakesTheGroundElseY) {
  const MeshSequence falling = falling_sheet(2.0, 0.5), resting = falling_sheet(2.0, 0.0);
  UpChoice up = choose_up("auto", "z=0", resting);
  EXPECT_EQ(up.name, "+z");
  EXPECT_EQ(up.source, "--ground z=0");
  EXPECT_EQ(up.turn(glm::vec3(0, 0, 1)), glm::vec3(0, 1, 0));
  EXPECT_EQ(choose_up("auto", "-z=3", resting).name, "-z");  // a ground solid on its +z side
  up = choose_up("auto", "", falling);                       // a fall alone turns nothing: it warns
  EXPECT_EQ(up.name, "+y");
  EXPECT_EQ(up.warning,
            "up +y (the default), but the cloth falls along -z: if +z is up, give --up z or --ground");
  up = choose_up("auto", "", resting);
  EXPECT_EQ(up.name, "+y");
  EXPECT_TRUE(up.turn.identity());
  EXPECT_TRUE(up.warning.empty());
}

TEST(UpAxis, AnUpToldOtherwiseThanTheGroundOrTheFallIsWarnedOf) {
  const MeshSequence falling = falling_sheet(2.0, 0.5);
  EXPECT_EQ(choose_up("y", "z=0", falling).warning, "--up y, but the cloth stands on --ground z=0 (up +z)");
  EXPECT_EQ(choose_up("y", "", falling).warning,
            "--up y, but the cloth falls along -z: if +z is up, give --up z or --ground");
  EXPECT_TRUE(choose_up("z", "z=0", falling).warning.empty());
  // A vector along an axis turns the glb; another is the camera's up only.
  EXPECT_EQ(choose_up("0,0,2", "", falling).name, "+z");
  const UpChoice tilted = choose_up("0,1,1", "", falling);
  EXPECT_TRUE(tilted.turn.identity());
  EXPECT_NEAR(glm::length(tilted.up), 1.0, 1e-15);
  EXPECT_THROW(choose_up("upward", "", falling), std::invalid_argument);
}

}  // namespace
}  // namespace pleat
