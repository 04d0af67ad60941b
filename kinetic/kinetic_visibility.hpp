// KineticVisibility: the cones of a cloth sequence, frame after frame, with every slicing plane's structure
// kept alive between frames (DESIGN.md §3; Stewart 1999 §6 names this as future work).
//
// Built from the topology, a slicing plan (fixed for the sequence) and the first frame (a static build).
// advance(next) moves every slice through the interval to the next frame (kinetic_slice.hpp): the mesh
// vertices that cross a plane are applied as local edits of its chains, the slice points move linearly from
// their points at one frame to their points at the next (moving_orientation.hpp explains this model), and
// certificate failures are repaired in exact time order by edge flips; where repair would cost more than a
// rebuild, or the slice degenerates, it is rebuilt. The cones are then grown on the kept structure and merged
// by the same code as the static engine (static_core/frame_assembly.hpp): the output equals a full static
// recompute of the same frame (tests/kinetic_visibility_test.cpp proves it on random motions).
// Slices are independent and processed in parallel (TBB). `topology` must outlive the engine.
// The constructor validates the topology and the first frame, advance() each frame
// (sim_io/mesh_validation.hpp: InputError; a rejected frame leaves the engine as it was).
#pragma once

#include <array>
#include <cstddef>
#include <memory>

#include "sim_io/mesh.hpp"
#include "static_core/slicing_plan.hpp"
#include "static_core/visibility.hpp"
#include "static_core/visibility_cone.hpp"

namespace pleat {
namespace kinetic {
class KineticSlice;

/// Why a slice was built from scratch in an interval.
enum class RebuildReason : int { none = 0, degenerate, crossing, policy, repair_failed, count };
const char* rebuild_reason_name(RebuildReason reason);

/// When repairing a slice costs more than rebuilding it. Measured by bench/run_kinetic_policy.sh
/// (bench/results/kinetic_policy.md: static vs X = 0, 0.25, 1, 100 for `--max-events-per-vertex X
/// --max-edit-fraction X` on the drape and a curtain at native and 4x rate): X = 0 is the best on the drape
/// and the curtain at native rate, and within 4% of the best at 4x. An event or edit costs more
/// (certificates, exact decisions, flips, CGAL's vertex removal and insertion) than CGAL's rebuild of a small
/// share of the slice, so the defaults repair only slices with few events and edits (the constants below) and
/// keep every slice that has none.
struct KineticPolicy {
  /// Rebuild when an interval's events exceed 16 plus this many per slice vertex; also, before processing
  /// them, when more certificates than that fail in the interval or are left undecided by the interval filter
  /// (an exact decision costs about 5 us on average, bench/results/kinetic_micro.md).
  double max_events_per_vertex = 0.0;
  /// Rebuild when the slice vertices removed plus inserted exceed 2 plus this fraction of the slice.
  double max_edit_fraction = 0.0;
};
}  // namespace kinetic

struct KineticParams {
  bool parallel = true;           ///< TBB-parallel over slices and vertices
  kinetic::KineticPolicy policy;  ///< repair or rebuild
  /// Check the kinetic invariants exactly after every event and every slice's invariants after each interval
  /// (KineticSlice::advance, check_invariants); a violation throws InvariantError. On in Debug builds.
#ifdef NDEBUG
  bool check_invariants = false;
#else
  bool check_invariants = true;
#endif
};

/// Counters of one advance(), summed over slices (reported by `pleat visibility --stats`).
struct KineticFrameStats {
  double seconds = 0.0;          ///< wall time of advance()
  std::size_t certificates = 0;  ///< triangle and hull certificates computed
  std::size_t exact_certificates =
      0;                       ///< of which the filter could not decide (exact signs, intervals or rationals)
  std::size_t flips = 0;       ///< triangle collapses repaired by an edge flip
  std::size_t hull_enter = 0;  ///< vertices that crossed a hull edge (windows change)
  std::size_t hull_leave = 0;  ///< hull vertices that went reflex (windows change)
  std::size_t touches = 0;     ///< certificates that touched zero and held
  std::size_t side_changes_regular = 0;   ///< (mesh vertex, plane) crossings of a regular vertex
  std::size_t side_changes_critical = 0;  ///< ... of an extremum, saddle or boundary vertex
  std::size_t removed = 0;                ///< slice vertices removed by local edits
  std::size_t inserted = 0;               ///< slice vertices inserted by local edits
  std::size_t slices_unchanged = 0;       ///< no event, no edit: only the cone geometry was re-evaluated
  std::size_t slices_repaired = 0;  ///< kept and repaired locally (regions, windows, corners re-derived)
  std::size_t slices_rebuilt = 0;   ///< built from scratch
  std::array<std::size_t, static_cast<std::size_t>(kinetic::RebuildReason::count)> rebuilt_because{};

  std::size_t events() const { return flips + hull_enter + hull_leave + touches; }
  /// Sums every counter (and the time): totals over frames.
  KineticFrameStats& operator+=(const KineticFrameStats& other);
};

class KineticVisibility {
 public:
  KineticVisibility(const MeshTopology& topology, SlicingPlan plan, const Frame& first,
                    const KineticParams& params = {});
  ~KineticVisibility();
  KineticVisibility(KineticVisibility&&) noexcept;
  KineticVisibility& operator=(KineticVisibility&&) noexcept;

  /// The cones of the current frame (the first one after construction).
  const FrameVisibility& current() const;
  /// Moves to `next` (same topology) and returns its cones; the reference stays valid until the next call.
  const FrameVisibility& advance(const Frame& next);
  /// What the last advance() did (zeros after construction).
  const KineticFrameStats& last_stats() const;
  const SlicingPlan& plan() const;
  /// The kept state of one plane (internal type, for tests and benchmarks).
  const kinetic::KineticSlice& slice(std::size_t plane) const;

  struct Impl;

 private:
  std::unique_ptr<Impl> m_impl;
};

}  // namespace pleat
