// glTF: seam welding, morph-target animations (LINEAR, STEP, CUBICSPLINE), node transforms, the flipbook glb
// written by write_shaded_glb read back, unsupported features, and corruptions of a small glb.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>
#include <tiny_gltf.h>

#include <cstdlib>
#include <cstring>
#include <nlohmann/json.hpp>

#include "sim_io/gltf_reader.hpp"
#include "sim_io/gltf_writer.hpp"
#include "sim_io/load_sequence.hpp"
#include "sim_io/mesh_report.hpp"
#include "sim_io_fixtures.hpp"
#include "support/input_error.hpp"
#include "support/srgb.hpp"
#include "test_support.hpp"

namespace pleat {
namespace {

using nlohmann::json;
using test::TempDir;

const bool kRapidcheckParams = [] {
  return ::setenv("RC_PARAMS", "seed=20240612 max_success=300", 0) == 0;
}();

// Builds a .gltf + .bin by hand: one bufferView per accessor.
class GltfBuilder {
 public:
  GltfBuilder() {
    m_doc = {{"asset", {{"version", "2.0"}}}, {"accessors", json::array()}, {"bufferViews", json::array()}};
  }
  int floats(const std::vector<float>& values, const std::string& type, bool bounds = false) {
    const int components = type == "VEC3" ? 3 : 1;
    json accessor = {
        {"componentType", 5126}, {"count", values.size() / std::size_t(components)}, {"type", type}};
    if (bounds) {
      std::vector<float> lo(values.begin(), values.begin() + components), hi = lo;
      for (std::size_t i = 0; i < values.size(); ++i) {
        lo[i % std::size_t(components)] = std::min(lo[i % std::size_t(components)], values[i]);
        hi[i % std::size_t(components)] = std::max(hi[i % std::size_t(components)], values[i]);
      }
      accessor["min"] = lo;
      accessor["max"] = hi;
    }
    return add(values.data(), values.size() * 4, accessor);
  }
  int indices(const std::vector<std::uint32_t>& values) {
    return add(values.data(), values.size() * 4,
               {{"componentType", 5125}, {"count", values.size()}, {"type", "SCALAR"}});
  }
  json& doc() { return m_doc; }
  std::filesystem::path write(const TempDir& dir, const std::string& name) {
    if (!m_bin.empty()) {
      m_doc["buffers"] = {{{"byteLength", m_bin.size()}, {"uri", name + ".bin"}}};
      test::write_bytes(dir / (name + ".bin"), m_bin);
    }
    test::write_bytes(dir / (name + ".gltf"), m_doc.dump(1));
    return dir / (name + ".gltf");
  }

