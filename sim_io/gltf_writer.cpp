#include "sim_io/gltf_writer.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <limits>
#include <map>
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

std::string frame_name(std::int64_t source_frame) {
  std::string digits = std::to_string(source_frame);
  if (digits.size() < 4) digits.insert(0, 4 - digits.size(), '0');
  return "frame_" + digits;
}

// Keyframes of flipbook node j: visible (scale 1) from times[j] to times[j + 1]; the last frame stays
// until the clip ends, 1 / fps after its time. `frame_times` increase strictly.
void flipbook_keys(std::size_t j, const std::vector<double>& frame_times, double fps,
                   std::vector<float>& times, std::vector<float>& scales) {
  times.clear();
  scales.clear();
  const auto key = [&](double t, float s) {
    times.push_back(float(t));
    scales.insert(scales.end(), {s, s, s});
  };
  const std::size_t n = frame_times.size();
  const double end = j + 1 < n ? frame_times[j + 1] : frame_times[j] + 1.0 / fps;
  if (j == 0) {
    key(frame_times[0], 1.0f);
    key(end, 0.0f);
  } else {
    key(frame_times[0], 0.0f);
    key(frame_times[j], 1.0f);
    key(end, j + 1 == n ? 1.0f : 0.0f);
  }
}

// The input layout's vertices: the input's, in its order, then a copy of a vertex for each further
// (UV, normal) pair its corners give (seams, hard edges). Fills the triangles over them and each vertex's
// welded vertex, input vertex, UV and normal.
struct InputVertices {
  std::vector<Index> welded, input;
  std::vector<glm::vec2> texcoords;
  std::vector<glm::vec3> normals;
  std::vector<Triangle> triangles;
};

