// The glb `pleat shade` writes carries each side's cones as vertex attributes (_SKY_VISIBILITY, _BENT_CONE:
// sim_io/gltf_writer.hpp) equal to the cones it shaded with, and the Khronos glTF-Validator reports no error
// on it (npm gltf-validator, installed by scripts/setup.sh; tests/tools/validate_gltf.mjs).
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <cmath>
#include <filesystem>

#include "shading/cone_cache.hpp"
#include "sim_io/load_sequence.hpp"
#include "sim_io/mesh_sequence.hpp"
#include "test_support.hpp"

namespace pleat {
namespace {

/// The floats of accessor `index` (tightly read through its buffer view's stride).
std::vector<float> floats(const tinygltf::Model& model, int index, int components) {
  const tinygltf::Accessor& a = model.accessors.at(index);
  const tinygltf::BufferView& view = model.bufferViews.at(a.bufferView);
  const int stride = view.byteStride ? int(view.byteStride) : 4 * components;
  std::vector<float> out;
  for (std::size_t i = 0; i < a.count; ++i)
    for (int c = 0; c < components; ++c) {
      float x = 0;
      std::memcpy(
          &x, model.buffers[view.buffer].data.data() + view.byteOffset + a.byteOffset + i * stride + 4 * c,
          4);
      out.push_back(x);
    }
  return out;
}

TEST(ShadedGlb, CarriesTheConesAsVertexAttributesAndValidates) {
  test::TempDir dir;
  const std::string obj = (dir / "c.obj").string(), pc2 = (dir / "c.pc2").string();
  ASSERT_EQ(test::run_pleat("generate sleeve -o " + obj + " --resolution 12 --frames 6").exit_code, 0);
  const std::string input = obj + " --cache " + pc2 + " --frames 1:4";
  const auto v = test::run_pleat("visibility " + input + " -o " + (dir / "a.csv").string() +
                                 " --engine static --cones " + (dir / "c.cones").string());
  ASSERT_EQ(v.exit_code, 0) << v.output;
  const auto s = test::run_pleat("shade " + input + " -o " + (dir / "s.glb").string() +
                                 " --light sky:1 --cones " + (dir / "c.cones").string());
  ASSERT_EQ(s.exit_code, 0) << s.output;

  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string err, warn;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, (dir / "s.glb").string())) << err;
  ASSERT_EQ(model.meshes.size(), 3u);
  ConeCacheReader cache(dir / "c.cones");
  const MeshSequence sequence = load_sequence(obj, pc2);
  std::size_t partly_visible = 0;
  for (std::size_t j = 0; j < 3; ++j) {
    FrameVisibility cones;
    cache.read_frame(j, sequence.frame(j + 1), cones);
    ASSERT_EQ(model.meshes[j].primitives.size(), 2u);
    for (int side = 0; side < 2; ++side) {
      const auto& attributes = model.meshes[j].primitives[side].attributes;
      ASSERT_TRUE(attributes.count("_SKY_VISIBILITY") && attributes.count("_BENT_CONE"));
      const std::vector<float> a = floats(model, attributes.at("_SKY_VISIBILITY"), 1);
      const std::vector<float> b = floats(model, attributes.at("_BENT_CONE"), 4);
      ASSERT_EQ(a.size(), cones.measures[side].size());
      for (std::size_t i = 0; i < a.size(); ++i) {
        const ConeMeasures& m = cones.measures[side][i];
        EXPECT_EQ(a[i], float(m.sky_visibility));
        for (int c = 0; c < 3; ++c) EXPECT_EQ(b[4 * i + c], float(m.bent_normal[c]));
        // w: cos of the half-angle of the circular cone with the cone's solid angle, 2 pi (1 - w).
        EXPECT_NEAR(2.0 * M_PI * (1.0 - b[4 * i + 3]), m.solid_angle, 1e-5);
        partly_visible += m.sky_visibility > 0.05 && m.sky_visibility < 0.95;
      }
    }
  }
  EXPECT_GT(partly_visible, 50u);  // a folded cloth: the attributes carry real cones

  const std::string command = "node " + std::string(PLEAT_SOURCE_DIR) + "/tests/tools/validate_gltf.mjs " +
                              PLEAT_GLTF_VALIDATOR_DIR + " " + (dir / "s.glb").string() + " 2>&1";
  FILE* pipe = ::popen(command.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string output;
  char buffer[4096];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) output.append(buffer, n);
  const int status = ::pclose(pipe);
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 0)
      << output << "(the validator is installed by scripts/setup.sh)";
  EXPECT_NE(output.find(": 0 errors"), std::string::npos) << output;
}

}  // namespace
}  // namespace pleat
