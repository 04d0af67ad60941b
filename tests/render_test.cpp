// PNG rendering (shading/render): uniform colour of a flat sheet facing the camera, back colours from behind,
// background on misses, camera parsing and auto-framing, atomic PNG output, turntables, labelled panels.
#include "shading/render.hpp"

#include <gtest/gtest.h>
#include <stb/stb_image.h>

#include <cmath>
#include <cstdlib>
#include <glm/glm.hpp>

#include "oracles/test_meshes.hpp"
#include "test_support.hpp"

namespace pleat {
namespace {

using Mesh = test::TestMesh;

/// n x n grid on [-1, 1]^2 in the plane z = 0, front (+n) towards +z.
Mesh square_sheet(int n) { return test::flat_sheet(n, n, 2.0 / (n - 1), {-1.0, -1.0}); }

glm::u8vec3 expected_byte(glm::vec3 srgb) {
  return {static_cast<std::uint8_t>(std::lround(srgb.x * 255.0f)),
          static_cast<std::uint8_t>(std::lround(srgb.y * 255.0f)),
          static_cast<std::uint8_t>(std::lround(srgb.z * 255.0f))};
}

void expect_close(glm::u8vec3 got, glm::u8vec3 want, int x, int y) {
  for (int k = 0; k < 3; ++k)
    EXPECT_LE(std::abs(int(got[k]) - int(want[k])), 1) << "pixel " << x << "," << y << " channel " << k;
}

TEST(Render, FlatSheetFacingTheCameraShowsItsColourInTheCentre) {
  const Mesh sheet = square_sheet(8);
  const glm::vec3 front(0.8f, 0.35f, 0.2f), back(0.1f, 0.3f, 0.9f);
  const std::vector<glm::vec3> fronts(sheet.topology.num_vertices, front),
      backs(sheet.topology.num_vertices, back);
  Camera camera;
  camera.eye = {0.0, 0.0, 4.0};
  camera.target = {0.0, 0.0, 0.0};
  const Image image = render_image(sheet.topology, sheet.frame, fronts, backs, camera, 64, 48);
  ASSERT_EQ(image.width, 64);
  ASSERT_EQ(image.height, 48);
  for (int y = 20; y < 28; ++y)
    for (int x = 28; x < 36; ++x) expect_close(image.pixel(x, y), expected_byte(front), x, y);
  // The sheet covers |x|,|y| <= 1 at distance 4 with a 35° field: the corners see the background, grey.
  const glm::u8vec3 corner = image.pixel(0, 0);
  EXPECT_EQ(corner.r, corner.g);
  EXPECT_EQ(corner.g, corner.b);
  EXPECT_GT(image.pixel(0, 0).r, image.pixel(0, 47).r);  // lighter at the top
}

TEST(Render, BackColoursAreSeenFromBehind) {
  const Mesh sheet = square_sheet(8);
  const glm::vec3 front(0.8f, 0.35f, 0.2f), back(0.1f, 0.3f, 0.9f);
  const std::vector<glm::vec3> fronts(sheet.topology.num_vertices, front),
      backs(sheet.topology.num_vertices, back);
  Camera camera;
  camera.eye = {0.3, 0.2, -4.0};
  camera.target = {0.0, 0.0, 0.0};
  const Image image = render_image(sheet.topology, sheet.frame, fronts, backs, camera, 64, 48);
  for (int y = 20; y < 28; ++y)
    for (int x = 28; x < 36; ++x) expect_close(image.pixel(x, y), expected_byte(back), x, y);
}

TEST(Render, InterpolatesVertexColoursInLinearLight) {
  // Left edge black, right edge white: the middle column is 50% linear, i.e. sRGB ≈ 0.735.
  const Mesh sheet = square_sheet(2);
  std::vector<glm::vec3> colours(4);
  colours[0] = colours[2] = glm::vec3(0.0f);
  colours[1] = colours[3] = glm::vec3(1.0f);
  Camera camera;
  camera.eye = {0.0, 0.0, 2.0};
  camera.fov_y_degrees = 30.0;
  const Image image = render_image(sheet.topology, sheet.frame, colours, colours, camera, 65, 33);
  const int mid = image.pixel(32, 16).r;
  EXPECT_NEAR(mid, std::lround(255 * (1.055 * std::pow(0.5, 1 / 2.4) - 0.055)), 3);
  EXPECT_LT(image.pixel(28, 16).r, mid);
  EXPECT_GT(image.pixel(36, 16).r, mid);
}

TEST(Render, ParseCamera) {
  const Camera c = parse_camera("1,2,3, 0,0,0, 0,1,0, 45");
  EXPECT_EQ(c.eye, glm::dvec3(1, 2, 3));
  EXPECT_EQ(c.target, glm::dvec3(0, 0, 0));
  EXPECT_EQ(c.up, glm::dvec3(0, 1, 0));
  EXPECT_EQ(c.fov_y_degrees, 45.0);
  EXPECT_EQ(parse_camera("1,2,3,0,0,0,0,1,0").fov_y_degrees, Camera{}.fov_y_degrees);
  EXPECT_THROW(parse_camera("1,2,3"), std::invalid_argument);
  EXPECT_THROW(parse_camera("1,2,x,0,0,0,0,1,0"), std::invalid_argument);
  EXPECT_THROW(parse_camera("0,0,0,0,0,0,0,1,0"), std::invalid_argument);  // eye == target
  EXPECT_THROW(parse_camera("0,5,0,0,0,0,0,1,0"), std::invalid_argument);  // up parallel to view
  EXPECT_THROW(parse_camera("0,0,5,0,0,0,0,1,0,190"), std::invalid_argument);
}

TEST(Render, AutoFrameKeepsEveryVertexInView) {
  Mesh sheet = square_sheet(6);
  for (glm::dvec3& p : sheet.frame.positions) p = p * 3.0 + glm::dvec3(10.0, -4.0, 2.0);
  AutoFrameParams params;
  params.aspect = 2.0;
  const Camera camera = auto_frame(sheet.frame, params);
  const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
  const glm::dvec3 right = glm::normalize(glm::cross(forward, camera.up));
  const glm::dvec3 up = glm::cross(right, forward);
  const double tan_y = std::tan(camera.fov_y_degrees * std::acos(-1.0) / 360.0),
               tan_x = tan_y * params.aspect;
  for (const glm::dvec3& p : sheet.frame.positions) {
    const glm::dvec3 d = p - camera.eye;
    const double z = glm::dot(d, forward);
    ASSERT_GT(z, 0.0);
    EXPECT_LE(std::abs(glm::dot(d, right) / z), tan_x);
    EXPECT_LE(std::abs(glm::dot(d, up) / z), tan_y);
  }
  // The sheet lies in z = const, so the automatic front is +z: the camera is on the +z side.
  EXPECT_GT(camera.eye.z, 2.0);
  EXPECT_THROW(auto_frame(Bounds{}), std::invalid_argument);
}

TEST(Render, WritesPngAtomicallyAndItReadsBack) {
  test::TempDir dir;
  const Mesh sheet = square_sheet(4);
  const std::vector<glm::vec3> colours(sheet.topology.num_vertices, glm::vec3(0.2f, 0.6f, 0.4f));
  Camera camera;
  camera.eye = {0.0, 0.0, 3.0};
  const auto path = dir / "sheet.png";
  render_png(path, sheet.topology, sheet.frame, colours, colours, camera, 40, 30);
  int w = 0, h = 0, channels = 0;
  unsigned char* data = stbi_load(path.string().c_str(), &w, &h, &channels, 3);
  ASSERT_NE(data, nullptr);
  EXPECT_EQ(w, 40);
  EXPECT_EQ(h, 30);
  const unsigned char* centre = data + (15 * 40 + 20) * 3;
  expect_close({centre[0], centre[1], centre[2]}, expected_byte(glm::vec3(0.2f, 0.6f, 0.4f)), 20, 15);
  stbi_image_free(data);
  int files = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir.path())) ++files;
  EXPECT_EQ(files, 1) << "no temporary file left behind";
  EXPECT_THROW(
      render_png(dir / "missing" / "x.png", sheet.topology, sheet.frame, colours, colours, camera, 8, 8),
      std::runtime_error);
}

