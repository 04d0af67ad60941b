#include "sim_io/gltf_writer.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <glm/common.hpp>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "support/srgb.hpp"

namespace pleat {

namespace {

constexpr std::uint32_t kGlbMagic = 0x46546C67u;  // "glTF"
constexpr std::uint32_t kChunkJson = 0x4E4F534Au;
constexpr std::uint32_t kChunkBin = 0x004E4942u;

void put_u32(std::ostream& out, std::uint32_t v) {
  const char b[4] = {char(v & 0xFF), char((v >> 8) & 0xFF), char((v >> 16) & 0xFF), char((v >> 24) & 0xFF)};
  out.write(b, 4);
}

void put_floats(std::ostream& out, const std::vector<float>& values) {
  static_assert(std::endian::native == std::endian::little, "GLB writer assumes a little-endian host");
  out.write(reinterpret_cast<const char*>(values.data()), std::streamsize(values.size() * sizeof(float)));
}

std::string frame_name(std::size_t frame) {
  std::string digits = std::to_string(frame);
  if (digits.size() < 4) digits.insert(0, 4 - digits.size(), '0');
  return "frame_" + digits;
}

// Keyframes of flipbook node j out of n: visible (scale 1) from time j/fps to (j+1)/fps.
void flipbook_keys(std::size_t j, std::size_t n, double fps, std::vector<float>& times,
                   std::vector<float>& scales) {
  times.clear();
  scales.clear();
  const auto key = [&](double t, float s) {
    times.push_back(float(t));
    scales.insert(scales.end(), {s, s, s});
  };
  if (j == 0) {
    key(0.0, 1.0f);
    key(1.0 / fps, 0.0f);
  } else {
    key(0.0, 0.0f);
    key(double(j) / fps, 1.0f);
    key(double(j + 1) / fps, j + 1 == n ? 1.0f : 0.0f);  // the last frame stays until the clip ends
  }
}

}  // namespace

PositionBounds position_bounds(const Frame& frame) {
  PositionBounds b{glm::vec3(std::numeric_limits<float>::max()),
                   glm::vec3(std::numeric_limits<float>::lowest())};
  for (const glm::dvec3& p : frame.positions) {
    const glm::vec3 q(p);
    b.lo = glm::min(b.lo, q);
    b.hi = glm::max(b.hi, q);
  }
  return b;
}

ShadedGlbWriter::ShadedGlbWriter(const std::filesystem::path& path, const MeshSequence& sequence,
                                 std::vector<std::size_t> frames, double fps, bool with_visibility)
    : ShadedGlbWriter(path, sequence, std::move(frames), fps, with_visibility, {}) {}

ShadedGlbWriter::ShadedGlbWriter(const std::filesystem::path& path, const MeshSequence& sequence,
                                 std::vector<std::size_t> frames, double fps, bool with_visibility,
                                 const std::vector<PositionBounds>& bounds)
    : m_sequence(sequence), m_frames(std::move(frames)), m_with_visibility(with_visibility), m_file(path) {
  if (!bounds.empty() && bounds.size() != m_frames.size())
    throw std::invalid_argument("ShadedGlbWriter: one bounds per frame");
  if (m_frames.empty()) throw std::invalid_argument("ShadedGlbWriter: no frames");
  if (!(fps > 0.0) || !std::isfinite(fps))
    throw std::invalid_argument("ShadedGlbWriter: fps must be positive");
  for (std::size_t f : m_frames)
    if (f >= sequence.num_frames()) throw std::invalid_argument("ShadedGlbWriter: frame index out of range");
  const MeshTopology& topology = sequence.topology();
  if (topology.triangles.empty()) throw std::invalid_argument("ShadedGlbWriter: the mesh has no triangles");
  const std::uint64_t V = topology.num_vertices, T = topology.triangles.size(), F = m_frames.size();
  const std::uint64_t index_bytes = 12 * T;
  // Per frame: positions and both sides' colours (VEC3), then with visibility both sides' A (SCALAR) and
  // bent cones (VEC4); one buffer view per element type and frame.
  const std::uint64_t vec3_bytes = 36 * V, scalar_bytes = with_visibility ? 8 * V : 0,
                      vec4_bytes = with_visibility ? 32 * V : 0;
  const std::uint64_t frame_bytes = vec3_bytes + scalar_bytes + vec4_bytes;
  using nlohmann::json;

  json accessors = json::array(), buffer_views = json::array(), meshes = json::array(), nodes = json::array();
  buffer_views.push_back(
      {{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 2 * index_bytes}, {"target", 34963}});
  accessors.push_back(
      {{"bufferView", 0}, {"byteOffset", 0}, {"componentType", 5125}, {"count", 3 * T}, {"type", "SCALAR"}});
  accessors.push_back({{"bufferView", 0},
                       {"byteOffset", index_bytes},
                       {"componentType", 5125},
                       {"count", 3 * T},
                       {"type", "SCALAR"}});
  json children = json::array();
  for (std::size_t j = 0; j < F; ++j) {
    // Exact float bounds of the positions as they will be stored.
    const auto [lo, hi] = bounds.empty() ? position_bounds(sequence.frame(m_frames[j])) : bounds[j];
    const std::uint64_t offset = 2 * index_bytes + j * frame_bytes;
    const std::size_t vec3_view = buffer_views.size();
    buffer_views.push_back({{"buffer", 0},
                            {"byteOffset", offset},
                            {"byteLength", vec3_bytes},
                            {"byteStride", 12},
                            {"target", 34962}});
    const std::size_t position = accessors.size();
    accessors.push_back({{"bufferView", vec3_view},
                         {"byteOffset", 0},
                         {"componentType", 5126},
                         {"count", V},
                         {"type", "VEC3"},
                         {"min", {lo.x, lo.y, lo.z}},
                         {"max", {hi.x, hi.y, hi.z}}});
    for (std::uint64_t side = 0; side < 2; ++side)
      accessors.push_back({{"bufferView", vec3_view},
                           {"byteOffset", (1 + side) * 12 * V},
                           {"componentType", 5126},
                           {"count", V},
                           {"type", "VEC3"}});
    std::array<json, 2> sides{json::object({{"POSITION", position}, {"COLOR_0", position + 1}}),
                              json::object({{"POSITION", position}, {"COLOR_0", position + 2}})};
    if (with_visibility) {
      const std::size_t scalar_view = buffer_views.size();
      buffer_views.push_back({{"buffer", 0},
                              {"byteOffset", offset + vec3_bytes},
                              {"byteLength", scalar_bytes},
                              {"byteStride", 4},
                              {"target", 34962}});
      buffer_views.push_back({{"buffer", 0},
                              {"byteOffset", offset + vec3_bytes + scalar_bytes},
                              {"byteLength", vec4_bytes},
                              {"byteStride", 16},
                              {"target", 34962}});
      for (std::uint64_t side = 0; side < 2; ++side) {
        sides[side]["_SKY_VISIBILITY"] = accessors.size();
        accessors.push_back({{"bufferView", scalar_view},
                             {"byteOffset", side * 4 * V},
                             {"componentType", 5126},
                             {"count", V},
                             {"type", "SCALAR"}});
        sides[side]["_BENT_CONE"] = accessors.size();
        accessors.push_back({{"bufferView", scalar_view + 1},
                             {"byteOffset", side * 16 * V},
                             {"componentType", 5126},
                             {"count", V},
                             {"type", "VEC4"}});
      }
    }
    json front = {{"attributes", sides[0]}, {"indices", 0}, {"material", 0}, {"mode", 4}};
    json back = {{"attributes", sides[1]},
                 {"indices", 1},
                 {"material", 0},
                 {"mode", 4},
                 {"extras", {{"pleat_side", "back"}}}};
    meshes.push_back({{"name", frame_name(m_frames[j])}, {"primitives", {front, back}}});
    const double visible = j == 0 ? 1.0 : 0.0;
    nodes.push_back({{"name", frame_name(m_frames[j])}, {"mesh", j}, {"scale", {visible, visible, visible}}});
    children.push_back(j + 1);
  }
  json all_nodes = json::array();
  all_nodes.push_back(
      {{"name", sequence.name().empty() ? std::string("pleat")
                                        : std::filesystem::path(sequence.name()).stem().string()},
       {"children", children}});
  for (json& node : nodes) all_nodes.push_back(std::move(node));

  json document = {
      {"asset",
       {{"version", "2.0"}, {"generator", "pleat (flipbook: one node per frame, STEP scale visibility)"}}},
      {"extensionsUsed", {"KHR_materials_unlit"}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0}}}}},
      {"nodes", all_nodes},
      {"meshes", meshes},
      {"materials",
       {{{"name", "pleat_shaded"},
         {"pbrMetallicRoughness",
          {{"baseColorFactor", {1.0, 1.0, 1.0, 1.0}}, {"metallicFactor", 0.0}, {"roughnessFactor", 1.0}}},
         {"extensions", {{"KHR_materials_unlit", json::object()}}}}}},
  };

  // Animation: per node a STEP scale sampler; its keys go after the frames in the binary chunk.
  std::uint64_t tail_offset = 2 * index_bytes + F * frame_bytes;
  const std::size_t tail_view = buffer_views.size();
  if (F > 1) {
    json samplers = json::array(), channels = json::array();
    std::vector<float> times, scales;
    for (std::size_t j = 0; j < F; ++j) {
      flipbook_keys(j, F, fps, times, scales);
      const std::size_t input = accessors.size();
      const std::uint64_t at = m_tail.size();
      accessors.push_back({{"bufferView", tail_view},
                           {"byteOffset", at},
                           {"componentType", 5126},
                           {"count", times.size()},
                           {"type", "SCALAR"},
                           {"min", {times.front()}},
                           {"max", {times.back()}}});
      accessors.push_back({{"bufferView", tail_view},
                           {"byteOffset", at + 4 * times.size()},
                           {"componentType", 5126},
                           {"count", times.size()},
                           {"type", "VEC3"}});
      const auto append = [&](const std::vector<float>& v) {
        const auto* b = reinterpret_cast<const unsigned char*>(v.data());
        m_tail.insert(m_tail.end(), b, b + v.size() * sizeof(float));
      };
      append(times);
      append(scales);
      samplers.push_back({{"input", input}, {"output", input + 1}, {"interpolation", "STEP"}});
      channels.push_back({{"sampler", j}, {"target", {{"node", j + 1}, {"path", "scale"}}}});
    }
    buffer_views.push_back({{"buffer", 0}, {"byteOffset", tail_offset}, {"byteLength", m_tail.size()}});
    document["animations"] = {{{"name", "pleat_flipbook"}, {"samplers", samplers}, {"channels", channels}}};
  }
  m_tail_bytes = m_tail.size();
  const std::uint64_t bin_bytes = tail_offset + m_tail_bytes;
  document["accessors"] = accessors;
  document["bufferViews"] = buffer_views;
  document["buffers"] = {{{"byteLength", bin_bytes}}};

  std::string json_text = document.dump();
  while (json_text.size() % 4 != 0) json_text.push_back(' ');
  const std::uint64_t total = 12 + 8 + json_text.size() + 8 + bin_bytes;
  if (total > std::numeric_limits<std::uint32_t>::max())
    throw std::runtime_error(path.string() +
                             ": the shaded sequence exceeds the 4 GB GLB limit; write fewer frames");
  std::ostream& out = m_file.stream();
  put_u32(out, kGlbMagic);
  put_u32(out, 2);
  put_u32(out, std::uint32_t(total));
  put_u32(out, std::uint32_t(json_text.size()));
  put_u32(out, kChunkJson);
  out.write(json_text.data(), std::streamsize(json_text.size()));
  put_u32(out, std::uint32_t(bin_bytes));
  put_u32(out, kChunkBin);
  std::vector<std::uint32_t> indices;
  indices.reserve(3 * T);
  for (const Triangle& t : topology.triangles) indices.insert(indices.end(), {t[0], t[1], t[2]});
  out.write(reinterpret_cast<const char*>(indices.data()), std::streamsize(indices.size() * 4));
  indices.clear();
  for (const Triangle& t : topology.triangles) indices.insert(indices.end(), {t[0], t[2], t[1]});
  out.write(reinterpret_cast<const char*>(indices.data()), std::streamsize(indices.size() * 4));
}

