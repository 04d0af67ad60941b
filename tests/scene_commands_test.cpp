// Every subcommand that takes a scene (visibility, shade, compare; info takes none) runs with a static
// occluder, an animated occluder and a ground plane, and the images it makes show the scene: the occluder or
// the ground is drawn where the cloth alone leaves background, and the cloth is still there. An error of
// pleat's own making (a library entry handed a bad frame) exits 1, not 2.
#include <gtest/gtest.h>
#include <stb/stb_image.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "cli/global_options.hpp"
#include "shading/render.hpp"
#include "sim_io/obj_format.hpp"
#include "sim_io/pc2_format.hpp"
#include "sim_io/visibility_csv.hpp"
#include "support/input_error.hpp"
#include "test_support.hpp"

namespace pleat {
namespace {

namespace fs = std::filesystem;
using test::run_pleat;

struct Png {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;
  const unsigned char* at(int x, int y) const { return rgb.data() + 3 * (std::size_t(y) * width + x); }
};

Png read_png(const fs::path& path) {
  Png image;
  int channels = 0;
  unsigned char* data = stbi_load(path.string().c_str(), &image.width, &image.height, &channels, 3);
  if (!data) return image;
  image.rgb.assign(data, data + 3 * std::size_t(image.width) * image.height);
  stbi_image_free(data);
  return image;
}

// The cloth is lit by an orange sky: its pixels are orange; the scene's (slate and warm greys) and the
// background's are not.
bool orange(const unsigned char* p) { return p[0] > p[2] + 40; }

int largest_difference(const unsigned char* p, const unsigned char* q) {
  return std::max({std::abs(p[0] - q[0]), std::abs(p[1] - q[1]), std::abs(p[2] - q[2])});
}

struct Counts {
  std::size_t cloth = 0;  ///< orange pixels in the scene's image
  std::size_t scene =
      0;  ///< pixels of neither cloth that differ from the cloth-alone image by more than 6 levels
};

// Compares the image of the cloth in its scene with that of the cloth alone (same camera).
Counts count_pixels(const Png& in_scene, const Png& alone) {
  Counts counts;
  EXPECT_EQ(in_scene.width, alone.width);
  EXPECT_EQ(in_scene.height, alone.height);
  if (in_scene.width != alone.width || in_scene.height != alone.height) return counts;
  for (int y = 0; y < in_scene.height; ++y)
    for (int x = 0; x < in_scene.width; ++x) {
      const unsigned char *p = in_scene.at(x, y), *q = alone.at(x, y);
      counts.cloth += orange(p);
      counts.scene += !orange(p) && !orange(q) && largest_difference(p, q) > 6;
    }
  return counts;
}

class SceneCommands : public testing::Test {
 protected:
  void SetUp() override {
    const auto made =
        run_pleat("generate curtain -o " + (m_dir / "c.obj").string() + " --resolution 8 --frames 3");
    ASSERT_EQ(made.exit_code, 0) << made.output;
    m_input = (m_dir / "c.obj").string() + " --cache " + (m_dir / "c.pc2").string();
    // A floor plate under the hanging curtain (y from 0 down to -2.4): static, and rising frame by frame.
    const MeshTopology square{.num_vertices = 4, .triangles = {{0, 1, 2}, {0, 2, 3}}};
    const auto plate = [](double y) {
      return std::vector<glm::dvec3>{{-2, y, 2}, {2, y, 2}, {2, y, -2}, {-2, y, -2}};
    };
    write_obj(m_dir / "floor.obj", square, plate(-2.6));
    write_pc2(m_dir / "floor.pc2", {plate(-2.8), plate(-2.7), plate(-2.6)}, 0.0, 1.0);
    m_scenes = {{"static", "--occluder " + (m_dir / "floor.obj").string()},
                {"animated",
                 "--occluder " + (m_dir / "floor.obj").string() + ",cache=" + (m_dir / "floor.pc2").string()},
                {"ground", "--ground y=-2.6"}};
  }

