// From per-plane 2D cones to a frame's 3D cones: the part of Stewart's algorithm after the slices
// (Stewart 1999 §2.4; docs/method.md §7–§8), shared by the static engine and the kinetic one.
//
// Each plane's slice vertices hand their 2D cones to mesh vertices by the plan's ConeStorage rule (the
// paper's: to the nearer endpoint of their edge, nearest per plane; on the fan: to both endpoints, nearest
// per orientation, or the nearest below and above the vertex blended at its height). A vertex with no cone in
// an orientation borrows those of its nearest vertex along mesh edges that has one (multi-source Dijkstra per
// orientation and side). Then every vertex's 2D cones are merged into 3D cones per side and measured. Both
// engines hand this stage PlaneCones that are equal, so they produce the same output. Internal header:
// static_core and kinetic only.
// Thread safety: a FrameAssembler assembles one frame at a time (TBB-parallel over vertices inside).
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "static_core/internal/occluder_shadows.hpp"
#include "static_core/internal/slice_cones.hpp"
#include "static_core/internal/slice_triangulation.hpp"
#include "static_core/mesh.hpp"
#include "static_core/mesh_slicer.hpp"
#include "static_core/slicing_plan.hpp"
#include "static_core/visibility_cone.hpp"
#include "static_core/visibility_params.hpp"

