// `pleat view` in a real browser: headless Chromium (Debian's chromium, SwiftShader WebGL) loads the page
// from file://, draws the cloth, redraws when the frame and the sun change, and with sky-only light computes
// the same per-vertex colours as `pleat shade` (its glb's COLOR_0) within 1e-3 in sRGB. Bad input: one line,
// exit 2, no page. The screenshots are kept in the test's temporary directory while it runs; see README for
// one.
#include <gtest/gtest.h>
#include <stb/stb_image.h>
#include <tiny_gltf.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "test_support.hpp"

namespace pleat {
namespace {

/// Runs a shell command; returns its exit status and output.
std::pair<int, std::string> shell(const std::string& command) {
  FILE* pipe = ::popen((command + " 2>/dev/null").c_str(), "r");
  if (!pipe) return {-1, ""};
  std::string output;
  char buffer[65536];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) output.append(buffer, n);
  const int status = ::pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

const std::string kChromium =
    "timeout 120 chromium --headless --no-sandbox --disable-dev-shm-usage --enable-unsafe-swiftshader "
    "--use-angle=swiftshader --virtual-time-budget=10000 ";

struct Image {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;
};

Image screenshot(const std::filesystem::path& page, const std::string& query,
                 const std::filesystem::path& png) {
  const auto [status, output] = shell(kChromium + "--window-size=640,480 --screenshot=" + png.string() +
                                      " 'file://" + page.string() + "?" + query + "'");
  EXPECT_EQ(status, 0) << "chromium failed (scripts/setup.sh installs it): " << output;
  Image image;
  int channels = 0;
  unsigned char* data = stbi_load(png.c_str(), &image.width, &image.height, &channels, 3);
  if (!data) return image;
  image.rgb.assign(data, data + 3 * image.width * image.height);
  stbi_image_free(data);
  return image;
}

/// Fraction of pixels right of the control panel (x >= 320) that are not the page's background (#202428).
double cloth_fraction(const Image& image) {
  std::size_t cloth = 0, total = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 320; x < image.width; ++x) {
      const unsigned char* p = &image.rgb[3 * (y * image.width + x)];
      cloth += std::abs(p[0] - 0x20) + std::abs(p[1] - 0x24) + std::abs(p[2] - 0x28) > 12;
      ++total;
    }
  return total ? double(cloth) / double(total) : 0.0;
}

/// Fraction of pixels that differ by more than 8 levels in some channel.
double changed_fraction(const Image& a, const Image& b) {
  if (a.rgb.size() != b.rgb.size() || a.rgb.empty()) return 0.0;
  std::size_t changed = 0;
  for (std::size_t i = 0; i < a.rgb.size(); i += 3)
    changed += std::abs(a.rgb[i] - b.rgb[i]) > 8 || std::abs(a.rgb[i + 1] - b.rgb[i + 1]) > 8 ||
               std::abs(a.rgb[i + 2] - b.rgb[i + 2]) > 8;
  return double(changed) / (double(a.rgb.size()) / 3.0);
}

float linear_to_srgb(float c) {
  if (!(c > 0.0f)) return 0.0f;
  if (c >= 1.0f) return 1.0f;
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

TEST(Viewer, RelightsLiveInHeadlessChromiumAndMatchesPleatShade) {
  test::TempDir dir;
  const std::string obj = (dir / "c.obj").string(), pc2 = (dir / "c.pc2").string();
  ASSERT_EQ(test::run_pleat("generate sleeve -o " + obj + " --resolution 16 --frames 8").exit_code, 0);
  const auto shaded = test::run_pleat("shade " + obj + " --cache " + pc2 + " --frames 0:4 -o " +
                                      (dir / "s.glb").string() + " --light sky:1");
  ASSERT_EQ(shaded.exit_code, 0) << shaded.output;
  const auto viewed = test::run_pleat("view " + (dir / "s.glb").string() + " -o " + (dir / "view").string());
  ASSERT_EQ(viewed.exit_code, 0) << viewed.output;
  const std::filesystem::path page = dir / "view" / "index.html";
  ASSERT_TRUE(std::filesystem::exists(page));

  const Image first = screenshot(page, "frame=0", dir / "frame0.png");
  ASSERT_FALSE(first.rgb.empty());
  EXPECT_GT(cloth_fraction(first), 0.05) << "the cloth is not drawn";
  const Image later = screenshot(page, "frame=3", dir / "frame3.png");
  EXPECT_GT(changed_fraction(first, later), 0.01) << "the frame slider does not change the image";
  const Image sunny = screenshot(page, "frame=0&sun=4&az=120&el=30", dir / "sun.png");
  EXPECT_GT(changed_fraction(first, sunny), 0.01) << "moving the sun does not change the image";
  const Image baked = screenshot(page, "frame=0&baked=1", dir / "baked.png");
  EXPECT_LT(changed_fraction(first, baked), 0.01) << "sky-only live shading differs from the baked colours";

  // The viewer's colours for frame 2, sky only (its defaults: sky 1, albedo 0.6, exposure 1, as pleat
  // shade's).
  const auto [status, dom] = shell(kChromium + "--dump-dom 'file://" + page.string() + "?frame=2&dump=1'");
  ASSERT_EQ(status, 0);
  const std::size_t begin = dom.find("<pre id=\"dump\">"), end = dom.find("</pre>", begin);
  ASSERT_NE(begin, std::string::npos) << dom.substr(0, 2000);
  const nlohmann::json dump = nlohmann::json::parse(dom.substr(begin + 15, end - begin - 15));
  ASSERT_EQ(dump["frame"], 2);
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string err, warn;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, (dir / "s.glb").string())) << err;
  double worst = 0.0;
  std::size_t compared = 0;
  for (int side = 0; side < 2; ++side) {
    const auto& accessor =
        model.accessors.at(model.meshes.at(2).primitives.at(side).attributes.at("COLOR_0"));
    const auto& view = model.bufferViews.at(accessor.bufferView);
    const auto& colours = dump[side == 0 ? "front" : "back"];
    ASSERT_EQ(colours.size(), 3 * accessor.count);
    for (std::size_t i = 0; i < 3 * accessor.count; ++i) {
      float linear = 0;
      std::memcpy(&linear, model.buffers[0].data.data() + view.byteOffset + accessor.byteOffset + 4 * i, 4);
      worst = std::max(worst, std::abs(double(linear_to_srgb(linear)) - colours[i].get<double>()));
      ++compared;
    }
  }
  EXPECT_GT(compared, 1000u);
  EXPECT_LT(worst, 1e-3) << "the viewer's sky-only colours differ from pleat shade's";
  std::cout << "viewer vs pleat shade, sky only, frame 2: max |sRGB difference| " << worst << " over "
            << compared << " values\n";
}

TEST(Viewer, RefusesWhatIsNotAShadedGlb) {
  test::TempDir dir;
  const std::string obj = (dir / "c.obj").string();
  ASSERT_EQ(test::run_pleat("generate curtain -o " + obj + " --resolution 6 --frames 2").exit_code, 0);
  const auto not_glb = test::run_pleat("view " + obj + " -o " + (dir / "v1").string());
  EXPECT_EQ(not_glb.exit_code, 2);
  EXPECT_NE(not_glb.output.find("not a binary glTF"), std::string::npos) << not_glb.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "v1"));
  const auto missing =
      test::run_pleat("view " + (dir / "none.glb").string() + " -o " + (dir / "v2").string());
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_FALSE(std::filesystem::exists(dir / "v2"));
}

}  // namespace
}  // namespace pleat