ShadedGlbWriter::~ShadedGlbWriter() = default;

void ShadedGlbWriter::add_frame(const std::vector<glm::vec3>& front_srgb,
                                const std::vector<glm::vec3>& back_srgb) {
  if (m_with_visibility)
    throw std::logic_error("ShadedGlbWriter::add_frame: this writer was made with visibility");
  add_frame(front_srgb, back_srgb, {}, {});
}

void ShadedGlbWriter::add_frame(const std::vector<glm::vec3>& front_srgb,
                                const std::vector<glm::vec3>& back_srgb, const SideVisibility& front,
                                const SideVisibility& back) {
  if (m_next >= m_frames.size())
    throw std::logic_error("ShadedGlbWriter::add_frame: more frames than announced");
  const Frame frame = m_sequence.frame(m_frames[m_next]);
  std::vector<glm::vec3> positions(frame.positions.begin(), frame.positions.end());
  add_frame(positions, front_srgb, back_srgb, front, back);
}

void ShadedGlbWriter::add_frame(const std::vector<glm::vec3>& positions,
                                const std::vector<glm::vec3>& front_srgb,
                                const std::vector<glm::vec3>& back_srgb, const SideVisibility& front,
                                const SideVisibility& back) {
  if (m_next >= m_frames.size())
    throw std::logic_error("ShadedGlbWriter::add_frame: more frames than announced");
  const Index V = m_sequence.topology().num_vertices;
  if (front_srgb.size() != V || back_srgb.size() != V)
    throw std::invalid_argument("ShadedGlbWriter::add_frame: one colour per welded vertex and side");
  if (m_with_visibility)
    for (const SideVisibility* side : {&front, &back})
      if (side->sky_visibility.size() != V || side->bent_cone.size() != V)
        throw std::invalid_argument("ShadedGlbWriter::add_frame: one visibility per welded vertex and side");
  if (positions.size() != V)
    throw std::invalid_argument("ShadedGlbWriter::add_frame: one position per welded vertex");
  std::vector<float> values;
  values.reserve(4 * std::size_t(V));
  for (const glm::vec3& p : positions) values.insert(values.end(), {p.x, p.y, p.z});
  std::ostream& out = m_file.stream();
  put_floats(out, values);
  for (const auto* colours : {&front_srgb, &back_srgb}) {
    values.clear();
    for (const glm::vec3& c : *colours)
      values.insert(values.end(), {srgb_to_linear(c.r), srgb_to_linear(c.g), srgb_to_linear(c.b)});
    put_floats(out, values);
  }
  if (m_with_visibility) {
    for (const SideVisibility* side : {&front, &back}) put_floats(out, side->sky_visibility);
    for (const SideVisibility* side : {&front, &back}) {
      values.clear();
      for (const glm::vec4& b : side->bent_cone) values.insert(values.end(), {b.x, b.y, b.z, b.w});
      put_floats(out, values);
    }
  }
  ++m_next;
}

void ShadedGlbWriter::finish() {
  if (m_next != m_frames.size())
    throw std::logic_error("ShadedGlbWriter::finish: " + std::to_string(m_next) + " of " +
                           std::to_string(m_frames.size()) + " frames added");
  m_file.stream().write(reinterpret_cast<const char*>(m_tail.data()), std::streamsize(m_tail.size()));
  m_file.commit();
}

void write_shaded_glb(const std::filesystem::path& path, const MeshSequence& sequence,
                      const std::vector<std::size_t>& frames,
                      const std::vector<std::vector<glm::vec3>>& front_srgb,
                      const std::vector<std::vector<glm::vec3>>& back_srgb, double fps) {
  if (front_srgb.size() != frames.size() || back_srgb.size() != frames.size())
    throw std::invalid_argument("write_shaded_glb: one colour set per frame and side");
  ShadedGlbWriter writer(path, sequence, frames, fps);
  for (std::size_t j = 0; j < frames.size(); ++j) writer.add_frame(front_srgb[j], back_srgb[j]);
  writer.finish();
}

}  // namespace pleat
