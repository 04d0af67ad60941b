// One slicing plane kept alive across frames: its slice and constrained triangulation carried from frame to
// frame, certified at each new frame and repaired where the motion changes them; regions, windows and corners
// derived again from the triangulation each frame, the cones grown on it by static_core's code.
// Paper: Stewart 1999 §6 (named there as future work). Method: docs/method.md §11.1 (why the certificates
// suffice: the cones equal the static engine's), §11.2 (one interval, steps 1-4, and when a slice is
// rebuilt), §11.3 (the invariants), §11.4 (the policy), §11.5 (what is kept). Preconditions: the topology,
// connectivity and plane of build() are those of every later call; frames are validated by the engine
// (kinetic_visibility.hpp). Cost: an interval costs its certificates, O(faces of the slice), plus one CGAL
// edit per vertex that vanishes, appears or is taken out; a rebuild costs the static build's, O(s log s) for
// s slice vertices. Thread safety: one thread at a time per slice, with that thread's KineticScratch; slices
// are independent. Internal header (CGAL types): kinetic only.
#pragma once

#include <algorithm>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "kinetic/internal/kept_triangulation.hpp"
#include "kinetic/kinetic_policy.hpp"
#include "static_core/internal/frame_assembly.hpp"
#include "static_core/internal/slice_triangulation.hpp"

namespace pleat::kinetic {

/// An edge flip planned at the certificates (docs/method.md §11.2, step 2): flip edge `index` of `face`. It
/// reserves the two faces it replaces and, for an edge to the infinite vertex (a reflex hull corner made
/// into a triangle), the hull's faces on either side, whose corners it changes or depends on; a reserved
/// face holds the flip's number n in info().index (-2 - n for the face after, whose own corner it does not
/// change), a free one -1. A null face: cancelled.
struct PlannedFlip {
  cgal::FaceHandle face;
  int index = 0;
  cgal::FaceHandle before, after;  ///< hull faces beside an edge to the infinite vertex (else null)
};

/// Per-thread memory of KineticSlice (no allocation per frame once warmed up).
struct KineticScratch {
  SlicerScratch slicer;
  /// The next frame's slice while a slice is carried to it; then, swapped, the previous frame's buffers,
  /// reused by the next slice this thread carries (a slice keeps one Slice between frames, not two).
  Slice next;
  /// While a slice is carried: its kept triangulation, restored, and everything derived from it —
  /// slice-vertex map, corners, regions, windows — which are not kept between frames (see KineticSlice).
  SliceTriangulation triangulation;
  RestoreScratch restore;
  /// Set by the engine when invariants are checked (KineticParams::check_invariants): a slice rebuilt without
  /// keeping its triangulation has it checked before it is dropped (KineticSlice::check_invariants reports;
  /// without this it rebuilds the triangulation to check it).
  bool check_unkept = false;
  PlaneConeScratch cones;
  std::vector<std::int32_t> old_of_edge;  ///< per mesh edge: slice vertex of the previous frame, or -1
  std::vector<std::int32_t> new_of_old;
  std::vector<Index> born;                        ///< slice vertices to insert at the next frame
  std::vector<char> is_born;                      ///< per slice vertex of the next frame
  std::vector<cgal::VertexHandle> vertex_of_new;  ///< per slice vertex of the next frame
  std::vector<cgal::VertexHandle> take_out;       ///< vertices of failed certificates, still to remove
  /// Edge flips that repair failed certificates at the next frame, made once the vertices have moved there.
  std::vector<PlannedFlip> flips;
  std::vector<cgal::VertexHandle> vanishing;  ///< vertices whose slice vertex vanishes, still to remove
  std::vector<std::int32_t> recheck;          ///< neighbours of removed vertices: faces to certify
  std::vector<char> taken_out;                ///< per slice vertex of the next frame
  /// Per slice vertex of the next frame: whether its chain edges may not be constrained edges yet (it is new
  /// or put back, or a chain neighbour of a removed vertex). Every other chain edge joins two kept vertices
  /// that were its ends at frame k too, and stayed one constrained edge.
  std::vector<char> chain_loose;
  std::vector<std::int32_t>
      relabel;  ///< per vanishing slice vertex: the new one it hands its vertex to, or -1
  std::vector<Index> run_old, run_new;  ///< a fan swap's vanishing and new slice vertices, in chain order
  std::vector<Index> degree_old, degree_next;        ///< chain edges at each slice vertex
  std::vector<std::pair<Index, Index>> unconstrain;  ///< old closing edges of runs that grow (old ids)
  KineticScratch();
  ~KineticScratch();
};

/// The hull polygon of `cdt` (at its vertices' points) passes its lexicographically smallest point once. With
/// every hull corner convex or straight, that is: it winds once (the frame certificate's last part).
bool hull_winds_once(const cgal::Cdt& cdt);

class KineticSlice {
 public:
  /// The static build of `frame` (also the fallback). `storage` is the plan's rule (compute_plane_cones).
  void build(const MeshTopology& topology, const MeshConnectivity& connectivity, const Frame& frame,
             const SlicingPlane& plane, ConeStorage storage, const PlaneFaces& faces, const FrameMarks& marks,
             KineticScratch& scratch);
  /// From the current frame to `next` (docs/method.md §11.2). Returns what it did: one of
  /// slices_unchanged, slices_repaired or slices_rebuilt is 1 (and rebuilt_because the reason), and where its
  /// time went.
  KineticCounts advance(const MeshTopology& topology, const MeshConnectivity& connectivity, const Frame& next,
                        const SlicingPlane& plane, const PlaneFaces& faces, const FrameMarks& marks,
                        const KineticPolicy& policy, KineticScratch& scratch);