 private:
  int add(const void* data, std::size_t bytes, json accessor) {
    m_doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", m_bin.size()}, {"byteLength", bytes}});
    m_bin.append(static_cast<const char*>(data), bytes);
    accessor["bufferView"] = m_doc["bufferViews"].size() - 1;
    m_doc["accessors"].push_back(accessor);
    return int(m_doc["accessors"].size() - 1);
  }
  json m_doc;
  std::string m_bin;
};

// A unit quad (two triangles) over vertices 0..3.
const std::vector<float> kQuad = {0, 0, 0, 1, 0, 0, 1, 0, 1, 0, 0, 1};
const std::vector<std::uint32_t> kQuadIndices = {0, 1, 2, 0, 2, 3};

TEST(SimIoGltf, SeamSplitVerticesAreWelded) {
  // A 2x1 strip of quads exported as two primitives that both hold the middle column (a UV seam).
  TempDir dir;
  GltfBuilder b;
  const int left = b.floats({0, 0, 0, 1, 0, 0, 1, 0, 1, 0, 0, 1}, "VEC3", true);
  const int right = b.floats({1, 0, 0, 2, 0, 0, 2, 0, 1, 1, 0, 1}, "VEC3", true);
  const int idx = b.indices(kQuadIndices);
  b.doc()["meshes"] = {{{"primitives",
                         {{{"attributes", {{"POSITION", left}}}, {"indices", idx}},
                          {{"attributes", {{"POSITION", right}}}, {"indices", idx}}}}}};
  b.doc()["nodes"] = {{{"mesh", 0}}};
  b.doc()["scenes"] = {{{"nodes", {0}}}};
  const MeshSequence s = load_gltf(b.write(dir, "seam"));
  EXPECT_EQ(s.num_input_vertices(), 8u);
  EXPECT_EQ(s.topology().num_vertices, 6u);
  EXPECT_EQ(s.welded_duplicates(), 2u);
  const auto& map = s.welded_of_input();
  EXPECT_EQ(map[1], map[4]);  // (1,0,0)
  EXPECT_EQ(map[2], map[7]);  // (1,0,1)
  EXPECT_EQ(s.topology().triangles.size(), 4u);
  const TopologyCounts counts = count_topology(s.topology());
  EXPECT_EQ(counts.boundary_loops, 1u);
  EXPECT_EQ(counts.components, 1u);
  EXPECT_EQ(counts.non_manifold_edges, 0u);
  // Input order is kept for the input positions.
  EXPECT_EQ(s.input_positions(0)[4], glm::dvec3(1, 0, 0));
}

// A quad with one morph target lifting vertex 2 by 1 in y, driven by a weights channel.
std::filesystem::path morph_quad(const TempDir& dir, const std::string& name,
                                 const std::string& interpolation, const std::vector<float>& times,
                                 const std::vector<float>& weights) {
  GltfBuilder b;
  const int base = b.floats(kQuad, "VEC3", true);
  const int target = b.floats({0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0}, "VEC3", true);
  const int idx = b.indices(kQuadIndices);
  const int input = b.floats(times, "SCALAR", true);
  const int output = b.floats(weights, "SCALAR");
  b.doc()["meshes"] = {
      {{"primitives",
        {{{"attributes", {{"POSITION", base}}}, {"indices", idx}, {"targets", {{{"POSITION", target}}}}}}},
       {"weights", {0.0}}}};
  b.doc()["nodes"] = {{{"mesh", 0}, {"translation", {10.0, 0.0, 0.0}}}};
  b.doc()["scenes"] = {{{"nodes", {0}}}};
  b.doc()["animations"] = {
      {{"samplers", {{{"input", input}, {"output", output}, {"interpolation", interpolation}}}},
       {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "weights"}}}}}}}};
  return b.write(dir, name);
}

TEST(SimIoGltf, MorphTargetsLinearSampledAtKeyframes) {
  TempDir dir;
  const MeshSequence s =
      load_gltf(morph_quad(dir, "linear", "LINEAR", {0.0f, 0.5f, 1.0f}, {0.0f, 0.5f, 1.0f}));
  ASSERT_EQ(s.num_frames(), 3u);
  EXPECT_DOUBLE_EQ(s.frame_rate(), 2.0);
  EXPECT_EQ(s.frame(0).positions[2], glm::dvec3(11, 0, 1));  // node translation applied
  EXPECT_EQ(s.frame(1).positions[2], glm::dvec3(11, 0.5, 1));
  EXPECT_EQ(s.frame(2).positions[2], glm::dvec3(11, 1, 1));
  EXPECT_EQ(s.frame(2).positions[0], glm::dvec3(10, 0, 0));
}

TEST(SimIoGltf, MorphTargetsStepAndCubicSpline) {
  TempDir dir;
  const MeshSequence step = load_gltf(morph_quad(dir, "step", "STEP", {0.0f, 1.0f}, {0.25f, 0.75f}));
  EXPECT_EQ(step.frame(1).positions[2].y, 0.75);
  // CUBICSPLINE stores (in-tangent, value, out-tangent) per key: frames take the values.
  const MeshSequence cubic =
      load_gltf(morph_quad(dir, "cubic", "CUBICSPLINE", {0.0f, 1.0f}, {9.0f, 0.25f, 9.0f, 9.0f, 1.0f, 9.0f}));
  EXPECT_EQ(cubic.frame(0).positions[2].y, 0.25);
  EXPECT_EQ(cubic.frame(1).positions[2].y, 1.0);
}

