#include "kinetic/kinetic_visibility.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <cstring>

#include "kinetic/internal/change_tracking.hpp"
#include "kinetic/internal/kinetic_inspect.hpp"
#include "kinetic/internal/kinetic_slice.hpp"
#include "static_core/assert.hpp"
#include "static_core/internal/frame_assembly.hpp"
#include "static_core/mesh_validation.hpp"

namespace pleat {

using kinetic::KineticScratch;
using kinetic::KineticSlice;
using kinetic::RebuildReason;

struct KineticVisibility::Impl {
  Impl(const MeshTopology& topology, SlicingPlan plan_in, const Frame& first, const KineticParams& params)
      : topology(topology),
        plan(std::move(plan_in)),
        frame_plan(plan),
        params(params),
        connectivity(topology),
        cloth(cloth_vertices(topology)),
        assembler(topology, connectivity, frame_plan, {params.parallel, params.poll, params.progress}),
        previous(first),
        crossed_stamp(topology.num_vertices, 0) {
    planes_for_frame(plan, cloth, first, frame_plan.planes);
    slices.resize(frame_plan.planes.size());
    counts.resize(slices.size());
    changed_of_plane.resize(slices.size());
    candidate_faces_per_plane(topology, first, frame_plan, faces);
    mark_frame(topology, connectivity, first, marks);
    for_each_plane([&](std::size_t p) {
      slices[p].build(topology, connectivity, first, frame_plan.planes[p], plan.storage,
                      split_faces(topology, faces[p]), marks, local_scratch());
      check(p);
    });
    gather_and_assemble(first, false);
    stats = {};
  }

  template <class F>
  void for_each_plane(F&& f) {
    if (params.progress) params.progress->planes.store(slices.size(), std::memory_order_relaxed);
    const auto polled = [&](std::size_t p) {
      f(p);
      if (params.progress) params.progress->slices.fetch_add(1, std::memory_order_relaxed);
      if (params.poll) params.poll();
    };
    if (params.parallel)
      tbb::parallel_for(std::size_t(0), slices.size(), polled);
    else
      for (std::size_t p = 0; p < slices.size(); ++p) polled(p);
  }

  static std::string what_happened(const KineticCounts& c) {
    for (std::size_t r = 1; r < c.rebuilt_because.size(); ++r)
      if (c.rebuilt_because[r])
        return std::string("rebuilt: ") + kinetic::rebuild_reason_name(RebuildReason(r));
    return c.slices_repaired ? "repaired" : "kept";
  }

  KineticScratch& local_scratch() {
    KineticScratch& s = scratch.local();
    s.check_unkept = params.check_invariants;
    return s;
  }

  void check(std::size_t p) const {
    if (!params.check_invariants) return;
    std::string why;
    if (!slices[p].check_invariants(&why))  // thrown whatever PLEAT_CHECK_INVARIANTS says: the caller asked
      throw InvariantError("plane " + std::to_string(p) + " (" + what_happened(counts[p]) + "): " + why);
  }

  /// A mesh vertex crossing a plane is regular when its faces close around it (MeshConnectivity: not on
  /// the boundary, not at a non-manifold place) and the plane cuts its link in exactly two places (one arc
  /// above, one below); otherwise critical (extremum, saddle, boundary, non-manifold).
  bool is_regular(Index v, const SlicingPlane& plane, const Frame& frame) const {
    if (!connectivity.has_closed_fan(v)) return false;
    int cuts = 0;
    for (const Index f : connectivity.faces_around(v)) {
      const Triangle& t = topology.triangles[f];
      Index a = 0, b = 0;
      int k = 0;
      for (Index w : t)
        if (w != v) (k++ == 0 ? a : b) = w;
      cuts += on_or_above(plane, frame.positions[a]) != on_or_above(plane, frame.positions[b]);
    }
    return cuts == 2;
  }

  /// KineticPolicy::measured_cost: whether this interval carries the slices or rebuilds them all, and whether
  /// a rebuilt interval keeps the triangulations (the last one before an interval that carries).
  struct Schedule {
    static constexpr int kProbeEvery = 16;        // carrying: every 16th interval rebuilds, as a fresh sample
    static constexpr double kCarryMargin = 0.95;  // carry while it costs at most this share of a rebuild
    double carry_cost = -1.0, rebuild_cost = -1.0;  // seconds per slice vertex, averaged; -1: unknown
    int rebuilds_left = 0;                          // of a run of whole-interval rebuilds
    int doublings = 0;                              // of the next run's length (8, 16, 32, 64)
    int carried = 0;                                // intervals carried since the last whole-interval rebuild
  };

