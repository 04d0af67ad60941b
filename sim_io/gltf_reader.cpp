#include "sim_io/gltf_reader.hpp"

#include <tiny_gltf.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <numeric>
#include <optional>
#include <stdexcept>

#include "sim_io/input_file.hpp"
#include "sim_io/input_formats.hpp"
#include "support/input_error.hpp"
#include "support/srgb.hpp"

namespace pleat {

namespace {

using tinygltf::Model;

constexpr int kModeTriangles = 4;
constexpr int kModeTriangleStrip = 5;
constexpr int kModeTriangleFan = 6;

std::string at_accessor(int index) { return "accessor " + std::to_string(index); }

bool ignore_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*,
                  int, void*) {
  return true;  // pleat reads geometry only; images are neither decoded nor checked
}

std::uint32_t load_u32(const std::string& bytes, std::size_t offset) {
  std::uint32_t v = 0;
  for (int k = 3; k >= 0; --k) v = (v << 8) | static_cast<unsigned char>(bytes[offset + std::size_t(k)]);
  return v;
}

Model load_model(const std::filesystem::path& path) {
  const std::string file = path.string();
  const std::string bytes = read_whole_file(path);
  std::string extension = path.extension().string();
  for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
  const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  if (extension == ".glb" && !binary)
    throw InputError(file, "byte 0", "wrong magic: not a binary glTF (expected \"glTF\")");
  if (bytes.size() > std::numeric_limits<unsigned int>::max())
    throw InputError(file, "", "file too large (over 4 GB)");
  if (binary) {
    // Check the GLB framing ourselves for precise messages; tinygltf checks it again.
    if (bytes.size() < 20)
      throw InputError(file, "byte " + std::to_string(bytes.size()),
                       "truncated: a GLB needs a 12-byte header and a chunk");
    if (load_u32(bytes, 4) != 2)
      throw InputError(file, "byte 4",
                       "unsupported glTF container version " + std::to_string(load_u32(bytes, 4)));
    const std::uint64_t declared = load_u32(bytes, 8);
    if (declared > bytes.size())
      throw InputError(file, "byte " + std::to_string(bytes.size()),
                       "truncated: the GLB header announces " + std::to_string(declared) + " bytes");
    const std::uint64_t json_end = 20 + std::uint64_t(load_u32(bytes, 12));
    if (load_u32(bytes, 16) != 0x4E4F534Au)
      throw InputError(file, "byte 16", "the first GLB chunk is not JSON");
    if (json_end > declared)
      throw InputError(file, "byte " + std::to_string(declared),
                       "truncated: the JSON chunk runs past the end of the GLB");
  }
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(ignore_image, nullptr);
  Model model;
  std::string error, warning;
  const std::string base_dir = path.has_parent_path() ? path.parent_path().string() : std::string(".");
  bool ok = false;
  try {
    const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
    ok = binary
             ? loader.LoadBinaryFromMemory(&model, &error, &warning, data, unsigned(bytes.size()), base_dir)
             : loader.LoadASCIIFromString(&model, &error, &warning, bytes.data(), unsigned(bytes.size()),
                                          base_dir);
  } catch (const std::exception& e) {
    throw InputError(file, "", std::string("invalid glTF: ") + e.what());
  }
  if (!ok) {
    std::string first_line = error.substr(0, error.find('\n'));
    if (first_line.empty()) first_line = "unknown tinygltf error";
    throw InputError(file, "", "invalid glTF: " + first_line);
  }
  return model;
}

void check_extensions(const Model& model, const std::string& file) {
  for (const std::string& name : model.extensionsRequired) {
    const bool appearance_only = name.rfind("KHR_materials_", 0) == 0 || name.rfind("KHR_texture_", 0) == 0 ||
                                 name == "KHR_lights_punctual" || name == "EXT_texture_webp";
    if (!appearance_only)
      throw InputError(file, "extensionsRequired", "unsupported glTF feature: required extension " + name);
  }
}

// A typed, bounds-checked view of an accessor's elements.
struct AccessorView {
  const unsigned char* data = nullptr;
  std::size_t count = 0;
  std::size_t stride = 0;
  int component_type = 0;
  int components = 0;
  bool normalized = false;
};

AccessorView view_accessor(const Model& m, int index, const std::string& file, const std::string& role) {
  if (index < 0 || std::size_t(index) >= m.accessors.size())
    throw InputError(file, at_accessor(index), role + " refers to a missing accessor");
  const tinygltf::Accessor& a = m.accessors[std::size_t(index)];
  const std::string place = at_accessor(index);
  if (a.sparse.isSparse)
    throw InputError(file, place, "unsupported glTF feature: sparse accessor (" + role + ")");
  if (a.bufferView < 0 || std::size_t(a.bufferView) >= m.bufferViews.size())
    throw InputError(file, place,
                     "unsupported glTF feature: accessor without a valid bufferView (" + role + ")");
  const tinygltf::BufferView& bv = m.bufferViews[std::size_t(a.bufferView)];
  if (bv.buffer < 0 || std::size_t(bv.buffer) >= m.buffers.size())
    throw InputError(file, place,
                     "its bufferView " + std::to_string(a.bufferView) + " refers to a missing buffer");
  const tinygltf::Buffer& buffer = m.buffers[std::size_t(bv.buffer)];
  const int component_size = tinygltf::GetComponentSizeInBytes(std::uint32_t(a.componentType));
  const int components = tinygltf::GetNumComponentsInType(std::uint32_t(a.type));
  if (component_size <= 0 || components <= 0)
    throw InputError(file, place, "unknown component type or element type");
  const std::uint64_t element = std::uint64_t(component_size) * std::uint64_t(components);
  const std::uint64_t stride = bv.byteStride ? std::uint64_t(bv.byteStride) : element;
  if (stride < element) throw InputError(file, place, "byteStride smaller than the element size");
  if (std::uint64_t(bv.byteOffset) > buffer.data.size() ||
      std::uint64_t(bv.byteLength) > buffer.data.size() - bv.byteOffset)
    throw InputError(file, "bufferView " + std::to_string(a.bufferView), "runs past the end of its buffer");
  if (a.count > 0) {
    const std::uint64_t count = a.count;
    if (count > (std::uint64_t(bv.byteLength) / stride) + 1 ||
        std::uint64_t(a.byteOffset) + stride * (count - 1) + element > bv.byteLength)
      throw InputError(file, place,
                       "its " + std::to_string(count) + " elements run past the end of bufferView " +
                           std::to_string(a.bufferView));
  }
  AccessorView view;
  view.data = buffer.data.data() + bv.byteOffset + a.byteOffset;
  view.count = a.count;
  view.stride = std::size_t(stride);
  view.component_type = a.componentType;
  view.components = components;
  view.normalized = a.normalized;
  return view;
}

// Component c of element i as a float (float, or normalized integers as the glTF spec decodes them).
float read_float(const AccessorView& v, std::size_t i, int c) {
  const unsigned char* p = v.data + i * v.stride;
  switch (v.component_type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float f;
      std::memcpy(&f, p + 4 * c, 4);
      return f;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return float(p[c]) / 255.0f;
    case TINYGLTF_COMPONENT_TYPE_BYTE:
      return std::max(float(static_cast<signed char>(p[c])) / 127.0f, -1.0f);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      std::uint16_t s;
      std::memcpy(&s, p + 2 * c, 2);
      return float(s) / 65535.0f;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      std::int16_t s;
      std::memcpy(&s, p + 2 * c, 2);
      return std::max(float(s) / 32767.0f, -1.0f);
    }
    default:
      return std::numeric_limits<float>::quiet_NaN();
  }
}