InputVertices input_vertices(const MeshSequence& sequence) {
  const SurfaceAttributes& surface = sequence.surface();
  const bool uv = !surface.texcoords.empty(), normal = !surface.normals.empty();
  const Index n = sequence.num_input_vertices();
  InputVertices out;
  out.input.resize(n);
  for (Index v = 0; v < n; ++v) out.input[v] = v;
  out.texcoords.resize(uv ? n : 0);
  out.normals.resize(normal ? n : 0);
  using Key = std::array<std::uint32_t, 6>;  // input vertex, then the bits of u, v, nx, ny, nz
  const auto key_of = [](Index v, glm::vec2 t, glm::vec3 m) {
    const auto bits = [](float f) { return std::bit_cast<std::uint32_t>(f); };
    return Key{v, bits(t.x), bits(t.y), bits(m.x), bits(m.y), bits(m.z)};
  };
  std::vector<char> assigned(n, 0);
  std::map<Key, Index> copies;
  const std::vector<Triangle>& triangles = sequence.input_triangles();
  out.triangles.resize(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (std::size_t k = 0; k < 3; ++k) {
      const Index v = triangles[t][k];
      const glm::vec2 c_uv = uv ? surface.texcoords[3 * t + k] : glm::vec2(0.0f);
      const glm::vec3 c_n = normal ? surface.normals[3 * t + k] : glm::vec3(0.0f);
      Index g = v;
      if (!assigned[v]) {
        assigned[v] = 1;
        if (uv) out.texcoords[v] = c_uv;
        if (normal) out.normals[v] = c_n;
      } else if (key_of(v, uv ? out.texcoords[v] : c_uv, normal ? out.normals[v] : c_n) !=
                 key_of(v, c_uv, c_n)) {
        const auto [it, added] = copies.try_emplace(key_of(v, c_uv, c_n), Index(out.input.size()));
        if (added) {
          out.input.push_back(v);
          if (uv) out.texcoords.push_back(c_uv);
          if (normal) out.normals.push_back(c_n);
        }
        g = it->second;
      }
      out.triangles[t][k] = g;
    }
  out.welded.resize(out.input.size());
  for (std::size_t g = 0; g < out.input.size(); ++g) out.welded[g] = sequence.welded_of_input()[out.input[g]];
  return out;
}

using nlohmann::json;

/// The input layout's vertices with unit normals and finite UVs, as glTF wants them: normals normalized and
/// turned by `turn`; an attribute with a value that cannot be is left out.
InputVertices unit_input_vertices(const MeshSequence& sequence, const AxisTurn& turn) {
  InputVertices input = input_vertices(sequence);
  for (glm::vec3& n : input.normals) {
    const float length = glm::length(n);
    if (!(length > 0.0f) || !std::isfinite(length)) {
      input.normals.clear();
      break;
    }
    n = turn(n / length);
  }
  if (!std::all_of(input.texcoords.begin(), input.texcoords.end(),
                   [](glm::vec2 t) { return std::isfinite(t.x) && std::isfinite(t.y); }))
    input.texcoords.clear();
  return input;
}

/// Where things lie in a shaded GLB's binary chunk: the index blocks (front, and the back's reversed in the
/// sides layout), the input layout's UVs and normals, then per frame positions and both sides' colours
/// (VEC3), and with visibility both sides' A (SCALAR) and bent cones (VEC4); then the animation's keys.
struct GlbSizes {
  std::uint64_t V, T, F;
  std::uint64_t index_bytes, index_blocks, texcoord_bytes, normal_bytes, frames_offset;
  std::uint64_t vec3_bytes, scalar_bytes, vec4_bytes, frame_bytes;
};

GlbSizes glb_sizes(std::uint64_t V, std::uint64_t T, std::uint64_t F, bool input_layout,
                   const InputVertices& input, bool with_visibility) {
  GlbSizes s{};
  s.V = V, s.T = T, s.F = F;
  s.index_bytes = 12 * T, s.index_blocks = input_layout ? 1 : 2;
  s.texcoord_bytes = 8 * input.texcoords.size(), s.normal_bytes = 12 * input.normals.size();
  s.frames_offset = s.index_blocks * s.index_bytes + s.texcoord_bytes + s.normal_bytes;
  s.vec3_bytes = 36 * V, s.scalar_bytes = with_visibility ? 8 * V : 0,
  s.vec4_bytes = with_visibility ? 32 * V : 0;
  s.frame_bytes = s.vec3_bytes + s.scalar_bytes + s.vec4_bytes;
  return s;
}

/// The glTF document's arrays while they are built.
struct GlbArrays {
  json accessors = json::array(), buffer_views = json::array(), meshes = json::array(), nodes = json::array();
  json children = json::array();
};

/// The views and accessors every frame shares (indices; the input layout's UVs and normals). Returns the
/// input layout's per-vertex attributes ({} without any).
json add_shared_accessors(const GlbSizes& s, GlbArrays& g) {
  g.buffer_views.push_back(
      {{"buffer", 0}, {"byteOffset", 0}, {"byteLength", s.index_blocks * s.index_bytes}, {"target", 34963}});
  for (std::uint64_t block = 0; block < s.index_blocks; ++block)
    g.accessors.push_back({{"bufferView", 0},
                           {"byteOffset", block * s.index_bytes},
                           {"componentType", 5125},
                           {"count", 3 * s.T},
                           {"type", "SCALAR"}});
  json surface = json::object();  // the input layout's per-vertex attributes shared by every frame
  auto attribute = [&](const char* name, std::uint64_t offset, std::uint64_t bytes, int stride,
                       const char* type) {
    g.buffer_views.push_back({{"buffer", 0},
                              {"byteOffset", offset},
                              {"byteLength", bytes},
                              {"byteStride", stride},
                              {"target", 34962}});
    surface[name] = g.accessors.size();
    g.accessors.push_back({{"bufferView", g.buffer_views.size() - 1},
                           {"byteOffset", 0},
                           {"componentType", 5126},
                           {"count", s.V},
                           {"type", type}});
  };
  if (s.texcoord_bytes > 0)
    attribute("TEXCOORD_0", s.index_blocks * s.index_bytes, s.texcoord_bytes, 8, "VEC2");
  if (s.normal_bytes > 0)
    attribute("NORMAL", s.index_blocks * s.index_bytes + s.texcoord_bytes, s.normal_bytes, 12, "VEC3");
  return surface;
}

/// The primitives' attributes of frame j (views and accessors at the frame's place in the chunk; positions
/// bounded by lo, hi): [front, back], or in the input layout one primitive with both sides'.
std::array<json, 2> add_frame_accessors(std::size_t j, const GlbSizes& s, const glm::vec3& lo,
                                        const glm::vec3& hi, const json& surface, bool input_layout,
                                        bool with_visibility, GlbArrays& g) {
  const std::uint64_t offset = s.frames_offset + j * s.frame_bytes, V = s.V;
  const std::size_t vec3_view = g.buffer_views.size();
  g.buffer_views.push_back({{"buffer", 0},
                            {"byteOffset", offset},
                            {"byteLength", s.vec3_bytes},
                            {"byteStride", 12},
                            {"target", 34962}});
  const std::size_t position = g.accessors.size();
  g.accessors.push_back({{"bufferView", vec3_view},
                         {"byteOffset", 0},
                         {"componentType", 5126},
                         {"count", V},
                         {"type", "VEC3"},
                         {"min", {lo.x, lo.y, lo.z}},
                         {"max", {hi.x, hi.y, hi.z}}});
  for (std::uint64_t side = 0; side < 2; ++side)
    g.accessors.push_back({{"bufferView", vec3_view},
                           {"byteOffset", (1 + side) * 12 * V},
                           {"componentType", 5126},
                           {"count", V},
                           {"type", "VEC3"}});
  std::array<json, 2> sides{json::object({{"POSITION", position}, {"COLOR_0", position + 1}}),
                            json::object({{"POSITION", position}, {"COLOR_0", position + 2}})};
  if (input_layout) {  // one primitive: both sides' attributes, the back's colour in COLOR_1
    sides[0]["COLOR_1"] = position + 2;
    sides[0].update(surface);
  }
  if (!with_visibility) return sides;
  const std::size_t scalar_view = g.buffer_views.size();
  g.buffer_views.push_back({{"buffer", 0},
                            {"byteOffset", offset + s.vec3_bytes},
                            {"byteLength", s.scalar_bytes},
                            {"byteStride", 4},
                            {"target", 34962}});
  g.buffer_views.push_back({{"buffer", 0},
                            {"byteOffset", offset + s.vec3_bytes + s.scalar_bytes},
                            {"byteLength", s.vec4_bytes},
                            {"byteStride", 16},
                            {"target", 34962}});
  for (std::uint64_t side = 0; side < 2; ++side) {
    // The input layout names each side's attributes in its one primitive.
    json& attributes = input_layout ? sides[0] : sides[side];
    const std::string suffix = !input_layout ? "" : side == 0 ? "_FRONT" : "_BACK";
    attributes["_SKY_VISIBILITY" + suffix] = g.accessors.size();
    g.accessors.push_back({{"bufferView", scalar_view},
                           {"byteOffset", side * 4 * V},
                           {"componentType", 5126},
                           {"count", V},
                           {"type", "SCALAR"}});
    attributes["_BENT_CONE" + suffix] = g.accessors.size();
    g.accessors.push_back({{"bufferView", scalar_view + 1},
                           {"byteOffset", side * 16 * V},
                           {"componentType", 5126},
                           {"count", V},
                           {"type", "VEC4"}});
  }
  return sides;
}

/// Frame j's mesh (named after its source frame `source`) and node (visible for j == 0 only), from its
/// primitives' attributes; the input layout lists its seam copies' input vertices.
void add_frame_node(std::size_t j, std::int64_t source, const std::array<json, 2>& sides, bool input_layout,
                    const InputVertices& input, Index num_input_vertices, GlbArrays& g) {
  json front = {{"attributes", sides[0]}, {"indices", 0}, {"material", 0}, {"mode", 4}};
  json back = {{"attributes", sides[1]},
               {"indices", 1},
               {"material", 0},
               {"mode", 4},
               {"extras", {{"pleat_side", "back"}}}};
  json mesh = {{"name", frame_name(source)}};
  if (input_layout) {
    mesh["primitives"] = {front};
    if (input.input.size() > num_input_vertices)
      mesh["extras"] = {{"pleat_seam_copies",
                         std::vector<Index>(input.input.begin() + num_input_vertices, input.input.end())}};
  } else {
    mesh["primitives"] = {front, back};
  }
  g.meshes.push_back(std::move(mesh));
  const double visible = j == 0 ? 1.0 : 0.0;
  g.nodes.push_back({{"name", frame_name(source)}, {"mesh", j}, {"scale", {visible, visible, visible}}});
  g.children.push_back(j + 1);
}

/// The document's scene, nodes (a root named after the sequence, then the frames'), meshes and material.
json glb_document(const MeshSequence& sequence, bool input_layout, GlbArrays& g) {
  json all_nodes = json::array();
  all_nodes.push_back(
      {{"name", sequence.name().empty() ? std::string("pleat")
                                        : std::filesystem::path(sequence.name()).stem().string()},
       {"children", g.children}});
  for (json& node : g.nodes) all_nodes.push_back(std::move(node));
  return {
      {"asset",
       {{"version", "2.0"},
        {"generator", input_layout
                          ? "pleat (flipbook of the input mesh: one node per frame, STEP scale visibility)"
                          : "pleat (flipbook: one node per frame, STEP scale visibility)"}}},
      {"extensionsUsed", {"KHR_materials_unlit"}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0}}}}},
      {"nodes", all_nodes},
      {"meshes", g.meshes},
      {"materials",
       {{{"name", "pleat_shaded"},
         {"pbrMetallicRoughness",
          {{"baseColorFactor", {1.0, 1.0, 1.0, 1.0}}, {"metallicFactor", 0.0}, {"roughnessFactor", 1.0}}},
         {"doubleSided", input_layout},
         {"extensions", {{"KHR_materials_unlit", json::object()}}}}}},
  };
}

