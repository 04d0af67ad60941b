// The glb `pleat shade` writes carries each side's cones as vertex attributes (_SKY_VISIBILITY, _BENT_CONE:
// sim_io/gltf_writer.hpp) equal to the cones it shaded with, and the Khronos glTF-Validator reports no error
// on it (npm gltf-validator, installed by scripts/setup.sh; tests/tools/validate_gltf.mjs).
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "shading/cone_cache.hpp"
#include "sim_io/load_sequence.hpp"
#include "sim_io/mesh_sequence.hpp"
#include "sim_io/pc2_format.hpp"
#include "sim_io/visibility_csv.hpp"
#include "sim_io_fixtures.hpp"
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

/// The glb at `path`, read by tinygltf; an empty model (no meshes) with a test failure when it does not read.
tinygltf::Model read_glb(const std::filesystem::path& path) {
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string err, warn;
  if (!loader.LoadBinaryFromFile(&model, &err, &warn, path.string())) {
    ADD_FAILURE() << path << ": " << err;
    return {};
  }
  return model;
}

/// The Khronos glTF-Validator reports no error on `path`.
void expect_valid(const std::filesystem::path& path) {
  const std::string command = "node " + std::string(PLEAT_SOURCE_DIR) + "/tests/tools/validate_gltf.mjs " +
                              PLEAT_GLTF_VALIDATOR_DIR + " " + path.string() + " 2>&1";
  const test::CommandResult result = test::run_command(command);
  EXPECT_EQ(result.exit_code, 0) << result.output << "(the validator is installed by scripts/setup.sh)";
  EXPECT_NE(result.output.find(": 0 errors"), std::string::npos) << result.output;
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

  const tinygltf::Model model = read_glb(dir / "s.glb");
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

  expect_valid(dir / "s.glb");
}

