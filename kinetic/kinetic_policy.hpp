// The kinetic engine's policy (when a slice is repaired, when it is rebuilt, and why) and its counters (what
// an interval did, per slice, frame and run): shared by the engine (kinetic_visibility.hpp), its slices
// (internal/kinetic_slice.hpp), the command line's statistics and the benchmarks.
// Method: docs/method.md §11.2 (the rebuild reasons), §11.4 (the policy).
// Thread safety: plain values.
#pragma once

#include <array>
#include <cstddef>

namespace pleat {
namespace kinetic {

/// Why a slice was built from scratch in an interval.
/// frame_cost: the engine rebuilt every slice of the interval (KineticPolicy::measured_cost). no_cones: the
/// slice offered no cone at the last frame (it cut occluders only), so it was never triangulated: sliced
/// afresh.
enum class RebuildReason : int {
  none = 0,
  degenerate,
  crossing,
  policy,
  repair_failed,
  cost,
  frame_cost,
  no_cones,
  count
};
const char* rebuild_reason_name(RebuildReason reason);

/// When repairing a slice costs more than rebuilding it. A slice is repaired by local edits (its crossing
/// mesh edges' slice vertices removed and inserted) and by taking out and putting back the slice vertices of
/// the certificates that fail at the frame; each costs about one CGAL insertion, so past a share of the
/// slice CGAL's rebuild (spatially sorted insertion of every point) is cheaper. Measured by
/// bench/run_kinetic_policy.sh (bench/results/kinetic_policy.md).
struct KineticPolicy {
  /// Rebuild when the slice vertices removed, inserted and put back exceed 2 plus this fraction of the slice.
  double max_edit_fraction = 0.5;
  /// A slice rebuilt by the rule above is rebuilt outright, without an attempt at repair, until this many
  /// intervals have passed since the first such rebuild, then tried again: motion too fast to repair in one
  /// interval usually is in the next ones too, and a failed attempt costs its certificates and put-backs on
  /// top of the rebuild (measured: bench/results/kinetic_policy.md). 1 (with
  /// max_retry_doublings 0): try every interval.
  int retry_interval = 8;
  /// Rebuild a slice, then for the retry interval, when carrying it has cost more per slice vertex than
  /// rebuilding it: each slice measures both (wall time of its intervals, averaged) and takes the cheaper.
  /// The output is the same either way; which slices are rebuilt, and the counters, depend on the timings.
  /// The engine, above the slices, measures whole intervals too: the wall time per slice vertex of the
  /// planes' loop of intervals it carries against that of intervals that rebuild outright every slice the
  /// motion reaches (the static engine's work on them), and rebuilds every reached slice for a run of
  /// intervals (8, 16, 32, 64: doubling after each carrying probe that still loses) while carrying costs
  /// more than 0.95 of that; while carrying, every 16th interval rebuilds every reached slice to keep that
  /// estimate fresh (counted as rebuilt for frame_cost). Slices the motion does not reach are kept either
  /// way. False: neither measures (edits alone).
  bool measured_cost = true;
  /// A slice whose attempt after a run of outright rebuilds fails again (rebuilt for its edits or its cost)
  /// starts a run twice as long as the last, up to this many doublings (8, 16, 32 intervals by default); an
  /// interval that carries it, and finds carrying no dearer than rebuilding, ends the backoff. A slice that
  /// never pays to carry (the layered plies, motion at half the frame rate) is then tried every 32 intervals
  /// instead of every 8. 0: every run is retry_interval long.
  int max_retry_doublings = 2;
};
}  // namespace kinetic

/// What the kinetic engine did, per slice and interval (KineticSlice::advance), summed over slices for a
/// frame and over frames for a run. Every counter is listed once in kKineticCounters (name and meaning),
/// which the CLI's statistics and the benchmarks' reports iterate.
struct KineticCounts {
  std::size_t certificates = 0;  ///< triangle and hull-corner certificates checked at the frame
  std::size_t certificates_failed =
      0;                       ///< of which failed: a triangle flat or inverted, a hull corner reflex
  std::size_t reinserted = 0;  ///< slice vertices taken out and put back to repair failed ones
  std::size_t flipped = 0;     ///< failed certificates repaired at the frame by one edge flip (a triangle's
                               ///< edge, or a reflex hull corner made into a triangle)
  std::size_t relabeled =
      0;                    ///< fan swaps: a vanishing slice vertex's triangulation vertex given to a new one
  std::size_t removed = 0;  ///< slice vertices removed by local edits (their edge stopped crossing)
  std::size_t inserted = 0;  ///< slice vertices inserted by local edits (their edge started crossing)
  std::size_t side_changes_regular = 0;   ///< (mesh vertex, plane) crossings of a regular vertex
  std::size_t side_changes_critical = 0;  ///< ... of an extremum, saddle, boundary or non-manifold vertex
  std::size_t slices_unchanged = 0;       ///< no CGAL edit (at most fan swaps of equal length), no failed
                                     ///< certificate: the triangulation kept as it was, the cones regrown
  std::size_t slices_repaired = 0;  ///< kept and edited locally
  std::size_t slices_kept = 0;  ///< not reached by the motion (no moved vertex on an edge crossing it, before
                                ///< or after): slice, triangulation and cones kept, nothing regrown
  std::size_t slices_rebuilt = 0;  ///< built from scratch
  std::array<std::size_t, static_cast<std::size_t>(kinetic::RebuildReason::count)> rebuilt_because{};
  /// Where the time went (seconds, summed over slices, so CPU time when slices run in parallel): carrying
  /// the structure to the frame (slicing, edits, certificates, put-backs, rebuilds, regions) and growing
  /// the 2D cones on it (funnel trees, wedges, storage).
  double structure_seconds = 0.0;
  double cone_seconds = 0.0;

  KineticCounts& operator+=(const KineticCounts& other);
};

/// Every counter of KineticCounts (except rebuilt_because), in report order.
struct KineticCounter {
  const char* name;
  std::size_t KineticCounts::*field;
};
inline constexpr KineticCounter kKineticCounters[] = {
    {"certificates", &KineticCounts::certificates},
    {"certificates_failed", &KineticCounts::certificates_failed},
    {"reinserted", &KineticCounts::reinserted},
    {"flipped", &KineticCounts::flipped},
    {"relabeled", &KineticCounts::relabeled},
    {"removed", &KineticCounts::removed},
    {"inserted", &KineticCounts::inserted},
    {"side_changes_regular", &KineticCounts::side_changes_regular},
    {"side_changes_critical", &KineticCounts::side_changes_critical},
    {"slices_unchanged", &KineticCounts::slices_unchanged},
    {"slices_repaired", &KineticCounts::slices_repaired},
    {"slices_rebuilt", &KineticCounts::slices_rebuilt},
    {"slices_kept", &KineticCounts::slices_kept},
};

/// One advance(): its counters summed over slices, and its wall time (reported by `pleat visibility
/// --stats`).
struct KineticFrameStats : KineticCounts {
  double seconds = 0.0;           ///< wall time of advance()
  double assembly_seconds = 0.0;  ///< of which storage, fill and 3D cones (FrameAssembler; wall time)
  /// Receiving vertices whose 3D cones were assembled again (the others' inputs did not change); summed over
  /// frames for a run.
  std::size_t vertices_assembled = 0;
  using KineticCounts::operator+=;  // a slice's counters into the frame's
  /// Sums every counter and the time: totals over frames.
  KineticFrameStats& operator+=(const KineticFrameStats& other);
};

}  // namespace pleat