  test::TempDir m_dir;
  std::string m_input;
  std::vector<std::pair<std::string, std::string>> m_scenes;  // name, options
};

TEST_F(SceneCommands, VisibilityRunsInEveryScene) {
  ASSERT_EQ(run_pleat("visibility -q " + m_input + " -o " + (m_dir / "alone.csv").string()).exit_code, 0);
  const std::vector<VisibilityRow> alone = read_visibility_csv(m_dir / "alone.csv");
  for (const auto& [name, scene] : m_scenes) {
    const fs::path csv = m_dir / (name + ".csv");
    const auto result = run_pleat("visibility -q " + m_input + " " + scene + " -o " + csv.string());
    ASSERT_EQ(result.exit_code, 0) << name << "\n" << result.output;
    const std::vector<VisibilityRow> rows = read_visibility_csv(csv);
    ASSERT_EQ(rows.size(), alone.size());
    double darker = 0.0;  // the floor hides sky from the cloth
    for (std::size_t i = 0; i < rows.size(); ++i)
      darker += alone[i].front + alone[i].back - rows[i].front - rows[i].back;
    EXPECT_GT(darker, 1.0) << name;
  }
}

TEST_F(SceneCommands, ShadeRendersTheScene) {
  const std::string common = " -q --light sky:1,rgb=1,0.45,0.1 --frames 2 --width 160 --height 120 -o ";
  ASSERT_EQ(run_pleat("shade " + m_input + common + (m_dir / "alone.glb").string() + " --render " +
                      (m_dir / "alone").string())
                .exit_code,
            0);
  const Png alone = read_png(m_dir / "alone/frame_0002.png");
  ASSERT_GT(alone.width, 0);
  for (const auto& [name, scene] : m_scenes) {
    const auto result =
        run_pleat("shade " + m_input + " " + scene + common + (m_dir / (name + ".glb")).string() +
                  " --render " + (m_dir / name).string());
    ASSERT_EQ(result.exit_code, 0) << name << "\n" << result.output;
    const Counts counts = count_pixels(read_png(m_dir / name / "frame_0002.png"), alone);
    EXPECT_GT(counts.cloth, 500u) << name;
    EXPECT_GT(counts.scene, 500u) << name << ": the scene is not drawn";
  }
}

TEST_F(SceneCommands, CompareRendersAndTracesTheScene) {
  const std::string common = " --light sky:1,rgb=1,0.45,0.1 --frame 2 --paths 8 --width 120 --height 90 -o ";
  ASSERT_EQ(run_pleat("compare -q " + m_input + common + (m_dir / "alone.png").string()).exit_code, 0);
  const Png alone = read_png(m_dir / "alone.png");
  ASSERT_GT(alone.width, 0);
  for (const auto& [name, scene] : m_scenes) {
    const fs::path png = m_dir / (name + ".png");
    const auto result = run_pleat("compare " + m_input + " " + scene + common + png.string());
    ASSERT_EQ(result.exit_code, 0) << name << "\n" << result.output;
    EXPECT_NE(result.output.find("frame 2, 64 vertices x 2 sides"), std::string::npos) << result.output;
    const Counts counts = count_pixels(read_png(png), alone);
    EXPECT_GT(counts.cloth, 1000u) << name;  // two of the three panels
    EXPECT_GT(counts.scene, 1000u) << name << ": the scene is not drawn";
  }
}

TEST(SceneCommandErrors, AnEntryHandedABadFrameByPleatIsAnInternalError) {
  const MeshTopology triangle{.num_vertices = 3, .triangles = {{0, 1, 2}}};
  Frame too_few;
  too_few.positions = {{0, 0, 0}, {1, 0, 0}};
  const std::vector<glm::vec3> colours(3, glm::vec3(0.5f));
  try {
    render_image(triangle, too_few, colours, colours, Camera{}, 16, 16);
    FAIL() << "a frame of 2 positions for 3 vertices was rendered";
  } catch (const InputError& e) {                      // bad input to a library caller...
    EXPECT_EQ(cli::exit_status_of(e), cli::kFailure);  // ...and a bug of pleat's on the command line
  }
  EXPECT_EQ(cli::exit_status_of(InputError("cloth.obj", "line 3", "bad")), cli::kUsage);
}

}  // namespace
}  // namespace pleat