AccessorView float_accessor(const Model& m, int index, int type, bool allow_normalized,
                            const std::string& file, const std::string& role) {
  AccessorView v = view_accessor(m, index, file, role);
  const tinygltf::Accessor& a = m.accessors[std::size_t(index)];
  if (a.type != type) throw InputError(file, at_accessor(index), role + " has the wrong element type");
  const bool is_float = a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT;
  const bool is_normalized_int = a.normalized && a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
  if (!is_float && !(allow_normalized && is_normalized_int))
    throw InputError(file, at_accessor(index),
                     "unsupported glTF feature: " + role + " is not float (quantized data)");
  return v;
}

std::vector<std::uint32_t> read_indices(const Model& m, int index, const std::string& file) {
  const AccessorView v = view_accessor(m, index, file, "indices");
  const tinygltf::Accessor& a = m.accessors[std::size_t(index)];
  if (a.type != TINYGLTF_TYPE_SCALAR) throw InputError(file, at_accessor(index), "indices are not scalars");
  std::vector<std::uint32_t> out(v.count);
  for (std::size_t i = 0; i < v.count; ++i) {
    const unsigned char* p = v.data + i * v.stride;
    switch (v.component_type) {
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        out[i] = p[0];
        break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        std::uint16_t s;
        std::memcpy(&s, p, 2);
        out[i] = s;
        break;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        std::memcpy(&out[i], p, 4);
        break;
      default:
        throw InputError(file, at_accessor(index), "indices must be unsigned byte, short or int");
    }
  }
  return out;
}

