// Sets of directions in a plane, as disjoint counter-clockwise wedges (2D visibility cones are such sets).
//
// A Wedge is the range of angles [start, start + width] (radians, width in (0, 2pi]); an AngularSet keeps
// its wedges disjoint and sorted by start in [0, 2pi). Wedges whose ends meet within kAngleTolerance are
// merged: the ends are directions towards the same slice point computed twice, so they differ by rounding
// only (this merges representations; it decides nothing about the slice's topology).
// Cost: O(k log k) for k wedges.
// Thread safety: plain values; an AngularSet is used by one thread at a time.
#pragma once

#include <cmath>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <span>
#include <utility>
#include <vector>

namespace pleat {

inline constexpr double kTwoPi = 6.283185307179586476925286766559;
inline constexpr double kAngleTolerance = 1e-12;

/// A wedge of a 2D cone. Each end may carry its *reach*: the distance from the apex to the slice point that
/// bounds the wedge there (the tangent point of a shortest path, docs/method.md §7), or +infinity when no
/// point bounds it (a full turn, a half-plane of a flat slice, the side's horizon). A reach turns the end
/// into a point of the horizon that other viewpoints can aim at (aim_wedges); the set operations carry it
/// along.
struct Wedge {
  double start = 0.0;  ///< in [0, 2pi)
  double width = 0.0;  ///< in (0, 2pi]
  float start_reach = INFINITY;
  float end_reach = INFINITY;
  double end() const { return start + width; }
};

/// A linear interval [lo, hi] of angles and the reaches of its ends: what the set operations work on.
struct AngularInterval {
  double lo = 0.0, hi = 0.0;
  float lo_reach = INFINITY, hi_reach = INFINITY;
};

/// Angle of a direction in [0, 2pi).
double direction_angle(const glm::dvec2& d);
/// An angle reduced to [0, 2pi).
double wrap_angle(double a);
/// A monotone stand-in for atan2(y, x) in (-2, 2] (the "diamond angle"): the same order of directions, no
/// trigonometry. (0, 0) gives 0 only by convention.
inline double pseudo_angle(double x, double y) {
  const double sum = std::abs(x) + std::abs(y);
  const double r = sum > 0 ? y / sum : 0.0;  // in [-1, 1]
  if (x >= 0) return r;                      // (-pi/2, pi/2) -> (-1, 1)
  return y >= 0 ? 2 - r : -2 - r;            // the left half-plane -> (1, 2] and (-2, -1)
}
/// The counter-clockwise wedge from direction `from` to direction `to`, of width in (0, 2pi): for ranges
/// that may exceed a half-turn (exterior angles of the hull). The directions must not coincide.
Wedge wedge_between(const glm::dvec2& from, const glm::dvec2& to);
/// The same for a pair whose exact orientation is known to be a left turn (the wedge is below a
/// half-turn): the width is computed from the cross and dot products, so a wedge far thinner than the
/// angle's rounding stays thin and never wraps around to a full turn.
Wedge thin_wedge_between(const glm::dvec2& from, const glm::dvec2& to);

/// Appends the union of `wedges` to `out` (disjoint, sorted by start), using `scratch` for the intervals:
/// no allocation once the buffers have grown. The one implementation of the union (AngularSet uses it). Each
/// end of the union keeps the reach of the wedge end it comes from.
void unite_wedges(std::span<const Wedge> wedges, std::vector<AngularInterval>& scratch,
                  std::vector<Wedge>& out);

/// Splits wedges into linear intervals of [0, 2pi] (a wedge past 2pi in two, its cut ends without reach),
/// sorted by start; a full turn gives [0, 2pi] alone. The set operations work on these.
void split_into_intervals(std::span<const Wedge> wedges, std::vector<AngularInterval>& out);
/// Appends a ∩ b (sorted, disjoint intervals) to `out`, sorted; each end keeps the reach of the interval that
/// bounds it, or, where both bound it to within kAngleTolerance, the horizon's reach of either (the lesser).
/// The one implementation of the intersection's sweep (intersect_wedges uses it).
void intersect_intervals(std::span<const AngularInterval> a, std::span<const AngularInterval> b,
                         std::vector<AngularInterval>& out);
/// Merges sorted intervals in place (touching within kAngleTolerance), then appends them to `out` as wedges,
/// joining the interval that ends at 2pi with the one that starts at 0.
void merge_into_wedges(std::vector<AngularInterval>& intervals, std::vector<Wedge>& out);

/// Reusable buffers of intersect_wedges, blend_wedges and aim_wedges.
struct WedgeScratch {
  std::vector<AngularInterval> intervals, x, y, z;
  std::vector<Wedge> a, b, pad, trial;
};

/// Appends the intersection of the unions of `a` and `b` to `out` (disjoint, sorted by start), without
/// allocating once the buffers have grown. The one implementation of the intersection (AngularSet uses it).
void intersect_wedges(std::span<const Wedge> a, std::span<const Wedge> b, WedgeScratch& scratch,
                      std::vector<Wedge>& out);

/// Appends the rest of the turn outside `wedges` (is_united) to `out`: the gaps between them, sorted by
/// start, their ends without reach. The one implementation of the complement (AngularSet uses it).
void complement_wedges(std::span<const Wedge> wedges, std::vector<Wedge>& out);

/// True when `wedges` are in the form unite_wedges gives: sorted by start in [0, 2pi), positive widths, and
/// apart by more than kAngleTolerance (the last one may wrap past 2pi).
bool is_united(std::span<const Wedge> wedges);

/// Appends the part of `wedges` (is_united) in the half-turn [h, h + pi], h in [0, 2pi), to `out`: each wedge
/// meets it in at most two pieces (pieces up to kAngleTolerance wide are dropped), so no sort and no union.
/// The same set as intersect_wedges with the half-turn, in O(k).
void clip_to_half_turn(std::span<const Wedge> wedges, double h, std::vector<Wedge>& out);

/// The largest change of a wedge end that blend_wedges interpolates: beyond it the two sets are not the same
/// wedges seen from two nearby points, and are not blended.
inline constexpr double kMaxBlendTurn = kTwoPi / 4;

/// Appends to `out` the set between the united sets `a` (at t = 0) and `b` (at t = 1): the wedges of `a` and
/// `b` matched in counter-clockwise order (the cyclic shift that moves the ends least), each end moved the
/// shorter way round from a's to b's by the fraction t in [0, 1], and the result united. Where one set has
/// one wedge more (neither empty), the other is given the wedge or the gap it lacks, grown from nothing: a
/// wedge of width 0 at the middle of the extra wedge (a gap closing between the planes), or its wedge cut
/// across the middle of the extra gap (an occluder rising between them), whichever moves the ends least.
/// Returns false, and appends nothing, when the sets cannot be matched so: numbers of wedges two or more
/// apart, one set empty and the other not, one a full turn and the other not, or an end that would turn by
/// more than kMaxBlendTurn. Two empty sets blend to the empty set. O(k^3) for k wedges where the numbers
/// differ, else O(k^2); no allocation once `scratch` has grown.
bool blend_wedges(std::span<const Wedge> a, std::span<const Wedge> b, double t, WedgeScratch& scratch,
                  std::vector<Wedge>& out);

/// The largest turn by which aim_wedges moves an end: a larger one means the horizon point lies nearer the
/// eye than the eye lies from the apex, where the first-order parallax says nothing.
inline constexpr double kMaxAimTurn = kTwoPi / 8;

/// blend_wedges for 2D cones seen from another viewpoint: `a` is the cone at apex `apex_a` (at t = 0), `b` at
/// `apex_b` (t = 1), all three points in one (u, w) frame (parallel planes share it). Each pair of matched
/// ends with finite reaches gives two horizon points, apex + reach * direction; their blend at t is where the
/// occluding silhouette crosses the eye's plane, to first order, and the end becomes the direction from `eye`
/// to it (docs/method.md §7) — unless that turns it by more than kMaxAimTurn from the blended angle. Other
/// ends are blended as blend_wedges does. A wedge whose ends cross is dropped. Returns false as blend_wedges
/// does.
/// With `tangents`, each aimed end also gives the great circle the horizon follows across the planes there:
/// the plane through the eye and the end's two horizon points (the planes `gap` apart along their normal, the
/// eye at t between them), appended as a HorizonTangent.
struct HorizonTangent {
  double angle;       ///< the aimed end's angle in [0, 2pi)
  glm::dvec3 normal;  ///< unit normal of the horizon's great circle, in (u, w, plane normal) coordinates
};
bool aim_wedges(std::span<const Wedge> a, const glm::dvec2& apex_a, std::span<const Wedge> b,
                const glm::dvec2& apex_b, double t, const glm::dvec2& eye, WedgeScratch& scratch,
                std::vector<Wedge>& out, double gap = 0.0, std::vector<HorizonTangent>* tangents = nullptr);

class AngularSet {
 public:
  AngularSet() = default;
  /// The union of arbitrary wedges.
  static AngularSet from_wedges(const std::vector<Wedge>& wedges);
  static AngularSet full();

  const std::vector<Wedge>& wedges() const { return m_wedges; }
  bool empty() const { return m_wedges.empty(); }
  double measure() const;

  AngularSet unite(const AngularSet& other) const;
  AngularSet intersect(const AngularSet& other) const;
  AngularSet subtract(const AngularSet& other) const;
  AngularSet complement() const;
  /// True when the direction at `angle` is inside (ends included).
  bool contains(double angle) const;

 private:
  // Linear intervals [a, b] within [0, 2pi], sorted and disjoint; the wedges are derived from them.
  static std::vector<std::pair<double, double>> to_intervals(std::span<const Wedge> wedges);
  static AngularSet from_intervals(std::vector<std::pair<double, double>> intervals);
  std::vector<std::pair<double, double>> intervals() const { return to_intervals(m_wedges); }

  std::vector<Wedge> m_wedges;
};

}  // namespace pleat
