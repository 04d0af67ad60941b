#include "static_core/visibility.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <glm/geometric.hpp>
#include <memory>

#include "static_core/internal/frame_assembly.hpp"
#include "static_core/internal/slice_cones.hpp"
#include "static_core/internal/slice_triangulation.hpp"
#include "static_core/mesh_slicer.hpp"
#include "static_core/mesh_validation.hpp"

namespace pleat {
namespace {

struct Workspace {
  SlicerScratch slicer;
  SliceTriangulation triangulation;
  PlaneConeScratch cones;
};

void process_plane(const MeshTopology& topology, const MeshConnectivity& connectivity, const Frame& frame,
                   const SlicingPlane& plane, ConeStorage storage, std::span<const Index> faces,
                   const FrameMarks& marks, Workspace& ws, PlaneCones& out) {
  const PlaneFaces split = split_faces(topology, faces);
  slice_mesh(topology, connectivity, frame, plane, split.cloth, ws.slicer, out.slice, marks.flat_edges);
  out.crossings = 0;
  out.occluders.clear();
  if (!offer_plane_cones(topology.num_receivers(), storage, frame, marks.whole_fans, ws.cones, out)) return;
  slice_mesh(topology, connectivity, frame, plane, split.occluders, ws.slicer, out.occluders,
             marks.flat_edges);
  ws.triangulation.build(out.slice);
  out.crossings = ws.triangulation.crossings();
  compute_plane_cones(ws.triangulation, ws.cones, out);
}

}  // namespace

std::vector<glm::dvec3> area_weighted_normals(const MeshTopology& topology, const Frame& frame) {
  std::vector<glm::dvec3> n(topology.num_vertices, glm::dvec3(0.0));
  for (const Triangle& t : topology.triangles) {
    const glm::dvec3& a = frame.positions[t[0]];
    const glm::dvec3 c = glm::cross(frame.positions[t[1]] - a, frame.positions[t[2]] - a);
    for (Index v : t) n[v] += c;
  }
  for (auto& v : n) {
    const double len = glm::length(v);
    v = len > 0 ? v / len : glm::dvec3(0, 0, 1);
  }
  return n;
}

std::vector<glm::dvec3> vertex_normals(const MeshTopology& topology, const Frame& frame) {
  validate_mesh(topology, frame, "vertex_normals");
  return area_weighted_normals(topology, frame);
}

/// Everything a frame's computation reuses from the previous one: topology-derived structures, per-plane
/// results, per-thread workspaces and the assembler's memory.
struct StaticVisibility::Impl {
  Impl(const MeshTopology& topology, SlicingPlan plan, const VisibilityParams& params)
      : topology(topology),
        plan(std::move(plan)),
        params(params),
        connectivity(topology),
        planes(this->plan.planes.size()),
        plane_views(planes.size()),
        assembler(topology, connectivity, this->plan, params) {}

  void compute(const Frame& frame, FrameVisibility& result);

  const MeshTopology& topology;
  SlicingPlan plan;
  VisibilityParams params;
  MeshConnectivity connectivity;  // built once: a sequence keeps its connectivity
  std::vector<PlaneCones> planes;
  std::vector<const PlaneCones*> plane_views;  // the assembler's view of `planes`
  std::vector<std::vector<Index>> faces;       // candidate faces per plane
  FrameMarks marks;                            // this frame's (mark_frame)
  tbb::enumerable_thread_specific<Workspace> workspaces;
  FrameAssembler assembler;
  FrameVisibility result;
};

void StaticVisibility::Impl::compute(const Frame& frame, FrameVisibility& result) {
  candidate_faces_per_plane(topology, frame, plan, faces);
  mark_frame(topology, connectivity, frame, marks);
  // Every plane on its own: slice, triangulate, shortest-path trees, 2D cones.
  auto run = [&](std::size_t p) {
    process_plane(topology, connectivity, frame, plan.planes[p], plan.storage, faces[p], marks,
                  workspaces.local(), planes[p]);
  };
  if (params.parallel)
    tbb::parallel_for(std::size_t(0), planes.size(), run);
  else
    for (std::size_t p = 0; p < planes.size(); ++p) run(p);
  for (std::size_t p = 0; p < planes.size(); ++p) plane_views[p] = &planes[p];
  assembler.assemble(frame, marks, plane_views, result);
}

StaticVisibility::StaticVisibility(const MeshTopology& topology, SlicingPlan plan,
                                   const VisibilityParams& params) {
  validate_topology(topology, "StaticVisibility");
  m_impl = std::make_unique<Impl>(topology, std::move(plan), params);
}
StaticVisibility::~StaticVisibility() = default;
StaticVisibility::StaticVisibility(StaticVisibility&&) noexcept = default;
StaticVisibility& StaticVisibility::operator=(StaticVisibility&&) noexcept = default;

const FrameVisibility& StaticVisibility::compute(const Frame& frame) {
  validate_frame(m_impl->topology, frame, "StaticVisibility::compute");
  m_impl->compute(frame, m_impl->result);
  return m_impl->result;
}

const SlicingPlan& StaticVisibility::plan() const { return m_impl->plan; }

FrameVisibility compute_visibility(const MeshTopology& topology, const Frame& frame, const SlicingPlan& plan,
                                   const VisibilityParams& params) {
  FrameVisibility result;
  compute_visibility(topology, frame, plan, params, result);
  return result;
}

void compute_visibility(const MeshTopology& topology, const Frame& frame, const SlicingPlan& plan,
                        const VisibilityParams& params, FrameVisibility& result) {
  validate_mesh(topology, frame, "compute_visibility");
  StaticVisibility::Impl(topology, plan, params).compute(frame, result);
}

}  // namespace pleat