// The vertices and triangles of one glTF mesh: primitives sharing a POSITION accessor share vertices.
struct MeshLayout {
  std::vector<int> position_accessors;             // one slot per distinct POSITION accessor
  std::vector<std::size_t> offsets;                // first vertex of each slot
  std::vector<std::vector<int>> target_accessors;  // [slot][target] morph POSITION accessor, or -1
  std::size_t num_targets = 0;
  std::size_t num_vertices = 0;
  std::vector<Triangle> triangles;
  // TEXCOORD_0 and NORMAL per vertex (of the slots' primitives), each emptied when a slot lacks it.
  std::vector<glm::vec2> texcoords;
  std::vector<glm::vec3> normals;
  bool has_texcoords = true, has_normals = true;
};

// Appends the `n` values of a primitive's optional attribute `name` to `out`, or clears `out` and `has`
// when the primitive lacks it (a surface attribute is kept only where every primitive gives it).
template <int N>
void read_surface_attribute(const Model& m, const tinygltf::Primitive& prim, const char* name, int type,
                            std::size_t n, const std::string& file, std::vector<glm::vec<N, float>>& out,
                            bool& has) {
  const auto found = prim.attributes.find(name);
  if (!has || found == prim.attributes.end()) {
    has = false;
    out.clear();
    return;
  }
  const AccessorView values = float_accessor(m, found->second, type, N == 2, file, name);
  if (values.count != n)
    throw InputError(file, at_accessor(found->second),
                     std::string(name) + " has " + std::to_string(values.count) + " values for " +
                         std::to_string(n) + " positions");
  for (std::size_t i = 0; i < n; ++i) {
    glm::vec<N, float> v;
    for (int c = 0; c < N; ++c) v[c] = read_float(values, i, c);
    out.push_back(v);
  }
}

bool is_pleat_back_side(const tinygltf::Primitive& p) {
  if (!p.extras.IsObject() || !p.extras.Has("pleat_side")) return false;
  const tinygltf::Value& side = p.extras.Get("pleat_side");
  return side.IsString() && side.Get<std::string>() == "back";
}