/// The input layout: per frame the artist's mesh (input order, its UVs and normals, seam copies after), both
/// sides' colours and visibility in one primitive, frames at their source times; it validates, and a glb
/// read back gives its UVs again.
TEST(ShadedGlb, TheInputLayoutIsTheArtistsMeshWithItsUvsAndNormals) {
  test::TempDir dir;
  // Two quads; the second one's UVs are elsewhere in the texture, so vertices 1 and 2 sit on a seam.
  test::write_bytes(dir / "q.obj",
                    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
                    "vt 0 0\nvt 0.25 0\nvt 0.25 0.5\nvt 0 0.5\nvt 0.5 0\nvt 0.75 0\nvt 0.75 0.5\nvt 0.5 0.5\n"
                    "vn 0 0 2\nf 1/1/1 2/2/1 3/3/1 4/4/1\nf 2/5/1 5/6/1 6/7/1 3/8/1\n");
  std::vector<std::vector<glm::dvec3>> frames;
  for (int k = 0; k < 3; ++k)  // the second quad folds up over the first
    frames.push_back(
        {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {1 - 0.4 * k, 0, 0.9 * k}, {1 - 0.4 * k, 1, 0.9 * k}});
  write_pc2(dir / "q.pc2", frames, 5.0, 1.0);
  const std::string input = (dir / "q.obj").string() + " --cache " + (dir / "q.pc2").string();
  ASSERT_EQ(test::run_pleat("visibility " + input + " -o " + (dir / "v.csv").string()).exit_code, 0);
  const auto s =
      test::run_pleat("shade " + input + " -q -o " + (dir / "s.glb").string() + " --glb-layout input");
  ASSERT_EQ(s.exit_code, 0) << s.output;

  const tinygltf::Model model = read_glb(dir / "s.glb");
  ASSERT_EQ(model.meshes.size(), 3u);
  const std::vector<std::size_t> input_of = {0, 1, 2, 3, 4, 5, 1, 2};  // vertices 1, 2 copied at the seam
  const auto rows = read_visibility_csv(dir / "v.csv");
  for (std::size_t j = 0; j < 3; ++j) {
    const tinygltf::Mesh& mesh = model.meshes[j];
    EXPECT_EQ(mesh.name, "frame_000" + std::to_string(5 + j));
    ASSERT_EQ(mesh.primitives.size(), 1u);
    const auto& attributes = mesh.primitives[0].attributes;
    std::vector<std::string> names;
    for (const auto& [name, accessor] : attributes) names.push_back(name);
    EXPECT_EQ(names, (std::vector<std::string>{"COLOR_0", "COLOR_1", "NORMAL", "POSITION", "TEXCOORD_0",
                                               "_BENT_CONE_BACK", "_BENT_CONE_FRONT", "_SKY_VISIBILITY_BACK",
                                               "_SKY_VISIBILITY_FRONT"}));
    const std::vector<float> positions = floats(model, attributes.at("POSITION"), 3);
    const std::vector<float> uv = floats(model, attributes.at("TEXCOORD_0"), 2);
    const std::vector<float> normals = floats(model, attributes.at("NORMAL"), 3);
    const std::vector<float> front = floats(model, attributes.at("_SKY_VISIBILITY_FRONT"), 1);
    const std::vector<float> back = floats(model, attributes.at("_SKY_VISIBILITY_BACK"), 1);
    ASSERT_EQ(positions.size(), 3 * input_of.size());
    for (std::size_t g = 0; g < input_of.size(); ++g) {
      for (int c = 0; c < 3; ++c) EXPECT_EQ(positions[3 * g + c], float(frames[j][input_of[g]][c]));
      EXPECT_EQ(glm::vec3(normals[3 * g], normals[3 * g + 1], normals[3 * g + 2]), glm::vec3(0, 0, 1));
      const VisibilityRow& row = rows[6 * j + input_of[g]];
      EXPECT_EQ(front[g], float(row.front));
      EXPECT_EQ(back[g], float(row.back));
    }
    // UVs as given, v flipped: vertex 1 has (0.25, 0) in the first quad and its copy (0.5, 0) in the second.
    EXPECT_EQ(glm::vec2(uv[2], uv[3]), glm::vec2(0.25f, 1.0f));
    EXPECT_EQ(glm::vec2(uv[12], uv[13]), glm::vec2(0.5f, 1.0f));
    EXPECT_TRUE(mesh.extras.Has("pleat_seam_copies"));
  }
  // Folded: the sides see different skies (the colours and attributes differ by side).
  EXPECT_TRUE(
      std::any_of(rows.begin(), rows.end(), [](const VisibilityRow& r) { return r.front < r.back - 0.05; }));
  EXPECT_TRUE(model.materials.at(0).doubleSided);
  expect_valid(dir / "s.glb");
  const auto view = test::run_pleat("view " + (dir / "s.glb").string() + " -o " + (dir / "view").string());
  EXPECT_EQ(view.exit_code, 2);
  EXPECT_NE(view.output.find("--glb-layout sides"), std::string::npos) << view.output;

  // Read back: the glb's own vertices (seam copies weld again), its UVs, the source frames.
  const MeshSequence back = load_sequence(dir / "s.glb");
  EXPECT_EQ(back.num_input_vertices(), 8u);
  EXPECT_EQ(back.welded_duplicates(), 2u);
  EXPECT_EQ(back.source_frame(2), 7);
  ASSERT_EQ(back.surface().texcoords.size(), 12u);
  EXPECT_EQ(back.surface().texcoords[6], glm::vec2(0.5f, 1.0f));  // the second quad's first corner: the copy
  const auto again = test::run_pleat("shade " + (dir / "s.glb").string() + " -q -o " +
                                     (dir / "t.glb").string() + " --glb-layout input");
  ASSERT_EQ(again.exit_code, 0) << again.output;
  const tinygltf::Model second = read_glb(dir / "t.glb");
  ASSERT_EQ(second.meshes.size(), model.meshes.size());
  EXPECT_EQ(floats(second, second.meshes[0].primitives[0].attributes.at("TEXCOORD_0"), 2),
            floats(model, model.meshes[0].primitives[0].attributes.at("TEXCOORD_0"), 2));
}

}  // namespace
}  // namespace pleat