/// The flipbook animation of more than one frame: per node a STEP scale sampler whose keys are appended to
/// `tail` (read through one view at `tail_offset` of the chunk), into `document` and `g`.
void add_flipbook_animation(const MeshSequence& sequence, const std::vector<std::size_t>& frames, double fps,
                            std::uint64_t tail_offset, std::vector<unsigned char>& tail, json& document,
                            GlbArrays& g) {
  const std::size_t tail_view = g.buffer_views.size();
  json samplers = json::array(), channels = json::array();
  std::vector<double> frame_times;
  for (std::size_t f : frames) frame_times.push_back(sequence.frame_time(f));
  std::vector<float> times, scales;
  for (std::size_t j = 0; j < frames.size(); ++j) {
    flipbook_keys(j, frame_times, fps, times, scales);
    const std::size_t input = g.accessors.size();
    const std::uint64_t at = tail.size();
    g.accessors.push_back({{"bufferView", tail_view},
                           {"byteOffset", at},
                           {"componentType", 5126},
                           {"count", times.size()},
                           {"type", "SCALAR"},
                           {"min", {times.front()}},
                           {"max", {times.back()}}});
    g.accessors.push_back({{"bufferView", tail_view},
                           {"byteOffset", at + 4 * times.size()},
                           {"componentType", 5126},
                           {"count", times.size()},
                           {"type", "VEC3"}});
    const auto append = [&](const std::vector<float>& v) {
      const auto* b = reinterpret_cast<const unsigned char*>(v.data());
      tail.insert(tail.end(), b, b + v.size() * sizeof(float));
    };
    append(times);
    append(scales);
    samplers.push_back({{"input", input}, {"output", input + 1}, {"interpolation", "STEP"}});
    channels.push_back({{"sampler", j}, {"target", {{"node", j + 1}, {"path", "scale"}}}});
  }
  g.buffer_views.push_back({{"buffer", 0}, {"byteOffset", tail_offset}, {"byteLength", tail.size()}});
  document["animations"] = {{{"name", "pleat_flipbook"}, {"samplers", samplers}, {"channels", channels}}};
}