MeshLayout layout_of_mesh(const Model& m, int mesh_index, const std::string& file) {
  const std::string mesh_place = "mesh " + std::to_string(mesh_index);
  if (mesh_index < 0 || std::size_t(mesh_index) >= m.meshes.size())
    throw InputError(file, mesh_place, "missing mesh");
  const tinygltf::Mesh& mesh = m.meshes[std::size_t(mesh_index)];
  MeshLayout layout;
  bool targets_known = false;
  for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
    const tinygltf::Primitive& prim = mesh.primitives[p];
    const std::string place = mesh_place + " primitive " + std::to_string(p);
    if (is_pleat_back_side(prim)) continue;
    if (prim.extensions.count("KHR_draco_mesh_compression"))
      throw InputError(file, place, "unsupported glTF feature: KHR_draco_mesh_compression");
    const int mode = prim.mode < 0 ? kModeTriangles : prim.mode;
    if (mode != kModeTriangles && mode != kModeTriangleStrip && mode != kModeTriangleFan) {
      static const char* const kNames[] = {"POINTS", "LINES", "LINE_LOOP", "LINE_STRIP"};
      const std::string name = mode >= 0 && mode < 4 ? kNames[mode] : "mode " + std::to_string(mode);
      throw InputError(file, place,
                       "unsupported glTF feature: primitive mode " + name + " (pleat reads triangles)");
    }
    const auto position = prim.attributes.find("POSITION");
    if (position == prim.attributes.end())
      throw InputError(file, place, "primitive has no POSITION attribute");
    const AccessorView positions =
        float_accessor(m, position->second, TINYGLTF_TYPE_VEC3, false, file, "POSITION");
    if (!targets_known) {
      layout.num_targets = prim.targets.size();
      targets_known = true;
    } else if (prim.targets.size() != layout.num_targets) {
      throw InputError(file, place, "primitives of one mesh have different numbers of morph targets");
    }
    const auto existing =
        std::find(layout.position_accessors.begin(), layout.position_accessors.end(), position->second);
    std::size_t slot = std::size_t(existing - layout.position_accessors.begin());
    if (existing == layout.position_accessors.end()) {
      layout.position_accessors.push_back(position->second);
      layout.offsets.push_back(layout.num_vertices);
      std::vector<int> targets;
      for (std::size_t t = 0; t < prim.targets.size(); ++t) {
        const auto tp = prim.targets[t].find("POSITION");
        int accessor = -1;
        if (tp != prim.targets[t].end()) {
          accessor = tp->second;
          const AccessorView target =
              float_accessor(m, accessor, TINYGLTF_TYPE_VEC3, true, file, "morph target POSITION");
          if (target.count != positions.count)
            throw InputError(file, at_accessor(accessor),
                             "morph target has " + std::to_string(target.count) +
                                 " positions, its base has " + std::to_string(positions.count));
        }
        targets.push_back(accessor);
      }
      layout.target_accessors.push_back(std::move(targets));
      read_surface_attribute<2>(m, prim, "TEXCOORD_0", TINYGLTF_TYPE_VEC2, positions.count, file,
                                layout.texcoords, layout.has_texcoords);
      read_surface_attribute<3>(m, prim, "NORMAL", TINYGLTF_TYPE_VEC3, positions.count, file, layout.normals,
                                layout.has_normals);
      layout.num_vertices += positions.count;
      if (layout.num_vertices > std::numeric_limits<Index>::max())
        throw InputError(file, place, "too many vertices");
    }
    std::vector<std::uint32_t> corners;
    if (prim.indices >= 0) {
      corners = read_indices(m, prim.indices, file);
      for (std::uint32_t c : corners)
        if (c >= positions.count)
          throw InputError(file, at_accessor(prim.indices),
                           "index " + std::to_string(c) + " out of range (" +
                               std::to_string(positions.count) + " vertices) in " + place);
    } else {
      corners.resize(positions.count);
      std::iota(corners.begin(), corners.end(), 0u);
    }
    const auto base = Index(layout.offsets[slot]);
    const auto add = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
      layout.triangles.push_back({base + a, base + b, base + c});
    };
    if (mode == kModeTriangles) {
      if (corners.size() % 3 != 0)
        throw InputError(
            file, place,
            "TRIANGLES primitive with " + std::to_string(corners.size()) + " indices (not a multiple of 3)");
      for (std::size_t i = 0; i + 2 < corners.size(); i += 3) add(corners[i], corners[i + 1], corners[i + 2]);
    } else if (mode == kModeTriangleStrip) {
      for (std::size_t i = 0; i + 2 < corners.size(); ++i)
        if (i % 2 == 0)
          add(corners[i], corners[i + 1], corners[i + 2]);
        else
          add(corners[i], corners[i + 2], corners[i + 1]);
    } else {
      for (std::size_t i = 1; i + 1 < corners.size(); ++i) add(corners[i], corners[i + 1], corners[0]);
    }
  }
  return layout;
}

glm::dmat4 local_matrix(const tinygltf::Node& n, const std::vector<double>* scale_override) {
  if (n.matrix.size() == 16) return glm::make_mat4(n.matrix.data());
  glm::dmat4 m(1.0);
  if (n.translation.size() == 3)
    m = glm::translate(m, glm::dvec3(n.translation[0], n.translation[1], n.translation[2]));
  if (n.rotation.size() == 4)
    m *= glm::mat4_cast(glm::dquat(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]));
  const std::vector<double>& s = scale_override ? *scale_override : n.scale;
  if (s.size() == 3) m = glm::scale(m, glm::dvec3(s[0], s[1], s[2]));
  return m;
}

struct MeshNode {
  int node = -1;
  glm::dmat4 parent_world{1.0};  // world transform of the node's parent
};

// Mesh nodes of the default scene in traversal order, with their parents' world transforms.
std::vector<MeshNode> scene_mesh_nodes(const Model& m, const std::string& file) {
  std::vector<int> roots;
  if (!m.scenes.empty()) {
    const int s = m.defaultScene >= 0 && std::size_t(m.defaultScene) < m.scenes.size() ? m.defaultScene : 0;
    roots = m.scenes[std::size_t(s)].nodes;
  } else {
    std::vector<bool> is_child(m.nodes.size(), false);
    for (const auto& n : m.nodes)
      for (int c : n.children)
        if (c >= 0 && std::size_t(c) < m.nodes.size()) is_child[std::size_t(c)] = true;
    for (std::size_t i = 0; i < m.nodes.size(); ++i)
      if (!is_child[i]) roots.push_back(int(i));
  }
  std::vector<MeshNode> out;
  std::vector<bool> visited(m.nodes.size(), false);
  struct Item {
    int node;
    glm::dmat4 parent_world;
  };
  std::vector<Item> stack;
  for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, glm::dmat4(1.0)});
  while (!stack.empty()) {
    const Item item = stack.back();
    stack.pop_back();
    if (item.node < 0 || std::size_t(item.node) >= m.nodes.size())
      throw InputError(file, "node " + std::to_string(item.node), "the scene refers to a missing node");
    if (visited[std::size_t(item.node)])
      throw InputError(file, "node " + std::to_string(item.node),
                       "node reached twice (cycle or shared child)");
    visited[std::size_t(item.node)] = true;
    const tinygltf::Node& n = m.nodes[std::size_t(item.node)];
    if (n.mesh >= 0) {
      if (n.skin >= 0)
        throw InputError(file, "node " + std::to_string(item.node), "unsupported glTF feature: skinned mesh");
      out.push_back({item.node, item.parent_world});
    }
    const glm::dmat4 world = item.parent_world * local_matrix(n, nullptr);
    for (auto c = n.children.rbegin(); c != n.children.rend(); ++c) stack.push_back({*c, world});
  }
  return out;
}