TEST(SimIoGltf, CoincidentInOneFrameOnlyIsNotWelded) {
  // Vertex 2 meets vertex 3's position nowhere, but a target moving vertex 2 onto vertex 1 in the last
  // frame must not weld them: welding needs coincidence in every frame.
  TempDir dir;
  GltfBuilder b;
  const int base = b.floats(kQuad, "VEC3", true);
  const int target = b.floats({0, 0, 0, 0, 0, 0, 0, 0, -1, 0, 0, 0}, "VEC3", true);
  const int idx = b.indices(kQuadIndices);
  const int input = b.floats({0.0f, 1.0f}, "SCALAR", true);
  const int output = b.floats({0.0f, 1.0f}, "SCALAR");
  b.doc()["meshes"] = {
      {{"primitives",
        {{{"attributes", {{"POSITION", base}}}, {"indices", idx}, {"targets", {{{"POSITION", target}}}}}}}}};
  b.doc()["nodes"] = {{{"mesh", 0}}};
  b.doc()["scenes"] = {{{"nodes", {0}}}};
  b.doc()["animations"] = {
      {{"samplers", {{{"input", input}, {"output", output}}}},
       {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "weights"}}}}}}}};
  const MeshSequence s = load_gltf(b.write(dir, "moving"));
  EXPECT_EQ(s.frame(1).positions[2], s.frame(1).positions[1]);
  EXPECT_EQ(s.welded_duplicates(), 0u);
  EXPECT_EQ(count_degenerate_faces(s.topology(), s.frame(1)), 1u);  // triangle (0,1,2) collapses to a segment
  EXPECT_EQ(count_degenerate_faces(s.topology(), s.frame(0)), 0u);
}

std::vector<glm::vec3> grey_ramp(std::size_t n, float offset) {
  std::vector<glm::vec3> c(n);
  for (std::size_t i = 0; i < n; ++i)
    c[i] = glm::vec3(std::fmod(offset + 0.01f * float(i), 1.0f), 0.5f, 0.25f);
  return c;
}

TEST(SimIoGltf, ShadedFlipbookRoundTrip) {
  TempDir dir;
  const MeshSequence sheet = test::folding_sheet(4, 3, 5);
  const std::size_t V = sheet.topology().num_vertices;
  std::vector<std::vector<glm::vec3>> front, back;
  for (int f = 0; f < 5; ++f) {
    front.push_back(grey_ramp(V, 0.1f * float(f)));
    back.push_back(grey_ramp(V, 0.5f + 0.1f * float(f)));
  }
  write_shaded_glb(dir / "s.glb", sheet, {0, 1, 2, 3, 4}, front, back, 24.0);

  const MeshSequence loaded = load_sequence(dir / "s.glb");
  EXPECT_EQ(loaded.num_input_vertices(), V);
  EXPECT_EQ(loaded.welded_duplicates(), 0u);
  EXPECT_EQ(loaded.removed_faces(), 0u);
  EXPECT_EQ(loaded.topology().triangles, sheet.topology().triangles);
  EXPECT_EQ(test::all_positions(loaded), test::all_positions(sheet));
  for (std::size_t i = 0; i < 5; ++i) EXPECT_NEAR(loaded.frame_time(i), double(i) / 24.0, 1e-6);

  // The layout a viewer sees: one node per frame under a root, STEP scale channels, both sides coloured.
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string err, warn;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, (dir / "s.glb").string())) << err;
  ASSERT_EQ(model.meshes.size(), 5u);
  ASSERT_EQ(model.nodes.size(), 6u);
  EXPECT_EQ(model.nodes[1].scale, (std::vector<double>{1, 1, 1}));
  EXPECT_EQ(model.nodes[2].scale, (std::vector<double>{0, 0, 0}));
  ASSERT_EQ(model.animations.size(), 1u);
  EXPECT_EQ(model.animations[0].channels.size(), 5u);
  for (const auto& s : model.animations[0].samplers) EXPECT_EQ(s.interpolation, "STEP");
  EXPECT_FALSE(model.materials[0].doubleSided);
  EXPECT_TRUE(model.materials[0].extensions.count("KHR_materials_unlit"));
  const tinygltf::Mesh& mesh = model.meshes[2];
  ASSERT_EQ(mesh.primitives.size(), 2u);
  EXPECT_EQ(mesh.primitives[0].attributes.at("POSITION"), mesh.primitives[1].attributes.at("POSITION"));
  const auto& colour = model.accessors[std::size_t(mesh.primitives[1].attributes.at("COLOR_0"))];
  const auto& view = model.bufferViews[std::size_t(colour.bufferView)];
  float rgb[3];
  std::memcpy(rgb, model.buffers[0].data.data() + view.byteOffset + colour.byteOffset + 12 * 7, 12);
  EXPECT_FLOAT_EQ(rgb[0], srgb_to_linear(back[2][7].r));
  EXPECT_FLOAT_EQ(rgb[1], srgb_to_linear(0.5f));
  // The back primitive winds the other way.
  const auto& back_indices = model.accessors[std::size_t(mesh.primitives[1].indices)];
  const auto& bv = model.bufferViews[std::size_t(back_indices.bufferView)];
  std::uint32_t t[3];
  std::memcpy(t, model.buffers[0].data.data() + bv.byteOffset + back_indices.byteOffset, 12);
  const Triangle& first = sheet.topology().triangles[0];
  EXPECT_EQ(t[0], first[0]);
  EXPECT_EQ(t[1], first[2]);
  EXPECT_EQ(t[2], first[1]);
}