TEST(Render, TurntableWritesOneImagePerStep) {
  test::TempDir dir;
  const Mesh sheet = square_sheet(4);
  const std::vector<glm::vec3> fronts(sheet.topology.num_vertices, glm::vec3(0.9f, 0.1f, 0.1f));
  const std::vector<glm::vec3> backs(sheet.topology.num_vertices, glm::vec3(0.1f, 0.1f, 0.9f));
  Camera camera;
  camera.eye = {0.0, 0.0, 4.0};
  const auto paths =
      render_turntable(dir.path(), "spin", sheet.topology, sheet.frame, fronts, backs, camera, 4, 32, 24);
  ASSERT_EQ(paths.size(), 4u);
  for (const auto& p : paths) EXPECT_TRUE(std::filesystem::exists(p)) << p;
  EXPECT_EQ(paths[2].filename(), "spin_002.png");
  // Half a turn later the camera is behind the sheet.
  const Camera behind = orbit(camera, 180.0);
  EXPECT_NEAR(behind.eye.z, -4.0, 1e-12);
  EXPECT_NEAR(behind.eye.x, 0.0, 1e-12);
}

TEST(Render, SideBySideComposesLabelledPanels) {
  const Image left(30, 20, {255, 0, 0}), right(40, 24, {0, 0, 255});
  const LabeledImage panels[] = {{&left, "pleat"}, {&right, "path traced"}};
  const Image out = side_by_side(panels);
  EXPECT_EQ(out.width, 30 + 4 + 40);
  EXPECT_GT(out.height, 24);
  const int bar = out.height - 24;
  EXPECT_EQ(out.pixel(5, bar + 5), glm::u8vec3(255, 0, 0));
  EXPECT_EQ(out.pixel(34 + 5, bar + 5), glm::u8vec3(0, 0, 255));
  // Some label pixels are drawn in the bar.
  int lit = 0;
  for (int y = 0; y < bar; ++y)
    for (int x = 0; x < out.width; ++x) lit += out.pixel(x, y).r > 200 ? 1 : 0;
  EXPECT_GT(lit, 20);
  EXPECT_EQ(text_width("ab", 1), 11);
}

}  // namespace
}  // namespace pleat