std::vector<float> read_scalars(const Model& m, int accessor, const std::string& file,
                                const std::string& role) {
  const AccessorView v = float_accessor(m, accessor, TINYGLTF_TYPE_SCALAR, true, file, role);
  std::vector<float> out(v.count);
  for (std::size_t i = 0; i < v.count; ++i) out[i] = read_float(v, i, 0);
  return out;
}

const tinygltf::AnimationSampler& sampler_of(const tinygltf::Animation& a, int animation,
                                             const tinygltf::AnimationChannel& c, const std::string& file) {
  if (c.sampler < 0 || std::size_t(c.sampler) >= a.samplers.size())
    throw InputError(file, "animation " + std::to_string(animation), "channel refers to a missing sampler");
  const auto& s = a.samplers[std::size_t(c.sampler)];
  if (s.interpolation != "LINEAR" && s.interpolation != "STEP" && s.interpolation != "CUBICSPLINE")
    throw InputError(file, "animation " + std::to_string(animation),
                     "unsupported glTF feature: interpolation " + s.interpolation);
  return s;
}

std::vector<float> read_key_times(const Model& m, int accessor, const std::string& file) {
  std::vector<float> times = read_scalars(m, accessor, file, "animation input");
  if (times.empty()) throw InputError(file, at_accessor(accessor), "animation with no keyframes");
  for (std::size_t i = 0; i < times.size(); ++i) {
    if (!std::isfinite(times[i]))
      throw InputError(file, at_accessor(accessor), "keyframe time is not finite");
    if (i > 0 && !(times[i] > times[i - 1]))
      throw InputError(file, at_accessor(accessor), "keyframe times do not increase strictly");
  }
  return times;
}

// One piece of a frame: a mesh layout under morph weights and a world transform.
struct Part {
  std::size_t layout = 0;
  std::vector<double> weights;
  glm::dmat4 world{1.0};
};

class GltfSource : public FrameSource {
 public:
  GltfSource(std::string file, Model model, std::vector<MeshLayout> layouts,
             std::vector<std::vector<Part>> frames, std::vector<double> times, double scene_fps)
      : m_file(std::move(file)),
        m_model(std::move(model)),
        m_layouts(std::move(layouts)),
        m_frames(std::move(frames)),
        m_times(std::move(times)),
        m_scene_fps(scene_fps) {}

  std::size_t num_frames() const override { return m_frames.size(); }
  double frame_time(std::size_t i) const override { return m_times.at(i); }
  std::int64_t source_frame(std::size_t i) const override {
    return std::llround(m_times.at(i) * m_scene_fps);
  }
  std::vector<glm::dvec3> read_frame(std::size_t i) const override {
    std::vector<glm::dvec3> out;
    for (const Part& part : m_frames.at(i)) {
      const MeshLayout& layout = m_layouts[part.layout];
      const std::size_t first = out.size();
      out.resize(first + layout.num_vertices);
      for (std::size_t slot = 0; slot < layout.position_accessors.size(); ++slot) {
        const AccessorView base = float_accessor(m_model, layout.position_accessors[slot], TINYGLTF_TYPE_VEC3,
                                                 false, m_file, "POSITION");
        glm::dvec3* dst = out.data() + first + layout.offsets[slot];
        for (std::size_t v = 0; v < base.count; ++v)
          dst[v] = glm::dvec3(read_float(base, v, 0), read_float(base, v, 1), read_float(base, v, 2));
        for (std::size_t t = 0; t < layout.num_targets && t < part.weights.size(); ++t) {
          const int accessor = layout.target_accessors[slot][t];
          if (accessor < 0 || part.weights[t] == 0.0) continue;
          const AccessorView target =
              float_accessor(m_model, accessor, TINYGLTF_TYPE_VEC3, true, m_file, "morph target POSITION");
          for (std::size_t v = 0; v < target.count; ++v)
            dst[v] += part.weights[t] * glm::dvec3(read_float(target, v, 0), read_float(target, v, 1),
                                                   read_float(target, v, 2));
        }
        for (std::size_t v = 0; v < base.count; ++v) {
          dst[v] = glm::dvec3(part.world * glm::dvec4(dst[v], 1.0));
          if (!std::isfinite(dst[v].x) || !std::isfinite(dst[v].y) || !std::isfinite(dst[v].z))
            throw InputError(m_file,
                             "frame " + std::to_string(i) + ", vertex " +
                                 std::to_string(first + layout.offsets[slot] + v) + " (" +
                                 at_accessor(layout.position_accessors[slot]) + ")",
                             "non-finite position");
        }
      }
    }
    return out;
  }