TEST(SimIoGltf, SrgbToLinear) {
  EXPECT_EQ(srgb_to_linear(0.0f), 0.0f);
  EXPECT_EQ(srgb_to_linear(1.0f), 1.0f);
  EXPECT_NEAR(srgb_to_linear(0.5f), 0.21404f, 1e-5f);
  EXPECT_EQ(srgb_to_linear(-1.0f), 0.0f);
  EXPECT_EQ(srgb_to_linear(std::nanf("")), 0.0f);
}

TEST(SimIoGltf, DoubleSidedCopiesFromOtherExportersAreRemoved) {
  // A foreign double-sided export: the same triangles again, reversed, over the same vertices.
  TempDir dir;
  GltfBuilder b;
  const int base = b.floats(kQuad, "VEC3", true);
  const int idx = b.indices({0, 1, 2, 0, 2, 3, 0, 2, 1, 0, 3, 2});
  b.doc()["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", base}}}, {"indices", idx}}}}}};
  b.doc()["nodes"] = {{{"mesh", 0}}};
  const MeshSequence s = load_gltf(b.write(dir, "twice"));
  EXPECT_EQ(s.topology().triangles.size(), 2u);
  EXPECT_EQ(s.removed_faces(), 2u);
}

std::string error_place(const std::filesystem::path& p, const std::string& words) {
  try {
    load_gltf(p);
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), p.string());
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    return e.place();
  }
  return "no error";
}

TEST(SimIoGltf, UnsupportedFeaturesNameThePlace) {
  TempDir dir;
  {
    GltfBuilder b;
    const int base = b.floats(kQuad, "VEC3", true);
    const int idx = b.indices({0, 1, 1, 2});
    b.doc()["meshes"] = {
        {{"primitives", {{{"attributes", {{"POSITION", base}}}, {"indices", idx}, {"mode", 1}}}}}};
    b.doc()["nodes"] = {{{"mesh", 0}}};
    EXPECT_EQ(error_place(b.write(dir, "lines"), "LINES"), "mesh 0 primitive 0");
  }
  {
    GltfBuilder b;
    const int base = b.floats(kQuad, "VEC3", true);
    const int idx = b.indices(kQuadIndices);
    const int sparse_indices = b.indices({1});
    const int sparse_values = b.floats({0, 1, 0}, "VEC3");
    b.doc()["accessors"][std::size_t(base)]["sparse"] = {
        {"count", 1},
        {"indices",
         {{"bufferView", b.doc()["accessors"][std::size_t(sparse_indices)]["bufferView"]},
          {"componentType", 5125}}},
        {"values", {{"bufferView", b.doc()["accessors"][std::size_t(sparse_values)]["bufferView"]}}}};
    b.doc()["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", base}}}, {"indices", idx}}}}}};
    b.doc()["nodes"] = {{{"mesh", 0}}};
    EXPECT_EQ(error_place(b.write(dir, "sparse"), "sparse"), "accessor " + std::to_string(base));
  }
  {
    GltfBuilder b;
    const int base = b.floats(kQuad, "VEC3", true);
    const int idx = b.indices(kQuadIndices);
    b.doc()["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", base}}}, {"indices", idx}}}}}};
    b.doc()["nodes"] = {{{"mesh", 0}}};
    b.doc()["extensionsUsed"] = {"KHR_draco_mesh_compression"};
    b.doc()["extensionsRequired"] = {"KHR_draco_mesh_compression"};
    EXPECT_EQ(error_place(b.write(dir, "draco"), "KHR_draco_mesh_compression"), "extensionsRequired");
  }
  {
    GltfBuilder b;
    const int base = b.floats(kQuad, "VEC3", true);
    const int idx = b.indices({0, 1, 2, 0, 2, 4});
    b.doc()["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", base}}}, {"indices", idx}}}}}};
    b.doc()["nodes"] = {{{"mesh", 0}}};
    EXPECT_EQ(error_place(b.write(dir, "range"), "out of range"), "accessor " + std::to_string(idx));
  }
  {
    GltfBuilder b;
    const int base = b.floats({0, 0, 0, 1, 0, 0, 1, std::nanf(""), 1, 0, 0, 1}, "VEC3");
    const int idx = b.indices(kQuadIndices);
    b.doc()["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", base}}}, {"indices", idx}}}}}};
    b.doc()["nodes"] = {{{"mesh", 0}}};
    EXPECT_EQ(error_place(b.write(dir, "nan"), "non-finite"), "frame 0, vertex 2 (accessor 0)");
  }
  {
    GltfBuilder b;
    b.doc()["nodes"] = {{{"name", "empty"}}};
    EXPECT_EQ(error_place(b.write(dir, "empty"), "empty mesh"), "");
  }
}