  /// The planes of `next` (planes_for_frame) in frame_plan, each kept slice moved to its plane's place:
  /// a lattice plan's planes come and go with the cloth's extent; fresh[p] marks the planes new to this
  /// frame.
  void take_planes_of(const Frame& next) {
    fresh.assign(frame_plan.planes.size(), 0);
    dropped_offers.clear();
    if (!(plan.spacing > 0)) return;  // the planes are the plan's, every frame
    planes_for_frame(plan, cloth, next, next_planes);
    std::vector<KineticSlice> kept(next_planes.size());
    fresh.assign(next_planes.size(), 1);
    auto before = [](const SlicingPlane& a, const SlicingPlane& b) {
      return a.orientation != b.orientation ? a.orientation < b.orientation : a.offset < b.offset;
    };
    std::vector<char> taken(slices.size(), 0);
    for (std::size_t i = 0, j = 0; i < next_planes.size(); ++i) {  // both ordered by orientation, offset
      while (j < frame_plan.planes.size() && before(frame_plan.planes[j], next_planes[i])) ++j;
      if (j < frame_plan.planes.size() && !before(next_planes[i], frame_plan.planes[j])) {
        taken[j] = 1;
        kept[i] = std::move(slices[j++]);
        fresh[i] = 0;
      }
    }
    for (std::size_t j = 0; j < slices.size(); ++j)  // the cloth left these planes: their offers are gone
      if (!taken[j]) kinetic::append_offered(slices[j].cones(), dropped_offers);
    slices = std::move(kept);
    counts.resize(slices.size());
    changed_of_plane.resize(slices.size());
    frame_plan.planes.swap(next_planes);
  }

  void advance(const Frame& next) {
    const auto start = std::chrono::steady_clock::now();
    kinetic::find_moved_vertices(previous, next, moved, moved_list);
    if (moved_list.empty()) {  // a held frame, bit for bit: every slice and cone holds as it is
      stats = {};
      stats.slices_kept = slices.size();
      previous.time = next.time;
      stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      return;
    }
    take_planes_of(next);
    whole_fans_before.swap(marks.whole_fans);
    mark_frame(topology, connectivity, next, marks);
    find_reached_planes(next);
    candidate_faces_per_plane(topology, next, frame_plan, faces, reached);
    const bool engine_cost = params.policy.measured_cost;
    const bool rebuild_all =
        engine_cost && (schedule.rebuilds_left > 0 || schedule.carried >= Schedule::kProbeEvery ||
                        (schedule.rebuild_cost < 0 && schedule.carried > 0));
    // A run's last rebuild keeps the triangulations: the next interval carries them.
    const bool keep = !rebuild_all || schedule.rebuilds_left <= 1;
    // The policy compares the planes' loop alone: what comes before it (candidate faces, marks, what the
    // motion reaches) is the same work either way, and with few slices reached it would swamp them.
    const auto planes_start = std::chrono::steady_clock::now();
    for_each_plane([&](std::size_t p) { advance_plane(p, next, rebuild_all, keep); });
    if (engine_cost) update_schedule(rebuild_all, std::chrono::steady_clock::now() - planes_start);
    const auto assembly_start = std::chrono::steady_clock::now();
    if (!everything) gather_changes();
    gather_and_assemble(next, !everything);
    const double assembly_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - assembly_start).count();
    stats = {};
    stats.assembly_seconds = assembly_seconds;
    stats.vertices_assembled = assembler.last_assembled();
    for (std::size_t p = 0; p < slices.size(); ++p) stats += counts[p];
    count_side_changes(next);
    previous = next;
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  /// reached[p]: plane p's slice is reached by this interval's motion (kinetic/internal/change_tracking.hpp):
  /// some edge at a moved vertex, or at a vertex whose whole-fan mark changed, crosses it before or after; a
  /// plane new to the frame is reached.
  void find_reached_planes(const Frame& next) {
    // Nearly everything moved (a cloth in motion, at any frame rate): every slice counts as reached and every
    // vertex as changed, without the bounds and the offer comparisons, which would find little to keep.
    everything = moved_list.size() >= kEverything * double(topology.num_vertices);
    if (everything) {
      reached.assign(slices.size(), 1);
      return;
    }
    touched.assign(moved_list.begin(), moved_list.end());
    kinetic::append_whole_fan_changes(whole_fans_before, marks.whole_fans, touched);
    kinetic::planes_reached(connectivity, frame_plan.planes, plan.orientations.size(), previous, next,
                            touched, reached);
    for (std::size_t p = 0; p < slices.size(); ++p) reached[p] |= fresh[p];
  }