  /// To `next` by the static build, as the static engine does it (no attempt to carry), for the engine's
  /// whole-interval policy (KineticPolicy::measured_cost); `keep`: keep the triangulation for the next
  /// interval to carry. Counted as rebuilt for frame_cost.
  KineticCounts rebuild_outright(const MeshTopology& topology, const MeshConnectivity& connectivity,
                                 const Frame& next, const SlicingPlane& plane, const PlaneFaces& faces,
                                 const FrameMarks& marks, bool keep, KineticScratch& scratch);

  const PlaneCones& cones() const { return m_out; }
  /// The mesh edges that started or stopped crossing the plane in the last advance() (local edits only).
  const std::vector<Index>& changed_edges() const { return m_changed_edges; }
  /// The slice's triangulation with its regions, windows and corners, derived again (tests, benchmarks):
  /// a copy of the kept triangulation, or the static build of a slice that keeps none.
  void rederive_triangulation(SliceTriangulation& out) const;
  /// The triangulation is valid for the current points (exact), constraints are the slice's edges, and the
  /// regions, windows and corners are consistent. False with a reason otherwise.
  bool check_invariants(std::string* why) const;

 private:
  /// The static build of the slice in m_out; `keep`: as an editable slice, its triangulation kept when it can
  /// be (else not checked, not kept: the next interval rebuilds it).
  void finish_build(const MeshTopology& topology, const Frame& frame, const FrameMarks& marks,
                    KineticScratch& scratch, bool keep);
  void finish_frame(const MeshTopology& topology, const Frame& frame, const FrameMarks& marks,
                    KineticScratch& scratch);
  /// advance() but its timing.
  KineticCounts carry(const MeshTopology& topology, const MeshConnectivity& connectivity, const Frame& next,
                      const SlicingPlane& plane, std::span<const Index> faces, const FrameMarks& marks,
                      const KineticPolicy& policy, KineticScratch& scratch);
  /// The slice's offers to mesh vertices (offer_plane_cones); false when it offers none (it cuts occluders
  /// only): it then needs no triangulation and is not carried.
  bool offer_cones(const MeshTopology& topology, const Frame& frame, const FrameMarks& marks,
                   KineticScratch& scratch);
  /// The 2D cones of the offered slice vertices, from the triangulation in `scratch`.
  void grow_cones(double contact_tolerance, KineticScratch& scratch);
  /// Step 2 of an interval (docs/method.md §11.2): certify every face at the next frame and take out the
  /// vertices of failed certificates, up to `budget` of them. Returns why the slice must be rebuilt, or none.
  RebuildReason certify_at_next_frame(std::size_t budget, KineticScratch& scratch, KineticCounts& counts);

  PlaneCones m_out;
  /// What is kept between frames besides the slice: the constrained triangulation of an editable slice, as
  /// indices (kept_triangulation.hpp; empty for one that is rebuilt every interval). Its slice-vertex map,
  /// corners, regions and windows are derived again each frame in the thread's scratch (docs/method.md §11.5:
  /// keeping them saves no work).
  KeptTriangulation m_kept;
  ConeStorage m_storage = ConeStorage::NearestOnFan;
  std::vector<Index> m_changed_edges;
  /// 2D, no merged points, no crossings, and every chain edge one constrained edge (no chain touching another
  /// at a vertex inside its edge): the next interval can repair it.
  bool m_editable = false;
  bool m_offers = true;         ///< the last offer_cones found some offer
  double m_cone_seconds = 0.0;  ///< of the last offer_cones and grow_cones
  /// A run of outright rebuilds (KineticPolicy::retry_interval): how many are still to come, what started
  /// it (policy or cost), and how many times the next run's length will have doubled
  /// (KineticPolicy::max_retry_doublings).
  int m_rebuilds_left = 0;
  RebuildReason m_streak_reason = RebuildReason::policy;
  int m_backoff = 0;
  bool m_carried = false;  ///< the last interval carried the slice (no rebuild)
  /// Seconds per slice vertex of the slice's intervals (slicing to cones), averaged: carried (or attempted)
  /// since the last outright rebuild, and rebuilt outright (or built); -1 while unknown. The measured policy
  /// compares them.
  double m_carry_cost = -1.0, m_rebuild_cost = -1.0;
  bool m_attempted = false;  ///< the last interval tried to carry the slice
  double per_slice_vertex(double seconds) const {
    return seconds / double(std::max<std::size_t>(m_out.slice.vertices.size(), 1));
  }
  /// What the check of the interval's triangulation of a slice that keeps none found ("" = valid), when
  /// KineticScratch::check_unkept asked for it; else empty (check_invariants rebuilds and checks then).
  std::optional<std::string> m_unkept_check;
};

}  // namespace pleat::kinetic