/// The GLB header, the JSON chunk and the binary chunk's header, indices, UVs and normals, to `out`. Throws
/// naming `path` when the file would exceed GLB's 4 GB.
void write_glb_start(std::ostream& out, const std::filesystem::path& path, std::string json_text,
                     std::uint64_t bin_bytes, const std::vector<Triangle>& triangles, bool input_layout,
                     const InputVertices& input) {
  while (json_text.size() % 4 != 0) json_text.push_back(' ');
  const std::uint64_t total = 12 + 8 + json_text.size() + 8 + bin_bytes;
  if (total > std::numeric_limits<std::uint32_t>::max())
    throw std::runtime_error(path.string() +
                             ": the shaded sequence exceeds the 4 GB GLB limit; write fewer frames");
  put_u32(out, kGlbMagic);
  put_u32(out, 2);
  put_u32(out, std::uint32_t(total));
  put_u32(out, std::uint32_t(json_text.size()));
  put_u32(out, kChunkJson);
  out.write(json_text.data(), std::streamsize(json_text.size()));
  put_u32(out, std::uint32_t(bin_bytes));
  put_u32(out, kChunkBin);
  std::vector<std::uint32_t> indices;
  indices.reserve(3 * triangles.size());
  for (const Triangle& t : triangles) indices.insert(indices.end(), {t[0], t[1], t[2]});
  out.write(reinterpret_cast<const char*>(indices.data()), std::streamsize(indices.size() * 4));
  if (!input_layout) {
    indices.clear();
    for (const Triangle& t : triangles) indices.insert(indices.end(), {t[0], t[2], t[1]});
    out.write(reinterpret_cast<const char*>(indices.data()), std::streamsize(indices.size() * 4));
  }
  std::vector<float> values;
  for (const glm::vec2& t : input.texcoords) values.insert(values.end(), {t.x, t.y});
  put_floats(out, values);
  values.clear();
  for (const glm::vec3& n : input.normals) values.insert(values.end(), {n.x, n.y, n.z});
  put_floats(out, values);
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
                                 std::vector<std::size_t> frames, double fps, bool with_visibility,
                                 GlbLayout layout)
    : ShadedGlbWriter(path, sequence, std::move(frames), fps, with_visibility, {}, layout) {}

