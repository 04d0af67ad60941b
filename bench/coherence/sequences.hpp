// The cloth sequences of the frame-coherence benchmark and their frames at a temporal resolution.
//
// Real sequences: every data/NAME/ holding NAME.obj + NAME.pc2 (Blender simulations: drape, pile, rucked,
// ...), their size fixed, taken from a start sample where the cloth has landed (the drape from sample 20; the
// others from 24 samples before their end, so that the most folded frames are measured). Generated sequences:
// ClothGenerator's kinds (curtain, roll, flag, sleeve) at resolution sqrt(size) (3025 -> 55, 29929 -> 173,
// 300304 -> 548), 48 frames per motion cycle (24 fps), from frame 8 on (the cycle loops, so any length is
// available). Temporal resolution u: 1 = native frames; u = 2, 4, 8 insert u-1 linearly interpolated frames
// between consecutive native frames; u = 0.5 takes every other native frame. Frame k is at native time k / u.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "bench/coherence/plan_setting.hpp"
#include "sim_io/scene.hpp"
#include "static_core/mesh.hpp"
#include "static_core/slicing_plan.hpp"

namespace pleat::bench {

struct Sequence {
  std::string name;
  Index size = 0;  ///< as asked for (0 for a real sequence)
  bool real = false;
  /// A real sequence in the scene it was simulated in (bundled_scene): the cloth's vertices, then its
  /// colliders' (MeshTopology::num_occluder_vertices); every method measures the cloth's vertices in that
  /// scene. A generated one: the cloth alone.
  MeshTopology topology;
  MeshTopology cloth;  ///< the cloth's own topology (the plan is made on it)
  Bounds cover;        ///< the box of every frame of the cloth (a real sequence's plan covers it)
  std::string scene;   ///< what besides the cloth occludes ("" for none)
  std::function<Frame(std::size_t)> native;  ///< native frame i, counted from the start frame
  std::size_t native_available = 0;          ///< SIZE_MAX: loops
};

/// The real sequences found in `data` (sorted, the drape first), then the generated kinds.
std::vector<std::string> default_sequences(const std::filesystem::path& data);
bool is_sequence_name(const std::string& name, const std::filesystem::path& data);
bool is_real_sequence(const std::string& name, const std::filesystem::path& data);

/// Throws std::invalid_argument for a size that is not a square grid, and the readers' errors. `in_scene`: a
/// real sequence with its colliders (bundled_scene); else the cloth alone.
Sequence make_sequence(const std::string& name, Index size, const std::filesystem::path& data,
                       bool in_scene = false);

/// The colliders a bundled real sequence was simulated against (data/README.md): NAME_colliders.obj, with
/// NAME_colliders.pc2 when animated, and the ground y = 0 in every scene but the rucked sleeve's.
struct BundledScene {
  std::vector<OccluderSpec> occluders;
  std::vector<GroundPlane> grounds;
  std::string describe;
};
BundledScene bundled_scene(const std::string& name, const std::filesystem::path& data);

/// The cloth's part of a frame of `s` (its first s.cloth.num_vertices positions).
Frame cloth_part(const Sequence& s, const Frame& frame);
/// The plans the cone engines cut `s` with: pleat's default, and the paper's, made on the cloth of `first`.
SlicingPlan default_plan(const Sequence& s, const Frame& first);
SlicingPlan paper_plan(const Sequence& s, const Frame& first);
/// The plan of a named setting (plan_setting.hpp), made like default_plan.
SlicingPlan setting_plan(const Sequence& s, const Frame& first, const Setting& setting);

/// Frames 0..count-1 at temporal resolution u. Throws std::out_of_range past the sequence's end.
std::vector<Frame> make_frames(const Sequence& s, double u, int count);

}  // namespace pleat::bench