TEST(SimIoGltf, WrongMagicAndTruncatedGlb) {
  TempDir dir;
  test::write_bytes(dir / "x.glb", "not a glb at all, just text");
  EXPECT_EQ(error_place(dir / "x.glb", "magic"), "byte 0");
  const MeshSequence sheet = test::folding_sheet(1, 1, 2);
  const std::vector<glm::vec3> white(sheet.topology().num_vertices, glm::vec3(1.0f));
  write_shaded_glb(dir / "ok.glb", sheet, {0, 1}, {white, white}, {white, white}, 24.0);
  const std::string bytes = test::slurp(dir / "ok.glb");
  test::write_bytes(dir / "short.glb", bytes.substr(0, bytes.size() - 10));
  EXPECT_EQ(error_place(dir / "short.glb", "truncated"), "byte " + std::to_string(bytes.size() - 10));
}

class GlbCorruption {
 public:
  GlbCorruption() {
    const MeshSequence sheet = test::folding_sheet(2, 1, 3);
    const std::vector<glm::vec3> grey(sheet.topology().num_vertices, glm::vec3(0.5f));
    write_shaded_glb(m_dir / "s.glb", sheet, {0, 1, 2}, {grey, grey, grey}, {grey, grey, grey}, 24.0);
    m_bytes = test::slurp(m_dir / "s.glb");
  }
  const std::string& bytes() const { return m_bytes; }
  void check(const std::string& corrupted) {
    test::write_bytes(m_dir / "c.glb", corrupted);
    try {
      const MeshSequence s = load_sequence(m_dir / "c.glb");
      for (std::size_t i = 0; i < s.num_frames(); ++i) s.frame(i);
    } catch (const InputError&) {
      // a clean failure; anything else fails the property
    }
  }

 private:
  TempDir m_dir;
  std::string m_bytes;
};

RC_GTEST_PROP(SimIoGltf, GlbBitFlipsLoadOrFailCleanly, ()) {
  static GlbCorruption fixture;
  fixture.check(test::flip_random_bits(fixture.bytes()));
}

RC_GTEST_PROP(SimIoGltf, GlbTruncationsLoadOrFailCleanly, ()) {
  static GlbCorruption fixture;
  fixture.check(fixture.bytes().substr(0, *rc::gen::inRange<std::size_t>(0, fixture.bytes().size())));
}

RC_GTEST_PROP(SimIoGltf, GlbOverwritesLoadOrFailCleanly, ()) {
  static GlbCorruption fixture;
  std::string bytes = fixture.bytes();
  const auto at = *rc::gen::inRange<std::size_t>(0, bytes.size());
  const auto junk =
      *rc::gen::container<std::string>(*rc::gen::inRange<std::size_t>(1, 9), rc::gen::arbitrary<char>());
  for (std::size_t k = 0; k < junk.size() && at + k < bytes.size(); ++k) bytes[at + k] = junk[k];
  fixture.check(bytes);
}

}  // namespace
}  // namespace pleat
