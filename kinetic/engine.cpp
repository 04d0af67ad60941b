#include "kinetic/engine.hpp"

#include <stdexcept>
#include <string>

namespace pleat {

EngineKind engine_kind_from_name(std::string_view name) {
  if (name == "kinetic") return EngineKind::Kinetic;
  if (name == "static") return EngineKind::Static;
  throw std::invalid_argument("engine '" + std::string(name) + "' is not kinetic or static");
}

const char* engine_kind_name(EngineKind kind) { return kind == EngineKind::Static ? "static" : "kinetic"; }

Engine::Engine(const MeshTopology& topology, SlicingPlan plan, const EngineParams& params)
    : m_topology(&topology), m_plan(std::move(plan)), m_params(params) {
  if (m_params.kind == EngineKind::Static)
    m_static.emplace(topology, m_plan, VisibilityParams{params.parallel});
}

const FrameVisibility& Engine::compute(const Frame& frame) {
  if (m_static) return m_static->compute(frame);
  if (!m_kinetic) {
    KineticParams params;  // invariant checks: on in Debug builds only
    params.parallel = m_params.parallel;
    params.policy = m_params.policy;
    m_kinetic.emplace(*m_topology, m_plan, frame, params);
    return m_kinetic->current();
  }
  return m_kinetic->advance(frame);
}

const KineticFrameStats* Engine::kinetic_stats() const {
  return m_kinetic ? &m_kinetic->last_stats() : nullptr;
}

}  // namespace pleat
