// pleat::Engine: the one interface to both visibility engines, for a sequence whose topology and slicing plan
// are fixed: compute(frame) gives each frame's cones and measures in turn. The static engine
// (StaticVisibility) recomputes every frame; the kinetic one (KineticVisibility) is built on the first frame
// it is given and carried to each next one. Both give the same results (tests/kinetic_visibility_test.cpp),
// so the choice is one of speed only. The command line (`pleat visibility --engine`) and the Python module go
// through it. Frames need not be consecutive; each is validated (static_core/mesh_validation.hpp:
// InputError).
#pragma once

#include <functional>
#include <optional>
#include <string_view>

#include "kinetic/kinetic_visibility.hpp"
#include "static_core/mesh.hpp"
#include "static_core/slicing_plan.hpp"
#include "static_core/visibility.hpp"
#include "static_core/visibility_cone.hpp"

namespace pleat {

enum class EngineKind { Kinetic, Static };

/// "kinetic" or "static"; throws std::invalid_argument naming the text otherwise.
EngineKind engine_kind_from_name(std::string_view name);
const char* engine_kind_name(EngineKind kind);

struct EngineParams {
  EngineKind kind = EngineKind::Kinetic;
  bool parallel = true;           ///< TBB-parallel over slices (in the caller's task arena)
  kinetic::KineticPolicy policy;  ///< kinetic only: repair or rebuild
  /// VisibilityParams::poll, for either engine: an exception it throws leaves compute() and the engine
  /// usable (the kinetic one starts again from the next frame it is given, with the same results).
  std::function<void()> poll = {};
  FrameProgress* progress = nullptr;  ///< when set, advanced as each frame is computed (visibility.hpp)
};

class Engine {
 public:
  /// `topology` must outlive the engine; it is validated here (static) or with the first frame (kinetic).
  Engine(const MeshTopology& topology, SlicingPlan plan, const EngineParams& params = {});
  /// The cones and measures of `frame` (per welded vertex that receives cones); the reference stays valid
  /// until the next call. A rejected frame (InputError) leaves the engine as it was.
  const FrameVisibility& compute(const Frame& frame);
  /// The kinetic engine's counters for the last frame it carried: null for the static engine and before the
  /// first frame, zeros after the first (a static build).
  const KineticFrameStats* kinetic_stats() const;
  const SlicingPlan& plan() const { return m_plan; }
  EngineKind kind() const { return m_params.kind; }

 private:
  const MeshTopology* m_topology;
  SlicingPlan m_plan;
  EngineParams m_params;
  std::optional<StaticVisibility> m_static;
  std::optional<KineticVisibility> m_kinetic;
};

}  // namespace pleat