namespace pleat {
namespace {

/// `pleat shade --render-mode sky-visibility` draws A itself through viridis with a legend under the image,
/// and the ground in its own light colour (the old renders drew it as the background's grey).
TEST(Render, ShadeShowsSkyVisibilityWithALegendAndTheGroundApart) {
  test::TempDir dir;
  const std::string pile = std::string(PLEAT_SOURCE_DIR) + "/data/pile/pile.obj";
  const auto run =
      test::run_pleat("shade " + pile + " --cache " + std::string(PLEAT_SOURCE_DIR) +
                      "/data/pile/pile.pc2 --frames 0:1 --ground y=0 --render-mode sky-visibility "
                      "--render " +
                      (dir / "r").string() + " --width 200 --height 150 -q -o " + (dir / "o.glb").string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  std::filesystem::path png;
  for (const auto& entry : std::filesystem::directory_iterator(dir / "r")) png = entry.path();
  int w = 0, h = 0, channels = 0;
  unsigned char* data = stbi_load(png.string().c_str(), &w, &h, &channels, 3);
  ASSERT_NE(data, nullptr) << png;
  const auto at = [&](int x, int y) {
    return glm::ivec3(data[(y * w + x) * 3], data[(y * w + x) * 3 + 1], data[(y * w + x) * 3 + 2]);
  };
  EXPECT_EQ(w, 200);
  EXPECT_GT(h, 150 + 40);  // the legend under the image
  // The legend's bar runs from viridis(0) to viridis(1).
  const glm::ivec3 low = at(8, 150 + 10), high = at(200 - 9, 150 + 10);
  EXPECT_LE(glm::length(glm::vec3(low - glm::ivec3(68, 1, 84))), 4.0f);
  EXPECT_LE(glm::length(glm::vec3(high - glm::ivec3(253, 231, 37))), 4.0f);
  // The cloth in colour (viridis is nowhere grey), the ground in its light warm grey at the image's corner.
  int coloured = 0;
  for (int y = 0; y < 150; ++y)
    for (int x = 0; x < w; ++x) {
      const glm::ivec3 c = at(x, y);
      if (std::abs(c.g - c.r) > 40 || std::abs(c.b - c.g) > 40) ++coloured;
    }
  EXPECT_GT(coloured, 200);
  EXPECT_LE(glm::length(glm::vec3(at(2, 2) - glm::ivec3(199, 191, 179))), 6.0f);
  stbi_image_free(data);
}

}  // namespace
}  // namespace pleat