  /// Plane p to `next`: kept as it is when the motion does not reach it; else built (new to the frame),
  /// rebuilt (the whole-interval policy) or carried, and the vertices its offers changed listed in
  /// changed_of_plane[p].
  void advance_plane(std::size_t p, const Frame& next, bool rebuild_all, bool keep) {
    changed_of_plane[p].clear();
    if (!reached[p]) {
      counts[p] = {};
      counts[p].slices_kept = 1;
      return;
    }
    ChangeScratch& change = change_scratch.local();
    if (fresh[p] || everything)
      change.before.clear();
    else
      change.before.take(slices[p].cones());
    const PlaneFaces split = split_faces(topology, faces[p]);
    const SlicingPlane& plane = frame_plan.planes[p];
    if (fresh[p]) {  // a plane the cloth reached this frame: built as the static engine builds it
      counts[p] = {};
      counts[p].slices_rebuilt = 1;
      slices[p].build(topology, connectivity, next, plane, plan.storage, split, marks, local_scratch());
    } else {
      counts[p] = rebuild_all ? slices[p].rebuild_outright(topology, connectivity, next, plane, split, marks,
                                                           keep, local_scratch())
                              : slices[p].advance(topology, connectivity, next, plane, split, marks,
                                                  params.policy, local_scratch());
    }
    check(p);
    if (!everything)
      kinetic::offers_changed(topology.num_receivers(), change.before, slices[p].cones(), change.diff,
                              changed_of_plane[p]);
  }

  /// offers_changed (per mesh vertex) from the planes' lists and the planes dropped from the frame.
  void gather_changes() {
    offers_changed.assign(topology.num_vertices, 0);
    for (const Index v : dropped_offers) offers_changed[v] = 1;
    for (const std::vector<Index>& changed : changed_of_plane)
      for (const Index v : changed) offers_changed[v] = 1;
  }

  /// The mesh vertices that crossed each carried plane (each counted once per plane), regular or critical.
  void count_side_changes(const Frame& next) {
    for (std::size_t p = 0; p < slices.size(); ++p) {
      if (counts[p].slices_rebuilt || !reached[p]) continue;
      const SlicingPlane& plane = frame_plan.planes[p];
      for (Index e : slices[p].changed_edges())
        for (Index v : connectivity.endpoints()[e]) {
          if (on_or_above(plane, previous.positions[v]) == on_or_above(plane, next.positions[v])) continue;
          if (crossed_stamp[v] == p + 1 + stamp_base) continue;
          crossed_stamp[v] = p + 1 + stamp_base;
          ++(is_regular(v, plane, next) ? stats.side_changes_regular : stats.side_changes_critical);
        }
    }
    stamp_base += slices.size();
  }

  /// After an interval: its wall time per slice vertex into the estimate of its kind, then the next
  /// interval's kind (Schedule, KineticPolicy::measured_cost).
  void update_schedule(bool rebuilt_all, std::chrono::steady_clock::duration elapsed) {
    std::size_t vertices = 0;  // of the slices the interval carried or rebuilt
    for (std::size_t p = 0; p < slices.size(); ++p)
      if (reached[p]) vertices += slices[p].cones().slice.vertices.size();
    const double sample =
        std::chrono::duration<double>(elapsed).count() / double(std::max<std::size_t>(vertices, 1));
    auto average = [&](double& cost) { cost = cost < 0 ? sample : 0.5 * (cost + sample); };
    Schedule& s = schedule;
    if (rebuilt_all) {
      average(s.rebuild_cost);
      s.carried = 0;
      if (s.rebuilds_left > 0 && --s.rebuilds_left == 0) s.carry_cost = -1.0;  // the next carry is the probe
      return;
    }
    average(s.carry_cost);
    ++s.carried;
    if (s.rebuild_cost < 0) return;
    // Carrying must pay by a margin to be kept: where it costs about what a rebuild does, the probes and the
    // per-slice attempts that fail make it lose, and rebuilding is the static engine's work exactly.
    if (s.carry_cost >
        Schedule::kCarryMargin * s.rebuild_cost) {  // a run of rebuilds, longer after each lost probe
      s.rebuilds_left = 8 << s.doublings;
      s.doublings = std::min(s.doublings + 1, 3);
    } else {
      s.doublings = 0;
    }
  }

