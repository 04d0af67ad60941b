// One slicing plane kept alive across frames (DESIGN.md §3): its slice, constrained triangulation, regions,
// windows and corners carried from frame to frame, repaired where the motion changes them.
//
// An interval (frame k -> k+1) in four steps, all exact:
//   1. Topology: the mesh vertices that cross the plane change which mesh edges cross it. The slice vertices
//      of edges that stop crossing are removed (with their chain edges) from the triangulation at t = 0.
//      For a regular vertex this is the fan swap of the paper's §6: its old fan vertices leave the chain and
//      its new ones join it at step 3; a critical vertex (extremum, saddle, boundary) starts, ends, splits or
//      merges chains by the same edits.
//   2. Motion: the surviving slice vertices move linearly from their frame-k points to their frame-k+1
//      points (moving_orientation.hpp). Certificates: every finite triangle stays positively oriented, every
//      hull vertex stays convex or flat. Each certificate's first root in (t, 1] goes into a queue ordered by
//      exact time (ties: by creation order, so deterministic); cheapest decision first: the interval filter,
//      exact Bernstein signs at t = 0, interval subdivision, rational arithmetic only where intervals cannot
//      decide (root_isolation.hpp). A collapsing triangle flips the edge opposite
//      the vertex that crosses it — across a hull edge, that vertex joins the hull; a hull vertex going
//      reflex leaves the hull by a flip with the outside. Touching zeros need no repair. A triangle
//      degenerate at t = 1 is flipped too (static_core's triangulation has no degenerate triangles).
//   3. The slice vertices of edges that start crossing are inserted with their chain edges at t = 1.
//   4. Regions, windows and corners are re-derived from the triangulation when its combinatorics changed
//      (they depend on nothing else); the funnel trees and cones are grown on it (static_core's code). Trees
//      are regrown, not kept with tautness certificates: between two frames the tree at t = 1 is a function
//      of the kept triangulation and the points at t = 1, and certifying a kept tree over the interval (a
//      tautness certificate per node and tree, a visibility one per triangle edge its tree edge crosses,
//      13-27 ns each) costs nearly as much as regrowing it (65-71 ns per node and tree), while the wedges are
//      re-evaluated either way: a few percent of a frame at best (bench/results/kinetic_micro.md).
// Checks: with check_every_event (Debug builds, tests) the kinetic invariants after every event
// (event_invariants). Guard: before step 3 every triangle is checked exactly at t = 1 (the static engine's
// predicates on the same points); a failure, chains that cross, points that coincide, a collinear slice, or
// more events or edits than the policy allows rebuild the slice from scratch with static_core, and the reason
// is counted. Because hull, regions, windows and corners of a valid constrained triangulation do not depend
// on which triangulation it is, and shortest paths are unique, the result equals the static engine's.
// Internal header (CGAL types): kinetic only.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "kinetic/kinetic_visibility.hpp"
#include "kinetic/moving_orientation.hpp"
#include "static_core/frame_assembly.hpp"
#include "static_core/slice_triangulation.hpp"

namespace pleat::kinetic {

/// What happened to one slice in one interval.
struct SliceEventCounts {
  std::size_t certificates = 0;  ///< triangle and hull certificates computed
  std::size_t exact_certificates =
      0;                       ///< of which the filter could not decide (exact signs, intervals or rationals)
  std::size_t flips = 0;       ///< a triangle collapsed: its edge flipped
  std::size_t hull_enter = 0;  ///< a vertex crossed a hull edge and joined the hull
  std::size_t hull_leave = 0;  ///< a hull vertex went reflex and left the hull
  std::size_t touches = 0;     ///< a certificate touched zero and kept its sign
  std::size_t removed = 0;     ///< slice vertices removed (their mesh edge stopped crossing)
  std::size_t inserted = 0;    ///< slice vertices inserted (their mesh edge started crossing)
  bool structure_changed = false;  ///< regions, windows and corners were re-derived
  RebuildReason rebuild = RebuildReason::none;

