// The input formats' tables (sim_io/input_formats.hpp) and the kinds of light (shading/lights.hpp): each
// format or kind one row, found by its name or extension in any case, and every message and help text listing
// the rows.
#include "sim_io/input_formats.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli/output_paths.hpp"
#include "shading/lights.hpp"
#include "sim_io/load_sequence.hpp"
#include "sim_io/pc2_format.hpp"
#include "support/input_error.hpp"
#include "test_support.hpp"

namespace pleat {
namespace {

std::string upper(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = char(std::toupper(static_cast<unsigned char>(c)));
  return out;
}

TEST(InputFormats, EveryRowIsFoundByItsExtensionInAnyCase) {
  for (const MeshFormat* format : mesh_formats()) {
    if (format->extension.empty()) continue;
    EXPECT_EQ(&mesh_format_of("cloth" + std::string(format->extension)), format) << format->extension;
    EXPECT_EQ(&mesh_format_of("cloth" + upper(format->extension)), format) << format->extension;
  }
  for (const CacheFormat* format : cache_formats())
    EXPECT_EQ(&cache_format_of("cloth" + upper(format->extension)), format) << format->extension;
}

TEST(InputFormats, TheUnknownFormatMessagesListEveryRow) {
  try {
    load_sequence("cloth.ply");
    FAIL() << "a .ply";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("cloth.ply"), std::string::npos) << what;
    for (const MeshFormat* format : mesh_formats())
      EXPECT_NE(what.find(std::string(format->expected)), std::string::npos) << what;
  }
  try {
    cache_format_of("cloth.abc");
    FAIL() << "an .abc cache";
  } catch (const InputError& e) {
    for (const CacheFormat* format : cache_formats())
      EXPECT_NE(std::string(e.what()).find(std::string(format->extension)), std::string::npos) << e.what();
  }
}

TEST(InputFormats, ACacheAnnouncesItsPointCountBeforeAnyFrameIsRead) {
  test::TempDir dir;
  write_pc2(dir / "c.pc2", {{glm::dvec3(0.0), glm::dvec3(1.0)}}, 1.0, 1.0);
  EXPECT_EQ(cache_format_of(dir / "c.pc2").open(dir / "c.pc2", 24.0)->announced_points().points, 2);
  try {
    open_cache_for(dir / "c.pc2", 3, "cloth.obj", 24.0);
    FAIL() << "3 vertices against 2 points";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("byte 16"), std::string::npos) << what;
    EXPECT_NE(what.find("cloth.obj has 3 vertices"), std::string::npos) << what;
  }
}

TEST(InputFormats, AGltfOfAnyCaseHasItsBuffersProtected) {
  // Its external buffer is read with it: an output there is refused (a .GLTF once was not looked into).
  test::TempDir dir;
  for (const std::string name : {"scene.gltf", "scene.GLTF"}) {
    std::ofstream(dir / name) << R"({"asset": {"version": "2.0"}, "buffers": [{"uri": "my%20data.bin"}],
                                    "images": [{"uri": "data:image/png;base64,AAAA"}]})";
    const auto files = cli::files_read_for(dir / name);
    EXPECT_NE(std::find(files.begin(), files.end(), dir / name), files.end()) << name;
    EXPECT_NE(std::find(files.begin(), files.end(), dir / "my data.bin"), files.end()) << name;
    EXPECT_EQ(files.size(), 2u) << name;
  }
}

TEST(LightKinds, EveryKindIsOneRowOfTheTypeList) {
  // Its spec syntax in --help, and lights summed kind by kind whatever order they were given in.
  const std::string syntax = light_spec_syntax();
  for (const std::string_view name : {"sky:L", "cloudy:L", "dir:", "point:", "area:", "env:"})
    EXPECT_NE(syntax.find(name), std::string::npos) << syntax;
  Lighting lighting;
  for (const char* spec : {"point:0,0,2,I=8", "sky:1", "dir:0,0,-1,E=2", "cloudy:0.5,up=0,1,0"})
    add_light_spec(lighting, spec);
  EXPECT_EQ(lighting.size(), 4u);
  EXPECT_EQ(lighting.all<PointLight>().size(), 1u);
  EXPECT_EQ(lighting.describe(),
            "sky L=1\ncloudy L=0.5 up=0,1,0\ndirectional towards 0,0,-1 E=2\npoint at 0,0,2 I=8\n");
  try {
    add_light_spec(lighting, "spot:0,0,1");
    FAIL() << "no spot light";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("(sky, cloudy, dir, point, area, env)"), std::string::npos)
        << e.what();
  }
  try {
    parse_lighting_json(R"({"lights": [{"type": "spot"}]})", "l.json");
    FAIL() << "no spot light";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("(sky, cloudy, directional, point, area, env)"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace pleat