 private:
  std::string m_file;
  Model m_model;
  std::vector<MeshLayout> m_layouts;
  std::vector<std::vector<Part>> m_frames;
  std::vector<double> m_times;
  double m_scene_fps;
};

std::vector<double> default_weights(const Model& m, const tinygltf::Node& node, std::size_t num_targets) {
  std::vector<double> w = !node.weights.empty() ? node.weights : m.meshes[std::size_t(node.mesh)].weights;
  w.resize(num_targets, 0.0);
  return w;
}

/// The frames one layout of the default scene gives: the meshes' layouts, each frame's parts and its time
/// (empty when the layout does not apply).
struct FramesFound {
  std::vector<MeshLayout> layouts;
  std::vector<std::vector<Part>> frames;
  std::vector<double> times;
};

/// The scene's mesh nodes and how to place them.
struct Scene {
  const Model& model;
  const std::string& file;
  const std::vector<MeshNode>& mesh_nodes;
  glm::dmat4 world(const MeshNode& mn, const std::vector<double>* scale) const {
    return mn.parent_world * local_matrix(model.nodes[std::size_t(mn.node)], scale);
  }
};

/// Layout 1: the first animation with a morph-target `weights` channel on a mesh node of the scene; one frame
/// per keyframe.
FramesFound read_morph_animation(const Scene& scene) {
  const Model& model = scene.model;
  const std::string& file = scene.file;
  const std::vector<MeshNode>& mesh_nodes = scene.mesh_nodes;
  FramesFound found;
  for (std::size_t a = 0; a < model.animations.size() && found.frames.empty(); ++a) {
    const tinygltf::Animation& animation = model.animations[a];
    for (const tinygltf::AnimationChannel& channel : animation.channels) {
      if (channel.target_path != "weights") continue;
      const auto mn = std::find_if(mesh_nodes.begin(), mesh_nodes.end(),
                                   [&](const MeshNode& n) { return n.node == channel.target_node; });
      if (mn == mesh_nodes.end()) continue;
      const tinygltf::Node& node = model.nodes[std::size_t(mn->node)];
      MeshLayout layout = layout_of_mesh(model, node.mesh, file);
      if (layout.num_targets == 0) continue;
      const tinygltf::AnimationSampler& sampler = sampler_of(animation, int(a), channel, file);
      const std::vector<float> keys = read_key_times(model, sampler.input, file);
      const std::vector<float> values = read_scalars(model, sampler.output, file, "weights animation output");
      const bool cubic = sampler.interpolation == "CUBICSPLINE";
      const std::size_t per_key = layout.num_targets * (cubic ? 3 : 1);
      if (values.size() != keys.size() * per_key)
        throw InputError(file, at_accessor(sampler.output),
                         "weights output has " + std::to_string(values.size()) + " values, expected " +
                             std::to_string(keys.size() * per_key) + " (" + std::to_string(keys.size()) +
                             " keys x " + std::to_string(layout.num_targets) + " targets" +
                             (cubic ? " x 3" : "") + ")");
      const glm::dmat4 world = scene.world(*mn, nullptr);
      found.layouts.push_back(std::move(layout));
      for (std::size_t k = 0; k < keys.size(); ++k) {
        Part part;
        part.world = world;
        const std::size_t first =
            k * per_key + (cubic ? found.layouts[0].num_targets : 0);  // cubic: (in, value, out)
        part.weights.assign(values.begin() + std::ptrdiff_t(first),
                            values.begin() + std::ptrdiff_t(first + found.layouts[0].num_targets));
        found.frames.push_back({std::move(part)});
        found.times.push_back(double(keys[k]));
      }
      break;
    }
  }
  return found;
}

