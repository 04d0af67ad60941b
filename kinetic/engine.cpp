#include "kinetic/engine.hpp"

#include <stdexcept>
#include <string>

#include "support/input_error.hpp"

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
    m_static.emplace(topology, m_plan, VisibilityParams{params.parallel, params.poll, params.progress});
}

const FrameVisibility& Engine::compute(const Frame& frame) {
  if (m_static) return m_static->compute(frame);
  if (!m_kinetic) {
    KineticParams params;  // invariant checks: on in Debug builds only
    params.parallel = m_params.parallel;
    params.policy = m_params.policy;
    params.poll = m_params.poll;
    params.progress = m_params.progress;
    m_kinetic.emplace(*m_topology, m_plan, frame, params);
    return m_kinetic->current();
  }
  try {
    return m_kinetic->advance(frame);
  } catch (const InputError&) {
    throw;  // rejected before anything changed
  } catch (...) {
    m_kinetic.reset();  // abandoned between two frames (a poll threw): built again from the next frame
    throw;
  }
}

const KineticFrameStats* Engine::kinetic_stats() const {
  return m_kinetic ? &m_kinetic->last_stats() : nullptr;
}

}  // namespace pleat