  /// The frame's 3D cones; `incremental`: only the vertices whose inputs changed since the last frame
  /// (offers_changed, moved; FrameAssembler::assemble) are assembled again.
  void gather_and_assemble(const Frame& frame, bool incremental) {
    plane_views.resize(slices.size());
    for (std::size_t p = 0; p < slices.size(); ++p) plane_views[p] = &slices[p].cones();
    const AssemblyChanges changes{offers_changed, moved};
    assembler.assemble(frame, marks, plane_views, result, incremental ? &changes : nullptr);
  }

  const MeshTopology& topology;
  SlicingPlan plan;
  SlicingPlan frame_plan;  // the plan with the current frame's planes (planes_for_frame); the assembler's
  std::vector<SlicingPlane> next_planes;
  std::vector<char> fresh;  // per plane of the frame: not cut at the previous frame, built afresh
  KineticParams params;
  MeshConnectivity connectivity;     // built once for the sequence
  std::vector<Index> cloth;          // the vertices the cloth's triangles use (cloth_vertices)
  std::vector<KineticSlice> slices;  // one per plane of frame_plan
  std::vector<KineticCounts> counts;
  std::vector<std::vector<Index>> faces;
  FrameMarks marks;  // the frame's (mark_frame)
  tbb::enumerable_thread_specific<KineticScratch> scratch;
  FrameAssembler assembler;
  std::vector<const PlaneCones*> plane_views;
  Frame previous;
  std::vector<std::size_t> crossed_stamp;
  std::size_t stamp_base = 0;
  Schedule schedule;
  // What the interval changed (kinetic/internal/change_tracking.hpp).
  struct ChangeScratch {
    kinetic::OfferSnapshot before;  // a reached plane's offers before the interval
    kinetic::OfferDiffScratch diff;
  };
  tbb::enumerable_thread_specific<ChangeScratch> change_scratch;
  std::vector<char> moved;                           // per mesh vertex: its position changed, bit for bit
  std::vector<Index> moved_list, touched;            // the moved vertices; and those whose whole fan changed
  std::vector<std::uint8_t> whole_fans_before;       // the previous frame's FrameMarks::whole_fans
  std::vector<char> reached;                         // per plane: the motion reaches its slice
  std::vector<std::vector<Index>> changed_of_plane;  // per plane: vertices whose offers from it changed
  std::vector<Index> dropped_offers;                 // vertices offered cones by planes the cloth left
  std::vector<char> offers_changed;                  // per mesh vertex: some plane offers it something new
  /// The share of moved vertices from which a frame counts as moving everywhere (find_reached_planes).
  static constexpr double kEverything = 0.9;
  bool everything = false;  // this frame moved at least that share
  FrameVisibility result;
  KineticFrameStats stats;
};

KineticCounts& KineticCounts::operator+=(const KineticCounts& o) {
  for (const KineticCounter& c : kKineticCounters) this->*c.field += o.*c.field;
  for (std::size_t r = 0; r < rebuilt_because.size(); ++r) rebuilt_because[r] += o.rebuilt_because[r];
  structure_seconds += o.structure_seconds;
  cone_seconds += o.cone_seconds;
  return *this;
}

KineticFrameStats& KineticFrameStats::operator+=(const KineticFrameStats& o) {
  KineticCounts::operator+=(o);
  seconds += o.seconds;
  assembly_seconds += o.assembly_seconds;
  vertices_assembled += o.vertices_assembled;
  return *this;
}

KineticVisibility::KineticVisibility(const MeshTopology& topology, SlicingPlan plan, const Frame& first,
                                     const KineticParams& params) {
  validate_mesh(topology, first, "KineticVisibility");
  m_impl = std::make_unique<Impl>(topology, std::move(plan), first, params);
}
KineticVisibility::~KineticVisibility() = default;
KineticVisibility::KineticVisibility(KineticVisibility&&) noexcept = default;
KineticVisibility& KineticVisibility::operator=(KineticVisibility&&) noexcept = default;

const FrameVisibility& KineticVisibility::current() const { return m_impl->result; }
const FrameVisibility& KineticVisibility::advance(const Frame& next) {
  validate_frame(m_impl->topology, next, "KineticVisibility::advance");
  m_impl->advance(next);
  return m_impl->result;
}
const KineticFrameStats& KineticVisibility::last_stats() const { return m_impl->stats; }
const SlicingPlan& KineticVisibility::plan() const { return m_impl->plan; }
const KineticSlice& kinetic::KineticInspect::slice(const KineticVisibility& visibility, std::size_t plane) {
  return visibility.m_impl->slices.at(plane);
}

}  // namespace pleat
