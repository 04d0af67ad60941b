// Real (Blender) and generated cloth sequences for the frame-coherence benchmark.
#include "bench/coherence/sequences.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <stdexcept>

#include "sim_io/cloth_generators.hpp"
#include "sim_io/load_sequence.hpp"
#include "sim_io/mesh_sequence.hpp"

namespace pleat::bench {

namespace fs = std::filesystem;

namespace {

constexpr int kGeneratorCycle = 48;         // frames per motion cycle of the generated kinds
constexpr std::size_t kGeneratedStart = 8;  // first native frame of the generated kinds
constexpr std::size_t kDrapeStart = 20;     // the drape from sample 20 (Blender frame 41): the table turns
constexpr std::size_t kRealTail = 24;       // other real sequences: their last 24 samples (most folded)

fs::path obj_of(const fs::path& data, const std::string& name) { return data / name / (name + ".obj"); }
fs::path pc2_of(const fs::path& data, const std::string& name) { return data / name / (name + ".pc2"); }

}  // namespace

bool is_real_sequence(const std::string& name, const fs::path& data) {
  return !name.empty() && fs::exists(obj_of(data, name)) && fs::exists(pc2_of(data, name));
}

bool is_sequence_name(const std::string& name, const fs::path& data) {
  return is_real_sequence(name, data) || parse_cloth_kind(name).has_value();
}

std::vector<std::string> default_sequences(const fs::path& data) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(data, ec)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_directory() && is_real_sequence(name, data) && !parse_cloth_kind(name))
      names.push_back(name);
  }
  std::sort(names.begin(), names.end(), [](const std::string& a, const std::string& b) {
    return (a != "drape") < (b != "drape") || ((a != "drape") == (b != "drape") && a < b);
  });
  for (ClothKind kind : kAllClothKinds) names.emplace_back(cloth_kind_name(kind));
  return names;
}

BundledScene bundled_scene(const std::string& name, const fs::path& data) {
  BundledScene scene;
  const fs::path colliders = data / name / (name + "_colliders.obj");
  if (fs::exists(colliders)) {
    OccluderSpec spec{colliders.string(), {}};
    if (fs::exists(data / name / (name + "_colliders.pc2")))
      spec.cache = (data / name / (name + "_colliders.pc2")).string();
    scene.occluders.push_back(spec);
    scene.describe = name + "_colliders" + (spec.cache.empty() ? " (static)" : " (animated)");
  }
  if (name != "rucked") {  // simulated without a ground (data/README.md)
    scene.grounds.push_back(parse_ground_plane("y=0"));
    scene.describe += scene.describe.empty() ? "ground y=0" : ", ground y=0";
  }
  return scene;
}

Frame cloth_part(const Sequence& s, const Frame& frame) {
  Frame cloth{frame.time, {frame.positions.begin(), frame.positions.begin() + s.cloth.num_vertices}};
  return cloth;
}

SlicingPlan default_plan(const Sequence& s, const Frame& first) {
  return make_diffuse_plan(s.cloth, cloth_part(s, first), DiffusePlanParams{}, s.real ? &s.cover : nullptr);
}

SlicingPlan paper_plan(const Sequence& s, const Frame& first) {
  return make_paper_plan(s.cloth, cloth_part(s, first), s.real ? &s.cover : nullptr);
}

SlicingPlan setting_plan(const Sequence& s, const Frame& first, const Setting& setting) {
  SlicingPlan plan =
      make_diffuse_plan(s.cloth, cloth_part(s, first), setting.plan, s.real ? &s.cover : nullptr);
  plan.storage = setting.storage;
  plan.reconstruction = setting.reconstruction;
  return plan;
}

Sequence make_sequence(const std::string& name, Index size, const fs::path& data, bool in_scene) {
  Sequence s;
  s.name = name;
  s.size = size;
  if (!parse_cloth_kind(name)) {
    // The cloth and its scene, kept together (the scene reads the cloth's frames).
    struct Held {
      MeshSequence cloth;
      Scene scene;
      Held(MeshSequence c, const BundledScene& b)
          : cloth(std::move(c)), scene(cloth, b.occluders, b.grounds) {}
    };
    const BundledScene bundled = in_scene ? bundled_scene(name, data) : BundledScene{};
    const auto held =
        std::make_shared<const Held>(load_sequence(obj_of(data, name), pc2_of(data, name)), bundled);
    const std::size_t n = held->cloth.num_frames();
    const std::size_t start = name == "drape" ? kDrapeStart : (n > kRealTail ? n - kRealTail : 0);
    s.real = true;
    s.size = 0;
    s.topology = held->scene.topology();
    s.cloth = held->cloth.topology();
    s.cover = held->cloth.bounds();
    s.scene = bundled.describe;
    s.native_available = n > start ? n - start : 0;
    s.native = [held, start](std::size_t i) { return held->scene.frame(start + i); };
    return s;
  }
  const int resolution = static_cast<int>(std::lround(std::sqrt(double(size))));
  if (cloth_vertex_count(resolution) != size)
    throw std::invalid_argument("size " + std::to_string(size) +
                                " is not a square grid (try 3025, 29929, 300304)");
  auto generator = std::make_shared<ClothGenerator>(*parse_cloth_kind(name),
                                                    GeneratorParams{resolution, kGeneratorCycle, 24.0, 0});
  s.topology = generator->topology();
  s.cloth = s.topology;
  s.native_available = SIZE_MAX;
  s.native = [generator](std::size_t i) { return generator->frame((kGeneratedStart + i) % kGeneratorCycle); };
  return s;
}

std::vector<Frame> make_frames(const Sequence& s, double u, int count) {
  std::map<std::size_t, Frame> native;
  auto get = [&](std::size_t i) -> const Frame& {
    if (i >= s.native_available)
      throw std::out_of_range(s.name + " has " + std::to_string(s.native_available) +
                              " frames from its start; u=" + std::to_string(u) + " x " +
                              std::to_string(count) + " frames needs frame " + std::to_string(i));
    auto it = native.find(i);
    if (it == native.end()) it = native.emplace(i, s.native(i)).first;
    return it->second;
  };
  std::vector<Frame> frames(count);
  for (int k = 0; k < count; ++k) {
    const double t = double(k) / u;
    const std::size_t i = static_cast<std::size_t>(std::floor(t + 1e-9));
    const double f = t - double(i);
    const Frame& a = get(i);
    if (f < 1e-9) {
      frames[k] = a;
      continue;
    }
    const Frame& b = get(i + 1);
    Frame& out = frames[k];
    out.time = (1 - f) * a.time + f * b.time;
    out.positions.resize(a.positions.size());
    // a + f (b - a): a vertex at rest in both frames (a collider, a pinned or settled part) stays bit for bit
    // where it is, as a simulator's sub-frame samples leave it.
    for (std::size_t v = 0; v < a.positions.size(); ++v)
      out.positions[v] = a.positions[v] + f * (b.positions[v] - a.positions[v]);
  }
  return frames;
}

}  // namespace pleat::bench