ShadedGlbWriter::ShadedGlbWriter(const std::filesystem::path& path, const MeshSequence& sequence,
                                 std::vector<std::size_t> frames, double fps, bool with_visibility,
                                 const std::vector<PositionBounds>& bounds, GlbLayout layout,
                                 const AxisTurn& turn)
    : m_sequence(sequence),
      m_frames(std::move(frames)),
      m_with_visibility(with_visibility),
      m_turn(turn),
      m_file(path) {
  if (!bounds.empty() && bounds.size() != m_frames.size())
    throw std::invalid_argument("ShadedGlbWriter: one bounds per frame");
  if (m_frames.empty()) throw std::invalid_argument("ShadedGlbWriter: no frames");
  if (!(fps > 0.0) || !std::isfinite(fps))
    throw std::invalid_argument("ShadedGlbWriter: fps must be positive");
  for (std::size_t f : m_frames)
    if (f >= sequence.num_frames()) throw std::invalid_argument("ShadedGlbWriter: frame index out of range");
  const MeshTopology& topology = sequence.topology();
  if (topology.triangles.empty()) throw std::invalid_argument("ShadedGlbWriter: the mesh has no triangles");
  const bool input_layout = layout == GlbLayout::Input;
  InputVertices input;
  if (input_layout) {
    input = unit_input_vertices(sequence, turn);
    m_welded_of_vertex = input.welded;
  }
  const std::vector<Triangle>& triangles = input_layout ? input.triangles : topology.triangles;
  const GlbSizes sizes = glb_sizes(input_layout ? input.welded.size() : topology.num_vertices,
                                   triangles.size(), m_frames.size(), input_layout, input, with_visibility);
  GlbArrays arrays;
  const json surface = add_shared_accessors(sizes, arrays);
  for (std::size_t j = 0; j < m_frames.size(); ++j) {
    // Exact float bounds of the positions as they will be stored.
    auto [lo, hi] = bounds.empty() ? position_bounds(sequence.frame(m_frames[j])) : bounds[j];
    turn.bounds(lo, hi);
    const std::array<json, 2> sides =
        add_frame_accessors(j, sizes, lo, hi, surface, input_layout, with_visibility, arrays);
    add_frame_node(j, sequence.source_frame(m_frames[j]), sides, input_layout, input,
                   sequence.num_input_vertices(), arrays);
  }
  json document = glb_document(sequence, input_layout, arrays);
  // Animation: its keys go after the frames in the binary chunk.
  const std::uint64_t tail_offset = sizes.frames_offset + sizes.F * sizes.frame_bytes;
  if (m_frames.size() > 1)
    add_flipbook_animation(sequence, m_frames, fps, tail_offset, m_tail, document, arrays);
  m_tail_bytes = m_tail.size();
  const std::uint64_t bin_bytes = tail_offset + m_tail_bytes;
  document["accessors"] = arrays.accessors;
  document["bufferViews"] = arrays.buffer_views;
  document["buffers"] = {{{"byteLength", bin_bytes}}};
  write_glb_start(m_file.stream(), path, document.dump(), bin_bytes, triangles, input_layout, input);
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
  // The file's vertices: the welded ones (sides layout) or m_welded_of_vertex's (input layout).
  const std::size_t count = m_welded_of_vertex.empty() ? V : m_welded_of_vertex.size();
  const auto welded = [&](std::size_t g) { return m_welded_of_vertex.empty() ? g : m_welded_of_vertex[g]; };
  std::vector<float> values;
  values.reserve(4 * count);
  for (std::size_t g = 0; g < count; ++g) {
    const glm::vec3 p = m_turn(positions[welded(g)]);
    values.insert(values.end(), {p.x, p.y, p.z});
  }
  std::ostream& out = m_file.stream();
  put_floats(out, values);
  for (const auto* colours : {&front_srgb, &back_srgb}) {
    values.clear();
    for (std::size_t g = 0; g < count; ++g) {
      const glm::vec3& c = (*colours)[welded(g)];
      values.insert(values.end(), {srgb_to_linear(c.r), srgb_to_linear(c.g), srgb_to_linear(c.b)});
    }
    put_floats(out, values);
  }
  if (m_with_visibility) {
    for (const SideVisibility* side : {&front, &back}) {
      values.clear();
      for (std::size_t g = 0; g < count; ++g) values.push_back(side->sky_visibility[welded(g)]);
      put_floats(out, values);
    }
    for (const SideVisibility* side : {&front, &back}) {
      values.clear();
      for (std::size_t g = 0; g < count; ++g) {
        const glm::vec4& b = side->bent_cone[welded(g)];
        const glm::vec3 n = m_turn(glm::vec3(b));
        values.insert(values.end(), {n.x, n.y, n.z, b.w});
      }
      put_floats(out, values);
    }
  }
  m_file.check();  // a full disk ends the run at this frame
  ++m_next;
}

void ShadedGlbWriter::close() {
  if (m_closed) return;
  if (m_next != m_frames.size())
    throw std::logic_error("ShadedGlbWriter::finish: " + std::to_string(m_next) + " of " +
                           std::to_string(m_frames.size()) + " frames added");
  m_file.stream().write(reinterpret_cast<const char*>(m_tail.data()), std::streamsize(m_tail.size()));
  m_file.close();
  m_closed = true;
}

void ShadedGlbWriter::commit() {
  close();
  m_file.commit();
}

void ShadedGlbWriter::finish() { commit(); }

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
