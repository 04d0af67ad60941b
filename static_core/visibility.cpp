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
  compute_plane_cones(ws.triangulation, topology.contact_tolerance, ws.cones, out);
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
        frame_plan(this->plan),
        params(params),
        connectivity(topology),
        cloth(cloth_vertices(topology)),
        assembler(topology, connectivity, frame_plan, params) {}

  void compute(const Frame& frame, FrameVisibility& result);

  const MeshTopology& topology;
  SlicingPlan plan;
  SlicingPlan frame_plan;  // the plan with this frame's planes (planes_for_frame): what the assembler reads
  VisibilityParams params;
  MeshConnectivity connectivity;   // built once: a sequence keeps its connectivity
  std::vector<Index> cloth;        // the vertices the cloth's triangles use (cloth_vertices)
  std::vector<PlaneCones> planes;  // at least as many as the frame's planes: memory kept between frames
  std::vector<const PlaneCones*> plane_views;  // the assembler's view of `planes`
  std::vector<std::vector<Index>> faces;       // candidate faces per plane
  FrameMarks marks;                            // this frame's (mark_frame)
  tbb::enumerable_thread_specific<Workspace> workspaces;
  FrameAssembler assembler;
  FrameVisibility result;
};

void StaticVisibility::Impl::compute(const Frame& frame, FrameVisibility& result) {
  planes_for_frame(plan, cloth, frame, frame_plan.planes);
  const std::size_t n = frame_plan.planes.size();
  if (params.progress) params.progress->planes.store(n, std::memory_order_relaxed);
  if (planes.size() < n) planes.resize(n);
  candidate_faces_per_plane(topology, frame, frame_plan, faces);
  mark_frame(topology, connectivity, frame, marks);
  // Every plane on its own: slice, triangulate, shortest-path trees, 2D cones.
  auto run = [&](std::size_t p) {
    process_plane(topology, connectivity, frame, frame_plan.planes[p], plan.storage, faces[p], marks,
                  workspaces.local(), planes[p]);
    if (params.progress) params.progress->slices.fetch_add(1, std::memory_order_relaxed);
    if (params.poll) params.poll();
  };
  if (params.parallel)
    tbb::parallel_for(std::size_t(0), n, run);
  else
    for (std::size_t p = 0; p < n; ++p) run(p);
  plane_views.resize(n);
  for (std::size_t p = 0; p < n; ++p) plane_views[p] = &planes[p];
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
