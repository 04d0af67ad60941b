// compute_visibility: Stewart's algorithm for one frame, from slices to 3D visibility cones.
//
// A. J. Stewart, "Computing visibility from folded surfaces", Computers & Graphics 23 (1999).
// For every plane of the plan: slice the mesh (symbolic perturbation for vertices on the plane), build the
// convex hull and a constrained triangulation of the chains (CGAL, exact predicates), flood-fill visibility
// polygons, grow funnel shortest-path trees from each window endpoint, read 2D cones off the first path
// segments (holes subtracted), store them on mesh vertices (SlicingPlan::storage), fill vertices that got
// none, and merge each vertex's 2D cones into 3D cones per side. Cost: O(sum over slices of n log n) in
// practice. Precondition: the surface does not self-intersect (crossing chains are detected, counted and
// handled). Input is validated where it enters (static_core/mesh_validation.hpp): triangle indices in range,
// one finite position per vertex; anything else throws InputError naming the entry, the frame and the vertex
// or triangle.
// Thread safety: compute_visibility is reentrant; a StaticVisibility computes one frame at a time (itself
// TBB-parallel over slices and vertices with VisibilityParams::parallel).
#pragma once

#include <memory>

#include "static_core/mesh.hpp"
#include "static_core/slicing_plan.hpp"
#include "static_core/visibility_cone.hpp"
#include "static_core/visibility_params.hpp"

namespace pleat {

/// One frame, one shot. Validates the topology and the frame.
FrameVisibility compute_visibility(const MeshTopology& topology, const Frame& frame, const SlicingPlan& plan,
                                   const VisibilityParams& params = {});
/// The same into `result`, reusing its memory.
void compute_visibility(const MeshTopology& topology, const Frame& frame, const SlicingPlan& plan,
                        const VisibilityParams& params, FrameVisibility& result);

/// The static engine for a sequence: the topology and the plan are fixed, frames come one after another.
/// Everything that does not depend on positions (mesh edges, per-plane buffers, per-thread workspaces, the
/// result) is kept between frames, so a frame allocates almost nothing once the first one is done. Each
/// compute() is a full recompute of that frame — the reference the kinetic engine must reproduce.
/// `topology` must outlive the engine. The constructor validates the topology, compute() each frame.
class StaticVisibility {
 public:
  StaticVisibility(const MeshTopology& topology, SlicingPlan plan, const VisibilityParams& params = {});
  ~StaticVisibility();
  StaticVisibility(StaticVisibility&&) noexcept;
  StaticVisibility& operator=(StaticVisibility&&) noexcept;

  /// The cones of `frame`; the reference stays valid until the next call.
  const FrameVisibility& compute(const Frame& frame);
  const SlicingPlan& plan() const;

 private:
  friend void compute_visibility(const MeshTopology&, const Frame&, const SlicingPlan&,
                                 const VisibilityParams&, FrameVisibility&);
  struct Impl;
  std::unique_ptr<Impl> m_impl;
};

/// Area-weighted unit vertex normals (docs/method.md §1); isolated vertices get (0,0,1). Validates its input.
std::vector<glm::dvec3> vertex_normals(const MeshTopology& topology, const Frame& frame);

}  // namespace pleat