namespace pleat {

/// vertex_normals without its validation: for the engines, which validated the topology and the frame
/// where they entered.
std::vector<glm::dvec3> area_weighted_normals(const MeshTopology& topology, const Frame& frame);

/// What a frame marks on the mesh, once per frame (mark_frame): the vertex normals (area_weighted_normals,
/// which the whole fans and the 3D assembly both use), the flat occluder edges slice_mesh runs through
/// (flat_occluder_edges), and the vertices whose cones in a plane come from every cut of their fan: sharp
/// fans and open ones (mark_whole_fans in fan_cone.hpp).
struct FrameMarks {
  std::vector<glm::dvec3> normals;       ///< per mesh vertex
  std::vector<std::uint8_t> flat_edges;  ///< per mesh edge
  std::vector<std::uint8_t> whole_fans;  ///< per mesh vertex
};
void mark_frame(const MeshTopology& topology, const MeshConnectivity& connectivity, const Frame& frame,
                FrameMarks& marks);

/// A 2D cone handed to a mesh vertex: which side, which slice vertex of the plane, its 3D distance, and
/// whether the vertex lies on or above the plane (it is the `above` end of the slice vertex's edge).
struct StoredCone {
  Index vertex = 0;
  int side = 0;
  Index slice_vertex = 0;
  double distance = 0.0;
  bool vertex_above = false;
  /// Under AimedOnFan, for a vertex marked in FrameMarks::whole_fans, every slice vertex on its edges,
  /// nearest first (slice_vertex the first): PlaneCones::fan_cuts[cuts_begin, cuts_begin + cuts_count), whose
  /// cones make the vertex's (fan_cone.hpp); none for the others.
  std::uint32_t cuts_begin = 0, cuts_count = 0;
};

/// Everything one plane contributes to a frame.
struct PlaneCones {
  Slice slice;                     ///< the cloth's: triangulated, its vertices' cones grown
  Slice occluders;                 ///< the occluders': shadows on those cones (occluder_shadows.hpp)
  std::vector<StoredCone> stored;  ///< the cones the plane offers its mesh vertices (store_cones)
  std::vector<Index> fan_cuts;     ///< under AimedOnFan, the stored cones' cuts (StoredCone::cuts_begin)
  std::vector<glm::dvec2> chain_angles;  ///< per slice vertex: chain_edge_angles (of those in fan_cuts only)
  SliceCones cones;  ///< of the slice vertices `stored` and `fan_cuts` name; the others' are empty
  std::size_t crossings = 0;
};

/// The cones a plane offers its mesh vertices under `storage`: per mesh vertex and side, the nearest offering
/// slice vertex of `slice` (ties: the lower index), into `stored`. Only vertices below `num_receivers` are
/// offered cones (MeshTopology::num_receivers: occluders receive none). `best` is per-thread scratch of
/// 2 * num_receivers entries, all -1 on entry and on return.
void store_cones(Index num_receivers, ConeStorage storage, const Frame& frame, const Slice& slice,
                 std::vector<StoredCone>& stored, std::vector<std::int64_t>& best);

/// One cut of a mesh vertex's edge (list_fan_cuts): its distance from the vertex along the edge.
struct FanCut {
  double distance;
  Index slice_vertex;
};

/// Reusable memory of list_fan_cuts.
struct FanCutScratch {
  std::vector<std::int64_t> slot_of;  ///< 2 * num_receivers entries, all -1 between calls
  std::vector<FanCut> entries;
  std::vector<std::uint32_t> first, cursor;
};

/// Under AimedOnFan: for every stored cone (store_cones' output) of a vertex marked in `whole_fans` (per
/// vertex; empty: none), the slice vertices on its vertex's edges, nearest along the edge first (ties:
/// the lower index, as store_cones breaks them), into `fan_cuts` and the cones' cuts_begin and cuts_count;
/// the other cones get none. O(slice vertices).
void list_fan_cuts(Index num_receivers, const Frame& frame, const Slice& slice,
                   std::span<const std::uint8_t> whole_fans, std::vector<StoredCone>& stored,
                   FanCutScratch& scratch, std::vector<Index>& fan_cuts);

/// Per-thread memory of compute_plane_cones.
struct PlaneConeScratch {
  SliceConeScratch cones;
  OccluderChains chains;
  ShadowScratch shadows;
  std::vector<std::int64_t> best;
  FanCutScratch fan_cuts;
  std::vector<char> needed;
};

/// A plane's offers once its slice (out.slice) is cut: store_cones into out.stored, under AimedOnFan the
/// marked vertices' cuts (list_fan_cuts, `whole_fans` from FrameMarks) and their chain_edge_angles, and which
/// slice vertices need a 2D cone. Returns false when the plane offers none (its slice cuts occluders only):
/// then out.cones holds every slice vertex's empty cones and the slice needs no triangulation — no cone of it
/// is ever read. Both engines call it for every plane they re-derive, before triangulating.
bool offer_plane_cones(Index num_receivers, ConeStorage storage, const Frame& frame,
                       std::span<const std::uint8_t> whole_fans, PlaneConeScratch& scratch, PlaneCones& out);

/// The 2D cones of the slice vertices offer_plane_cones found needed, once the cloth's slice is triangulated,
/// with the occluders' shadows taken out (cast_occluder_shadows) — no other cone is ever read, so no other is
/// computed (occluders block sight lines and get none). `contact_tolerance` is the scene's
/// (MeshTopology::contact_tolerance).
void compute_plane_cones(const SliceTriangulation& triangulation, double contact_tolerance,
                         PlaneConeScratch& scratch, PlaneCones& out);

/// Per-thread memory of nearest_sources.
struct NearestSourceScratch {
  std::vector<double> dist;
  std::vector<std::pair<double, Index>> heap;
};

/// The fill of one orientation: for every vertex, the vertex with a cone of its own (`own`) nearest to it
/// along mesh edges of the given lengths (ties: the lower index; paths of equal length by the sum Dijkstra
/// forms), itself when it has one, -1 when none is reachable. Multi-source Dijkstra, started only from the
/// sources next to a vertex without one. O(m log m) for the m edges of the vertices that borrow.
void nearest_sources(const MeshConnectivity& connectivity, std::span<const double> edge_length,
                     std::span<const char> own, NearestSourceScratch& scratch, std::span<std::int32_t> src);

/// What changed since the frame an assembler assembled last, per mesh vertex (the kinetic engine's
/// incremental frames; kinetic/internal/change_tracking.hpp finds them): whether some plane's offers to the
/// vertex differ from that frame's (stored cone, distance, side of the plane, apex, fan cuts: anything step 4
/// reads of an offer), and whether its position differs bit for bit.
struct AssemblyChanges {
  std::span<const char> offers_changed;
  std::span<const char> moved;
};

/// Steps after the planes: CSR of stored cones, Dijkstra fill, 3D assembly and measures. Keeps its memory
/// between frames. `topology` and `plan` must outlive it.
class FrameAssembler {
 public:
  FrameAssembler(const MeshTopology& topology, const MeshConnectivity& connectivity, const SlicingPlan& plan,
                 const VisibilityParams& params);
  ~FrameAssembler();
  /// Writes normals, cones, measures and the static counters of `result`. With `changes` (relative to the
  /// frame of the last call, which must have completed and written this same `result`, untouched since),
  /// only the vertices whose 3D cone can differ are assembled again: those whose offers changed, whose fan
  /// (the vertex or a neighbour) moved, or whose fill source in some orientation changed or is a vertex whose
  /// offers changed or that moved. The others keep their cones and measures, which are what a full assembly
  /// gives, bit for bit (it is deterministic and their inputs are equal). Steps 1–3 run whole either way.
  void assemble(const Frame& frame, const FrameMarks& marks, std::span<const PlaneCones* const> planes,
                FrameVisibility& result, const AssemblyChanges* changes = nullptr);
  /// The receiving vertices the last assemble() assembled (all of them without changes).
  std::size_t last_assembled() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> m_impl;
};

}  // namespace pleat