  std::size_t events() const { return flips + hull_enter + hull_leave + touches; }
  /// Sums the counters (not `structure_changed` or `rebuild`): totals over slices.
  SliceEventCounts& operator+=(const SliceEventCounts& o) {
    certificates += o.certificates;
    exact_certificates += o.exact_certificates;
    flips += o.flips;
    hull_enter += o.hull_enter;
    hull_leave += o.hull_leave;
    touches += o.touches;
    removed += o.removed;
    inserted += o.inserted;
    return *this;
  }
};

/// A certificate's first zero: its face (and the face's certificate version then) and its certificate.
struct KineticEvent {
  RootTime time;
  cgal::FaceHandle face;
  std::uint32_t version = 0;
  bool fails = false;  ///< known to fail at `time` (CertificateFailure::fails): no exact sign test there
  std::uint64_t sequence = 0;  ///< creation order: the deterministic tie-break
  CertificatePolynomial certificate;
};

/// Per-thread memory of KineticSlice (no allocation per frame once warmed up, outside exact fallbacks).
struct KineticScratch {
  SlicerScratch slicer;
  PlaneConeScratch cones;
  std::vector<std::int32_t> old_of_edge;  ///< per mesh edge: slice vertex of the previous frame, or -1
  std::vector<std::int32_t> new_of_old;
  std::vector<Index> born;
  std::vector<char> is_born;                      ///< per slice vertex of the next frame
  std::vector<cgal::VertexHandle> vertex_of_new;  ///< per slice vertex of the next frame
  using Event = KineticEvent;
  std::vector<Event> queue;               ///< a binary heap, earliest event on top
  std::vector<cgal::FaceHandle> touched;  ///< faces to re-certify after a flip
  KineticScratch();
  ~KineticScratch();
};

/// The kinetic invariants of a slice in move (KineticSlice::advance's `check_every_event`), after the events
/// at time t: the triangulation's combinatorics are valid (CGAL's check), constraint flags agree on both
/// sides of every edge and number `constraints`, and every certificate is scheduled where it fails. Each face
/// has at most one live event (its version current): at t when its certificate is zero at t (an event of this
/// instant not yet processed) or negative just after t (a repair still to come), else at its first zero after
/// t, else none; at t = 1 a triangle must be positive or have its event now. A finite face certifies its
/// orientation, an infinite face (oo, a, b) the hull corner at b; a CDT vertex moves from its point to
/// next[its slice_vertex].point. Exact (interval filter, then exact polynomials). Empty when they hold, else
/// the first violation.
std::string event_invariants(const cgal::Cdt& cdt, std::span<const SliceVertex> next,
                             const std::vector<KineticEvent>& queue, const RootTime& t,
                             std::size_t constraints);

class KineticSlice {
 public:
  /// The static build of `frame` (also the fallback). `storage` is the plan's rule (compute_plane_cones).
  void build(const MeshTopology& topology, const MeshEdges& edges, const Frame& frame,
             const SlicingPlane& plane, ConeStorage storage, std::span<const Index> faces,
             KineticScratch& scratch);
  /// From the current frame to `next` (see the header comment). With `check_every_event`, the kinetic
  /// invariants are checked exactly after every event (the triangulation's combinatorics, the constraints,
  /// and every certificate scheduled at its first failure); a violation throws InvariantError (a bug).
  SliceEventCounts advance(const MeshTopology& topology, const MeshEdges& edges, const Frame& next,
                           const SlicingPlane& plane, std::span<const Index> faces,
                           const KineticPolicy& policy, KineticScratch& scratch,
                           bool check_every_event = false);

  const PlaneCones& cones() const { return m_out; }
  /// The mesh edges that started or stopped crossing the plane in the last advance() (local edits only).
  const std::vector<Index>& changed_edges() const { return m_changed_edges; }
  const SliceTriangulation& triangulation() const { return m_tri; }
  /// The triangulation is valid for the current points (exact), constraints are the slice's edges, and the
  /// regions, windows and corners are consistent. False with a reason otherwise.
  bool check_invariants(std::string* why) const;

 private:
  void finish_build(const MeshTopology& topology, const Frame& frame, KineticScratch& scratch);
  void finish_frame(const MeshTopology& topology, const Frame& frame, bool structure_changed,
                    KineticScratch& scratch);
  void grow_cones(const MeshTopology& topology, const Frame& frame, KineticScratch& scratch);
  /// Every chain edge between distinct points is a single constrained edge of the triangulation.
  bool chains_are_edges() const;
  RebuildReason move_survivors(const KineticPolicy& policy, std::optional<std::size_t> check_constraints,
                               KineticScratch& scratch, SliceEventCounts& counts);

  PlaneCones m_out;
  Slice m_next;
  SliceTriangulation m_tri;
  ConeStorage m_storage = ConeStorage::NearestOnFan;
  std::vector<Index> m_changed_edges;
  /// 2D, no merged points, no crossings, and every chain edge one constrained edge (no chain touching another
  /// at a vertex inside its edge): the next interval can repair it.
  bool m_editable = false;
};

}  // namespace pleat::kinetic