/// Layout 2: two or more mesh nodes with the same connectivity, shown one at a time; ordered by when their
/// animated scale first becomes non-zero, else in scene order at `scene_fps`.
FramesFound read_flipbook(const Scene& scene, double scene_fps) {
  const Model& model = scene.model;
  const std::string& file = scene.file;
  const std::vector<MeshNode>& mesh_nodes = scene.mesh_nodes;
  FramesFound found;
  std::vector<MeshLayout> candidates;
  bool same = true;
  for (const MeshNode& mn : mesh_nodes) {
    candidates.push_back(layout_of_mesh(model, model.nodes[std::size_t(mn.node)].mesh, file));
    same = same && candidates.back().num_vertices == candidates.front().num_vertices &&
           candidates.back().triangles == candidates.front().triangles;
  }
  // Scale channels of the first animation that has one for every mesh node (node -> channel).
  std::optional<std::map<int, std::pair<std::size_t, const tinygltf::AnimationChannel*>>> scale_channels;
  for (std::size_t a = 0; a < model.animations.size() && !scale_channels; ++a) {
    std::map<int, std::pair<std::size_t, const tinygltf::AnimationChannel*>> of_node;
    for (const auto& channel : model.animations[a].channels)
      if (channel.target_path == "scale") of_node[channel.target_node] = {a, &channel};
    if (std::all_of(mesh_nodes.begin(), mesh_nodes.end(),
                    [&](const MeshNode& n) { return of_node.count(n.node) > 0; }))
      scale_channels = std::move(of_node);
  }
  std::vector<int> mesh_indices;
  mesh_indices.reserve(mesh_nodes.size());
  for (const MeshNode& mn : mesh_nodes) mesh_indices.push_back(model.nodes[std::size_t(mn.node)].mesh);
  std::sort(mesh_indices.begin(), mesh_indices.end());
  const bool distinct_meshes =
      std::adjacent_find(mesh_indices.begin(), mesh_indices.end()) == mesh_indices.end();
  if (same && (scale_channels || distinct_meshes)) {
    struct FlipFrame {
      double time;
      std::size_t node;
      std::vector<double> scale;
    };
    std::vector<FlipFrame> order;
    for (std::size_t i = 0; i < mesh_nodes.size(); ++i) {
      FlipFrame f{double(i) / scene_fps, i, {}};
      if (scale_channels) {
        const auto [a, channel] = scale_channels->at(mesh_nodes[i].node);
        const tinygltf::Animation& animation = model.animations[a];
        const auto& sampler = sampler_of(animation, int(a), *channel, file);
        const std::vector<float> keys = read_key_times(model, sampler.input, file);
        const AccessorView values =
            float_accessor(model, sampler.output, TINYGLTF_TYPE_VEC3, true, file, "scale animation output");
        const bool cubic = sampler.interpolation == "CUBICSPLINE";
        if (values.count != keys.size() * (cubic ? 3 : 1))
          throw InputError(file, at_accessor(sampler.output),
                           "scale output count does not match its keyframes");
        bool visible = false;
        for (std::size_t k = 0; k < keys.size() && !visible; ++k) {
          const std::size_t e = cubic ? 3 * k + 1 : k;
          const glm::dvec3 s(read_float(values, e, 0), read_float(values, e, 1), read_float(values, e, 2));
          if (s != glm::dvec3(0.0)) {
            visible = true;
            f.time = keys[k];
            f.scale = {s.x, s.y, s.z};
          }
        }
        if (!visible)
          throw InputError(file, "node " + std::to_string(mesh_nodes[i].node),
                           "flipbook frame is never visible (its animated scale stays 0)");
      }
      order.push_back(std::move(f));
    }
    std::stable_sort(order.begin(), order.end(),
                     [](const FlipFrame& a, const FlipFrame& b) { return a.time < b.time; });
    for (std::size_t j = 0; j < order.size(); ++j) {
      found.layouts.push_back(std::move(candidates[order[j].node]));
      Part part;
      part.layout = j;
      part.world = scene.world(mesh_nodes[order[j].node], order[j].scale.empty() ? nullptr : &order[j].scale);
      found.frames.push_back({std::move(part)});
      found.times.push_back(order[j].time);
    }
  }
  return found;
}

/// Layout 3: every mesh node merged into one mesh, one frame at time 0.
FramesFound read_static(const Scene& scene) {
  const Model& model = scene.model;
  const std::string& file = scene.file;
  const std::vector<MeshNode>& mesh_nodes = scene.mesh_nodes;
  FramesFound found;
  std::vector<Part> parts;
  for (const MeshNode& mn : mesh_nodes) {
    const tinygltf::Node& node = model.nodes[std::size_t(mn.node)];
    found.layouts.push_back(layout_of_mesh(model, node.mesh, file));
    Part part;
    part.layout = found.layouts.size() - 1;
    part.weights = default_weights(model, node, found.layouts.back().num_targets);
    part.world = scene.world(mn, nullptr);
    parts.push_back(std::move(part));
  }
  found.frames.push_back(std::move(parts));
  found.times.push_back(0.0);
  return found;
}

}  // namespace

MeshSequence load_gltf(const std::filesystem::path& path, double scene_fps, const LoadScan& scan) {
  const std::string file = path.string();
  Model model = load_model(path);
  check_extensions(model, file);
  const std::vector<MeshNode> mesh_nodes = scene_mesh_nodes(model, file);
  if (mesh_nodes.empty()) throw InputError(file, "", "empty mesh: the scene has no mesh");
  const Scene scene{model, file, mesh_nodes};
  FramesFound found = read_morph_animation(scene);
  if (found.frames.empty() && mesh_nodes.size() >= 2) found = read_flipbook(scene, scene_fps);
  if (found.frames.empty()) found = read_static(scene);
  std::vector<MeshLayout>& layouts = found.layouts;
  std::vector<std::vector<Part>>& frames = found.frames;
  std::vector<double>& times = found.times;

  // Connectivity: the parts of the first frame, concatenated (every frame has the same parts' shapes), and
  // their UVs and normals (in world space, like the positions) per corner.
  std::vector<Triangle> triangles;
  std::size_t num_vertices = 0;
  SurfaceAttributes surface;
  bool has_texcoords = true, has_normals = true;
  for (const Part& part : frames.front()) {
    const MeshLayout& layout = layouts[part.layout];
    has_texcoords = has_texcoords && layout.has_texcoords;
    has_normals = has_normals && layout.has_normals;
    const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(glm::dmat3(part.world)));
    for (const Triangle& t : layout.triangles) {
      triangles.push_back(
          {Index(t[0] + num_vertices), Index(t[1] + num_vertices), Index(t[2] + num_vertices)});
      for (Index v : t) {
        if (has_texcoords) surface.texcoords.push_back(layout.texcoords[v]);
        if (has_normals) {
          const glm::dvec3 n = normal_matrix * glm::dvec3(layout.normals[v]);
          const double length = glm::length(n);
          surface.normals.push_back(glm::vec3(length > 0.0 ? n / length : n));
        }
      }
    }
    num_vertices += layout.num_vertices;
  }
  if (!has_texcoords) surface.texcoords.clear();
  if (!has_normals) surface.normals.clear();
  if (num_vertices == 0) throw InputError(file, "", "empty mesh: no vertices");
  if (num_vertices > std::numeric_limits<Index>::max()) throw InputError(file, "", "too many vertices");
  if (triangles.empty()) throw InputError(file, "", "empty mesh: no triangles");
  auto source = std::make_unique<GltfSource>(file, std::move(model), std::move(layouts), std::move(frames),
                                             std::move(times), scene_fps);
  return MeshSequence(file, std::move(triangles), Index(num_vertices), std::move(source), scan,
                      std::move(surface));
}

namespace {

MeshSequence open_gltf(const std::filesystem::path& input, const std::filesystem::path&,
                       const LoadOptions& options) {
  return load_gltf(input, options.scene_fps, options.scan);
}

// "%20" and the like of a URI.
std::string percent_decoded(const std::string& uri) {
  std::string text;
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
      text += char(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      text += uri[i];
    }
  }
  return text;
}

/// A .gltf and the external files (buffers, images) it names, beside it.
std::vector<std::filesystem::path> gltf_files(const std::filesystem::path& gltf) {
  std::vector<std::filesystem::path> files{gltf};
  std::ifstream in(gltf);
  const nlohmann::json document = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (!document.is_object()) return files;
  for (const char* kind : {"buffers", "images"}) {
    const auto list = document.find(kind);
    if (list == document.end() || !list->is_array()) continue;
    for (const nlohmann::json& item : *list) {
      if (!item.is_object() || !item.contains("uri") || !item["uri"].is_string()) continue;
      const std::string uri = item["uri"].get<std::string>();
      if (uri.rfind("data:", 0) == 0 || uri.find("://") != std::string::npos) continue;
      files.push_back(gltf.parent_path() / percent_decoded(uri));
    }
  }
  return files;
}

}  // namespace

namespace formats {
extern const MeshFormat kGltf{".gltf", ".gltf", "glTF", nullptr, open_gltf, gltf_files};
extern const MeshFormat kGlb{".glb", ".glb", "glTF", nullptr, open_gltf, nullptr};
}  // namespace formats

}  // namespace pleat
