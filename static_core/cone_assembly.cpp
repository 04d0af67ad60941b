#include "static_core/cone_assembly.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>
#include <memory>
#include <numeric>
#include <span>

#include "static_core/cone_rules.hpp"
#include "static_core/union_find.hpp"

namespace pleat {
namespace {

constexpr double kHalfPi = kTwoPi / 4;
constexpr double kContainTolerance = 1e-9;
/// Wedges of different slices are samples of one visible region when their arcs come this close on the
/// sphere (radians). Measured against 2048-ray casting (drape frame 60 and the four generated kinds):
/// 0.05 -> 0.25 -> 0.5 moves the drape's mean |dA| 0.041 -> 0.040 -> 0.039 and leaves the others within
/// noise; arcs of separate openings are usually much farther apart.
constexpr double kLinkTolerance = 0.25;
/// Half-width (radians) of the band given to a wedge that no other wedge of the vertex joins: half the
/// angle between neighbouring orientations of the paper's six (45 degrees), i.e. the part of the sphere this
/// sample stands for. Measured (4096 rays): drape frame 60 mean |dA| 0.0399 -> 0.0388, sleeve 0.0393 ->
/// 0.0363, the other generated kinds unchanged; none worse.
constexpr double kLoneWedgeHalfWidth = kTwoPi / 16;

/// cos and sin of kLinkTolerance and tan of kLoneWedgeHalfWidth: the distance tests compare cosines and
/// sines, so no inverse trigonometric function runs per test.
const double kCosLink = std::cos(kLinkTolerance);
const double kTanLoneWedge = std::tan(kLoneWedgeHalfWidth);

/// A clipped 2D wedge lifted into space: its ends as unit directions in the plane's (u, w) frame and in 3D,
/// and five sample directions along its arc. No trigonometry but the one sincos of each end.
struct SpatialWedge {
  SpatialWedge(const SlicingPlane* plane, const Wedge& w)
      : plane(plane), start(w.start), width(w.width), reflex(w.width > 2 * kHalfPi) {
    start2 = {std::cos(w.start), std::sin(w.start)};
    end2 = {std::cos(w.end()), std::sin(w.end())};
    if (reflex) {  // only unclipped wedges (the side's normal along the plane's): sample by angle
      for (int i = 0; i < 5; ++i) {
        const double a = w.start + 0.25 * i * w.width;
        sample[i] = lift({std::cos(a), std::sin(a)});
      }
      return;
    }
    sample[0] = lift(start2);
    sample[4] = lift(end2);
    // Up to a half-turn: the middle is along the integral of the direction over the arc, n x (start - end)
    // (length 2 sin(width / 2) > 0); the quarters bisect the half-arcs.
    sample[2] = glm::normalize(glm::cross(plane->normal, sample[0] - sample[4]));
    sample[1] = glm::normalize(sample[0] + sample[2]);
    sample[3] = glm::normalize(sample[2] + sample[4]);
  }
  const SlicingPlane* plane;
  double start, width;  ///< the clipped wedge's, in the plane's (u, w) frame
  bool reflex;          ///< wider than a half-turn (only unclipped wedges are)
  /// The normal of the horizon's great circle at each end, where known (zero: not known), and whether it is
  /// exactly the boundary there (the side's horizon or an occluding plane), not a tangent of a curved one.
  glm::dvec3 start_silhouette{0.0}, end_silhouette{0.0};
  bool start_on_plane = false, end_on_plane = false;
  glm::dvec2 start2, end2;           ///< the ends in the plane's (u, w) frame
  std::array<glm::dvec3, 5> sample;  ///< start, quarter, middle, three quarters, end
  const glm::dvec3& start_direction() const { return sample[0]; }
  const glm::dvec3& end_direction() const { return sample[4]; }
  const glm::dvec3& middle() const { return sample[2]; }
  glm::dvec3 lift(const glm::dvec2& d) const { return d.x * plane->u + d.y * plane->w; }
  /// Whether direction d (any length) projects into the arc, ends included within kContainTolerance (as a
  /// sine). A direction along the plane's normal projects onto the apex: not contained. (Squared lengths:
  /// no square root.)
  bool contains(const glm::dvec3& d) const {
    const glm::dvec2 p(glm::dot(d, plane->u), glm::dot(d, plane->w));
    const double len2 = p.x * p.x + p.y * p.y;
    if (!(len2 > 1e-24 * glm::dot(d, d))) return false;
    const double tolerance2 = kContainTolerance * kContainTolerance * len2;
    // Whether a signed sine times len is at least -kContainTolerance * len.
    auto within = [&](double sine) { return sine >= 0 || sine * sine <= tolerance2; };
    const double from_start = start2.x * p.y - start2.y * p.x;  // > 0: p counter-clockwise of the start
    const double to_end = p.x * end2.y - p.y * end2.x;          // > 0: p clockwise of the end
    if (!reflex) return within(from_start) && within(to_end);
    return within(from_start) || within(to_end);  // outside only strictly within the gap
  }
};

/// Whether a unit direction lies within kLinkTolerance of one of a wedge's ends.
bool near_ends(const glm::dvec3& d, const SpatialWedge& w) {
  return glm::dot(d, w.start_direction()) > kCosLink || glm::dot(d, w.end_direction()) > kCosLink;
}

/// How far from a plane's great circle a sample point of another arc may lie and still link to it over that
/// circle (same_region), in units of the circles' spacing pi / n for a vertex cut by n orientations: a point
/// farther than that is nearer another orientation's circle, which would have seen the region. Unlimited,
/// separate openings were joined the more often the more orientations there were (the value was chosen by
/// measurement: docs/benchmarks_archive.md, "Linking arcs only near their circle").
constexpr double kLinkHeightInSpacings = 1.5;
/// Farther, up to this many spacings, a point links only where those other circles did see the region: every
/// one that the great arc down from the point to the circle crosses holds the crossing in a visible arc (the
/// real cloth's pieces were under-linked; measured: docs/benchmarks_archive.md, "Linking farther where no
/// circle saw the gap blocked").
constexpr double kSeenLinkHeightInSpacings = 2.5;

/// A vertex side's lifted wedges, by cone (cone c's are wedges[cone_begin[c] .. cone_begin[c + 1])): what
/// every plane saw, for the link tests.
struct Sightings {
  std::span<const PlanarCone> cones;
  std::span<const SpatialWedge> wedges;
  std::span<const std::size_t> cone_begin;
  glm::dvec3 side_normal;

  /// Whether no plane saw blocked directions between d, a point of arc `from`, and its projection onto the
  /// circle of arc `to`: each other plane's circle that the great arc between the two crosses does so in the
  /// side's hemisphere and inside one of that plane's visible arcs.
  bool seen_between(const glm::dvec3& d, const SpatialWedge& from, const SpatialWedge& to) const {
    const glm::dvec3& to_normal = to.plane->normal;
    const double height = glm::dot(d, to_normal);
    const glm::dvec3 across = glm::cross(d, to_normal);  // normal of the great circle from d down to `to`'s
    if (!(glm::dot(across, across) > 1e-24)) return false;
    for (std::size_t c = 0; c < cones.size(); ++c) {
      const glm::dvec3& normal = cones[c].plane->normal;
      if (std::abs(glm::dot(normal, to_normal)) > 1 - 1e-12 ||
          std::abs(glm::dot(normal, from.plane->normal)) > 1 - 1e-12)
        continue;
      glm::dvec3 x = glm::cross(across, normal);
      const double length = glm::length(x);
      if (!(length > 1e-12)) continue;  // the same great circle
      x /= glm::dot(x, d) < 0 ? -length : length;
      const double x_height = glm::dot(x, to_normal);
      if (x_height * height < 0 || std::abs(x_height) > std::abs(height)) continue;  // not between them
      if (glm::dot(x, side_normal) < 0) return false;
      bool seen = false;
      for (std::size_t w = cone_begin[c]; w < cone_begin[c + 1] && !seen; ++w) seen = wedges[w].contains(x);
      if (!seen) return false;
    }
    return true;
  }
};

/// The sines of elevation from a circle within which a point over its arc links (kLinkHeightInSpacings), and
/// within which it links where it was seen between (kSeenLinkHeightInSpacings).
struct LinkHeights {
  double over = 1.0, seen_over = 1.0;
};

/// True when two wedges belong to one visible region: their arcs cross (the paper's test: the cones share
/// more than the apex), or a sample point of one arc (ends, quarters, middle) lies over the other arc —
/// its projection onto the other's plane falls inside that arc, with its sine of elevation from that plane
/// at most `heights.over`, or at most `heights.seen_over` where the planes between saw it (seen_between) —
/// or within kLinkTolerance of one of its ends. Slices sample a visible region along a few great circles, so
/// arcs of one narrow opening rarely cross exactly.
bool same_region(const SpatialWedge& a, const SpatialWedge& b, const LinkHeights& heights,
                 const Sightings& sightings) {
  // The disjunction above, its cheapest terms (dot products with the ends) first.
  for (const glm::dvec3& d : a.sample)
    if (near_ends(d, b)) return true;
  for (const glm::dvec3& d : b.sample)
    if (near_ends(d, a)) return true;
  const glm::dvec3 line = glm::cross(a.plane->normal, b.plane->normal);
  if (glm::length(line) > 1e-12) {
    if ((a.contains(line) && b.contains(line)) || (a.contains(-line) && b.contains(-line))) return true;
  }
  // A point of `p` over `q`'s arc, within the plain height or, farther, seen between.
  auto over_arc = [&](const SpatialWedge& p, const SpatialWedge& q) {
    for (const glm::dvec3& d : p.sample) {
      const double height = std::abs(glm::dot(d, q.plane->normal));
      if (height <= heights.seen_over && q.contains(d) &&
          (height <= heights.over || sightings.seen_between(d, p, q)))
        return true;
    }
    return false;
  };
  return over_arc(a, b) || over_arc(b, a);
}

/// One piece from a group of wedges: their bounding directions sorted radially about the group's mean
/// direction c (the integral of the direction over its wedges), by azimuth in the projection about c. The
/// paper sorts about the centroid of the points projected onto the tangent plane; that order breaks on the
/// slot-shaped cones of deep folds (a thin lune from +y to -y through the fold's opening), which are
/// star-shaped about their own mean direction. Every direction is in the side's closed hemisphere (the
/// wedges were clipped to it); rounding below the horizon is snapped just above it, a pair of antipodal
/// neighbours is bridged through c, and the result is counter-clockwise about the side normal. Returns the
/// piece's vector irradiance (zero when it has fewer than three vertices).
struct Bound {
  double azimuth;         ///< pseudo_angle about the group's centre
  glm::dvec3 direction;   ///< unit
  glm::dvec3 silhouette;  ///< the horizon's great circle there (zero: not known)
  bool on_plane;          ///< the silhouette is a plane's boundary, not a tangent of a curved horizon
};

/// Whether the horizon's great circle at bound q is known.
bool known(const Bound& q) { return glm::dot(q.silhouette, q.silhouette) > 0; }

/// The corner put between two consecutive bounding directions a and b of a piece, from the horizon's great
/// circles through them where known (silhouette_corner): the horizon followed instead of the chord.
constexpr double kParabolicBulge = 2.0 / 3;
constexpr double kMaxBulge = 1.0;
/// Where the great circles of normals na and nb meet between a and b (no farther from each than they are from
/// each other), within kMaxBulge of the chord's length from it, and in every half-space of `keep`.
bool meet(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& na, const glm::dvec3& nb,
          std::span<const glm::dvec3> keep, glm::dvec3& x) {
  x = glm::cross(na, nb);
  const double length = glm::length(x);
  if (!(length > 1e-9)) return false;
  x /= length;
  if (glm::dot(x, a + b) < 0) x = -x;
  const double ab = glm::dot(a, b);
  if (!(glm::dot(a, x) >= ab - 1e-12 && glm::dot(b, x) >= ab - 1e-12)) return false;
  const glm::dvec3 chord_normal = glm::cross(a, b);
  const double chord = glm::length(chord_normal);  // sine of the chord's angle
  if (!(chord > 1e-12) || std::abs(glm::dot(x, chord_normal)) > kMaxBulge * chord * chord) return false;
  for (const glm::dvec3& h : keep)
    if (!(glm::dot(x, h) >= -1e-12)) return false;
  return true;
}

/// The parabolic arc's point over the chord a-b whose triangle with it has the arc's area, given where the
/// end tangents meet (x): 2/3 of the way from the chord's middle to x (Archimedes).
glm::dvec3 parabolic(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& x) {
  const glm::dvec3 middle = glm::normalize(a + b);
  return glm::normalize(middle + kParabolicBulge * (x - middle));
}

/// The corner between `from` and `to`: 1 where their great circles meet (exactly for two planes' boundaries,
/// else the parabolic point), 2 there exactly where one end lies on an occluding plane's boundary and the
/// other on a curved horizon; failing that, 2 from each known tangent of a curved horizon alone, the parabola
/// through both ends with that tangent (averaged where both give one); 0 where nothing is known or no corner
/// lies between them. `keep` holds the side's normal first, then the occluding planes' (assemble_cone).
int silhouette_corner(const Bound& from, const Bound& to, std::span<const glm::dvec3> keep,
                      glm::dvec3& corner) {
  const glm::dvec3 &a = from.direction, &b = to.direction, &na = from.silhouette, &nb = to.silhouette;
  const bool known_a = known(from), known_b = known(to);
  glm::dvec3 x;
  if (known_a && known_b && meet(a, b, na, nb, keep, x)) {
    // An occluding plane (the ground) cuts the view: past the end on its boundary the visible set follows
    // that great circle until the curved horizon meets it, at an angle, where the horizon's tangent does.
    // That corner lies beyond the parabola's: kept only inside the bounds' sector, so the piece stays
    // star-shaped. (At the side's own horizon the cloth curves away smoothly: the parabola.)
    auto on_occluding_plane = [&](const Bound& q) {
      return q.on_plane && !(glm::dot(q.silhouette, keep.front()) > 1 - 1e-12);
    };
    if (from.on_plane != to.on_plane && (on_occluding_plane(from) || on_occluding_plane(to))) {
      corner = x;
      return 2;
    }
    // Between two planes' boundaries the corner is exact; a curved horizon bulges as a parabola.
    corner = from.on_plane && to.on_plane ? x : parabolic(a, b, x);
    return 1;
  }
  // One tangent of a curved horizon: the parabola through a and b with that tangent, whose bulge is where the
  // tangent meets the great circle of points as far from a as from b (a parabola's two tangents meet there).
  const glm::dvec3 bisector = a - b;
  glm::dvec3 from_a(0.0), from_b(0.0);
  const bool by_a = known_a && !from.on_plane && meet(a, b, na, bisector, keep, x);
  if (by_a) from_a = parabolic(a, b, x);
  const bool by_b = known_b && !to.on_plane && meet(a, b, bisector, nb, keep, x);
  if (by_b) from_b = parabolic(a, b, x);
  if (by_a && by_b) {
    corner = glm::normalize(from_a + from_b);
    return 2;
  }
  if (!by_a && !by_b) return 0;
  corner = by_a ? from_a : from_b;
  return 2;
}

/// The normal of the great circle through d along the chord from its neighbouring bound p to q (a central
/// difference for the horizon's tangent at d); zero where p and q coincide along d.
glm::dvec3 estimated_tangent(const glm::dvec3& p, const glm::dvec3& d, const glm::dvec3& q) {
  const glm::dvec3 n = glm::cross(d, q - p);
  const double length = glm::length(n);
  return length > 1e-12 ? n / length : glm::dvec3(0.0);
}

glm::dvec3 build_piece(const std::vector<const SpatialWedge*>& group, const glm::dvec3& side_normal,
                       std::span<const glm::dvec3> keep, std::vector<Bound>& order,
                       SphericalPolygon& bridged) {
  bridged.clear();
  glm::dvec3 centre(0.0);  // the integral of the direction over the arcs: n x (start - end) per arc
  for (const SpatialWedge* w : group)
    centre += glm::cross(w->plane->normal, w->start_direction() - w->end_direction());
  centre = glm::length(centre) > 1e-12 ? glm::normalize(centre) : side_normal;
  const glm::dvec3 a1 = glm::normalize(std::abs(centre.x) < 0.9 ? glm::cross(centre, glm::dvec3(1, 0, 0))
                                                                : glm::cross(centre, glm::dvec3(0, 1, 0)));
  const glm::dvec3 a2 = glm::cross(centre, a1);
  // Whether a corner lies strictly between two consecutive bounds' azimuths about the centre (cyclically), in
  // front of it: inserted there, the piece stays star-shaped about the centre, so simple.
  auto within_sector = [&](const glm::dvec3& d, double from, double to) {
    if (!(glm::dot(d, centre) >= -1e-12)) return false;
    const double x = glm::dot(d, a1), y = glm::dot(d, a2);
    if (x * x + y * y < 1e-24) return false;
    const double at = pseudo_angle(x, y);
    return from < to ? from < at && at < to : from < at || at < to;
  };
  order.clear();
  for (const SpatialWedge* w : group)
    for (int e = 0; e < 2; ++e) {
      glm::dvec3 d = glm::normalize(e == 0 ? w->start_direction() : w->end_direction());
      const double up = glm::dot(d, side_normal);
      if (up < 1e-15) {
        const glm::dvec3 flat = d - up * side_normal;
        if (glm::length(flat) == 0) continue;
        d = glm::normalize(glm::normalize(flat) + 1e-15 * side_normal);
      }
      const double x = glm::dot(d, a1), y = glm::dot(d, a2);
      if (x * x + y * y < 1e-24) continue;  // at the centre: no azimuth, and inside anyway
      order.push_back({pseudo_angle(x, y), d, e == 0 ? w->start_silhouette : w->end_silhouette,
                       e == 0 ? w->start_on_plane : w->end_on_plane});
    }
  std::sort(order.begin(), order.end(), [](const Bound& p, const Bound& q) { return p.azimuth < q.azimuth; });
  // Keep distinct directions (in place in `order`), then bridge antipodal neighbours.
  std::size_t kept = 0;
  for (std::size_t i = 0; i < order.size(); ++i) {
    if (kept > 0 && glm::dot(order[kept - 1].direction, order[i].direction) > 1 - 1e-15) continue;
    order[kept++] = order[i];
  }
  while (kept > 1 && glm::dot(order[kept - 1].direction, order[0].direction) > 1 - 1e-15) --kept;
  // Counter-clockwise about the side normal: Lambert's integral positive. Reversing a polygon negates its
  // vector irradiance.
  auto orient = [&] {
    const glm::dvec3 irradiance = vector_irradiance(bridged);
    if (glm::dot(side_normal, irradiance) >= 0) return irradiance;
    std::reverse(bridged.begin(), bridged.end());
    return -irradiance;
  };
  if (kept < 3) {
    if (group.size() != 1 || kept != 2) return glm::dvec3(0.0);
    // One wedge alone: a sample of a visible region along one great circle, of unknown extent across it.
    // Give it a thin band, kLoneWedgeHalfWidth to each side of its plane, instead of no area at all.
    const SpatialWedge& w = *group.front();
    for (const double side : {1.0, -1.0}) {
      glm::dvec3 d = glm::normalize(w.middle() + side * kTanLoneWedge * w.plane->normal);
      const double up = glm::dot(d, side_normal);
      if (up < 1e-15) d = glm::normalize(glm::normalize(d - up * side_normal) + 1e-15 * side_normal);
      bridged.push_back(side > 0 ? order[0].direction : order[1].direction);
      bridged.push_back(d);
    }
    return orient();
  }
  for (std::size_t i = 0; i < kept; ++i) {
    const Bound &here = order[i], &next = order[(i + 1) % kept];
    bridged.push_back(here.direction);
    if (glm::dot(here.direction, next.direction) < -1 + 1e-9) {
      if (glm::dot(centre, side_normal) > 0) bridged.push_back(centre);
      continue;
    }
    // A one-tangent corner (kind 2) is kept only inside its sector; two-tangent ones (kind 1) also outside
    // it: the slot-shaped pieces of folds, sorted about a centre near their edge, need them.
    glm::dvec3 corner;
    int kind = kept > 2 ? silhouette_corner(here, next, keep, corner) : 0;
    if (kind == 0 && kept > 3 && !known(here) && !known(next)) {
      // Neither end's horizon is known: each tangent estimated by central differences from the neighbouring
      // bounds, the corner kept only inside its sector (as a one-tangent corner).
      Bound from = here, to = next;
      from.silhouette =
          estimated_tangent(order[(i + kept - 1) % kept].direction, here.direction, next.direction);
      to.silhouette = estimated_tangent(here.direction, next.direction, order[(i + 2) % kept].direction);
      if (silhouette_corner(from, to, keep, corner) != 0) kind = 2;
    }
    if (kind == 1 || (kind == 2 && within_sector(corner, here.azimuth, next.azimuth)))
      bridged.push_back(corner);
  }
  return orient();
}

/// Running sums of a cone's measures over its pieces (Lambert's formula, the cosine-weighted moment).
struct MeasureSums {
  glm::dvec3 moment{0.0};
  double projected = 0.0, solid_angle = 0.0;
  void add(const SphericalPolygon& piece, const glm::dvec3& irradiance, double piece_solid_angle,
           const glm::dvec3& side_normal) {
    projected += glm::dot(side_normal, irradiance);
    moment += cosine_weighted_moment(piece, side_normal, piece_solid_angle);
    solid_angle += piece_solid_angle;
  }
  ConeMeasures measures(const glm::dvec3& side_normal) const {
    ConeMeasures m;
    m.solid_angle = solid_angle;
    m.sky_visibility = std::clamp(projected / (kTwoPi / 2), 0.0, 1.0);
    const double len = glm::length(moment);
    m.bent_normal = len > 1e-15 ? moment / len : side_normal;
    return m;
  }
};

/// Within kTouchTolerance (radians) of a piece's boundary a direction touches it: pieces built from the same
/// planes' wedge ends often share a vertex or put one on the other's edge, exactly but for rounding, and
/// there a winding number is decided by the rounding (a fan triangle turns half a turn either way).
constexpr double kTouchTolerance = 1e-9;

/// Whether unit direction p lies within kTouchTolerance of the boundary of `piece`: of a vertex, or of an
/// edge's arc (near its great circle and between its ends).
bool touches_boundary(const SphericalPolygon& piece, const glm::dvec3& p) {
  for (std::size_t i = 0; i < piece.size(); ++i) {
    const glm::dvec3 &a = piece[i], &b = piece[(i + 1) % piece.size()];
    if (glm::length(glm::cross(a, p)) < kTouchTolerance && glm::dot(a, p) > 0) return true;
    const glm::dvec3 n = glm::cross(a, b);
    const double length = glm::length(n);
    if (!(length > 0)) continue;
    if (std::abs(glm::dot(p, n)) < kTouchTolerance * length && glm::dot(glm::cross(a, p), n) >= 0 &&
        glm::dot(glm::cross(p, b), n) >= 0)
      return true;
  }
  return false;
}

/// Whether `piece` (its solid angle and bounding cap given) holds direction p strictly inside, not touching
/// its boundary.
bool holds_inside(const SphericalPolygon& piece, double solid_angle, const BoundingCap& cap,
                  const glm::dvec3& p) {
  return may_contain(cap, p) && contains_direction(piece, p, solid_angle) && !touches_boundary(piece, p);
}

/// True when one piece holds a vertex of the other strictly inside — not touching its boundary — (the pieces'
/// solid angles and bounding caps given).
bool pieces_overlap(const SphericalPolygon& a, double a_solid_angle, const BoundingCap& a_cap,
                    const SphericalPolygon& b, double b_solid_angle, const BoundingCap& b_cap) {
  if (a.size() < 3 || b.size() < 3) return false;
  for (const auto& p : a)
    if (holds_inside(b, b_solid_angle, b_cap, p)) return true;
  for (const auto& p : b)
    if (holds_inside(a, a_solid_angle, a_cap, p)) return true;
  return false;
}

}  // namespace

struct ConeAssemblyScratch::Buffers {
  std::vector<SpatialWedge> wedges;
  std::vector<Wedge> united, clipped, swap;
  std::vector<AngularInterval> intervals;
  std::vector<int> parent, group_of, roots;
  std::vector<const SpatialWedge*> members;
  std::vector<Bound> order;
  std::vector<glm::dvec3> keep;                 // the side normal and the half-spaces
  std::vector<std::size_t> cone_begin;          // per cone, its first lifted wedge; then their count
  std::vector<double> cone_horizon;             // per cone, where its side's half-turn starts (NaN: none)
  std::vector<std::pair<double, double>> arcs;  // one plane's clipped wedges: offset from its horizon, end
  std::vector<SphericalPolygon> pieces;         // capacity kept across calls
  std::vector<double> piece_solid_angle;
  std::vector<glm::dvec3> piece_irradiance;
  std::vector<BoundingCap> piece_cap;
  std::vector<std::unique_ptr<ConeReconstructor>> rules;  // per reconstruction rule, made when first used
  std::unique_ptr<ConeReconstructor> nearest_circle;      // the grouped rule's fallback (its step 4)
};

namespace {

/// Gaps narrower than this (radians) between two visible arcs of a plane are not tested (holds_gaps): a
/// rounding sliver, or a blocked sample too thin to matter.
constexpr double kMinGap = 1e-3;
/// The share of the visible arcs' length that the gaps the pieces hold must reach before the nearest-circle
/// rule rebuilds a cone. Rebuilding wherever a gap is held widens a small obstacle's single blocked sample to
/// its whole cell; a tenth keeps the rings of sky and leaves those (measured: docs/benchmarks_archive.md,
/// "Open fans, rings of sky, and an exact reference").
constexpr double kHeldShare = 0.1;

/// Whether the first `count` pieces hold gaps between consecutive visible arcs of the planes' great circles
/// (b.wedges, per cone from b.cone_begin: the arcs clipped to the half-turn in the side's hemisphere that
/// starts at b.cone_horizon) — the gaps' middles — adding up to kHeldShare of the visible arcs' length.
bool holds_gaps(std::span<const PlanarCone> cones, ConeAssemblyScratch::Buffers& b, std::size_t count) {
  double held = 0.0;
  for (std::size_t c = 0; c < cones.size(); ++c) {
    const std::size_t begin = b.cone_begin[c], end = b.cone_begin[c + 1];
    const double horizon = b.cone_horizon[c];
    if (end - begin < 2 || std::isnan(horizon)) continue;
    const SlicingPlane& plane = *cones[c].plane;
    b.arcs.clear();
    for (std::size_t i = begin; i < end; ++i) {
      const double from = wrap_angle(b.wedges[i].start - horizon);
      b.arcs.emplace_back(from, from + b.wedges[i].width);
    }
    std::sort(b.arcs.begin(), b.arcs.end());
    for (std::size_t i = 0; i + 1 < b.arcs.size(); ++i) {
      const double gap_from = b.arcs[i].second, gap_to = b.arcs[i + 1].first;
      if (!(gap_to - gap_from > kMinGap)) continue;
      const double middle = horizon + 0.5 * (gap_from + gap_to);
      const glm::dvec3 d = std::cos(middle) * plane.u + std::sin(middle) * plane.w;
      for (std::size_t k = 0; k < count; ++k)
        if (b.pieces[k].size() >= 3 && holds_inside(b.pieces[k], b.piece_solid_angle[k], b.piece_cap[k], d)) {
          held += gap_to - gap_from;
          break;
        }
    }
  }
  if (held == 0.0) return false;
  double visible = 0.0;
  for (const SpatialWedge& w : b.wedges) visible += w.width;
  return held >= kHeldShare * visible;
}

}  // namespace

ConeAssemblyScratch::ConeAssemblyScratch() : m_buffers(std::make_unique<Buffers>()) {}
ConeAssemblyScratch::~ConeAssemblyScratch() = default;

void assemble_cone(std::span<const PlanarCone> cones, const glm::dvec3& side_normal,
                   ConeAssemblyScratch& scratch, VisibilityCone& result) {
  assemble_and_measure_cone(cones, side_normal, scratch, result, nullptr);
}

void assemble_and_measure_cone(std::span<const PlanarCone> cones, const glm::dvec3& side_normal,
                               ConeAssemblyScratch& scratch, VisibilityCone& result, ConeMeasures* measures,
                               std::span<const glm::dvec3> half_spaces, ConeReconstruction rule) {
  auto& rules = scratch.m_buffers->rules;
  const std::size_t id = static_cast<std::size_t>(rule);
  if (id >= rules.size()) rules.resize(cone_reconstruction_rules().size());
  if (!rules[id]) rules[id] = cone_reconstruction_rule(rule).make();
  rules[id]->assemble(cones, side_normal, half_spaces, result, measures);
}

ConeMeasures measures_of_pieces(const VisibilityCone& cone, std::span<const glm::dvec3> irradiance,
                                std::span<const double> solid_angle, const glm::dvec3& side_normal) {
  MeasureSums sums;
  for (std::size_t i = 0; i < cone.pieces.size(); ++i)
    sums.add(cone.pieces[i], irradiance[i], solid_angle[i], side_normal);
  return sums.measures(side_normal);
}

namespace {

/// The paper's grouped reconstruction (the header's): wedges linked into groups, each group one piece.
void assemble_grouped(std::span<const PlanarCone> cones, const glm::dvec3& side_normal,
                      ConeAssemblyScratch::Buffers& b, VisibilityCone& result, ConeMeasures* measures,
                      std::span<const glm::dvec3> half_spaces) {
  // In a plane, the half-space {d : dot(d, h) >= 0} is the half-turn of directions within a quarter turn of
  // h's projection; a plane perpendicular to h lies on its boundary and keeps every direction.
  // Returns where the kept half-turn starts (NaN: the whole turn is kept).
  auto clip = [&](const SlicingPlane& plane, const glm::dvec3& h, std::span<const Wedge> in,
                  std::vector<Wedge>& out) {
    const glm::dvec2 m(glm::dot(plane.u, h), glm::dot(plane.w, h));
    if (!(glm::length(m) > 1e-9)) {
      out.assign(in.begin(), in.end());
      return std::numeric_limits<double>::quiet_NaN();
    }
    const double start = wrap_angle(direction_angle(m) - kHalfPi);
    clip_to_half_turn(in, start, out);
    return start;
  };
  b.keep.assign(1, side_normal);
  b.keep.insert(b.keep.end(), half_spaces.begin(), half_spaces.end());
  // The horizon's great circle at a wedge end: from the cone's tangents (an aimed end), or the boundary of
  // the side's or a plane's half-space the end was clipped to; zero where not known.
  auto silhouette = [&](const PlanarCone& cone, double angle, const glm::dvec3& direction, glm::dvec3& normal,
                        bool& on_plane) {
    for (const glm::dvec3& h : b.keep)
      if (std::abs(glm::dot(direction, h)) < 1e-9) {
        normal = h, on_plane = true;
        return;
      }
    const SlicingPlane& p = *cone.plane;
    for (const HorizonTangent& t : cone.tangents)
      if (std::abs(std::remainder(angle - t.angle, kTwoPi)) < 1e-9) {
        normal = t.normal.x * p.u + t.normal.y * p.w + t.normal.z * p.normal;
        return;
      }
  };
  // 1. Clip every wedge to the side's half-space (and the planes') and lift it into space.
  b.wedges.clear();
  b.cone_begin.clear();
  b.cone_horizon.clear();
  for (const PlanarCone& cone : cones) {
    b.cone_begin.push_back(b.wedges.size());
    const SlicingPlane& plane = *cone.plane;
    std::span<const Wedge> wedges = cone.wedges;
    if (!is_united(wedges)) {
      b.united.clear();
      unite_wedges(wedges, b.intervals, b.united);
      wedges = b.united;
    }
    b.clipped.clear();
    b.cone_horizon.push_back(clip(plane, side_normal, wedges, b.clipped));
    for (const glm::dvec3& h : half_spaces) {
      b.swap.clear();
      clip(plane, h, b.clipped, b.swap);
      b.clipped.swap(b.swap);
    }
    for (const Wedge& w : b.clipped)
      if (w.width > kContainTolerance) {
        SpatialWedge& lifted = b.wedges.emplace_back(&plane, w);
        silhouette(cone, w.start, lifted.start_direction(), lifted.start_silhouette, lifted.start_on_plane);
        silhouette(cone, w.end(), lifted.end_direction(), lifted.end_silhouette, lifted.end_on_plane);
      }
  }
  b.cone_begin.push_back(b.wedges.size());
  // 2. Group by intersection (union-find). The circles' spacing is pi / n for the n orientations (planes
  //    with distinct normals, up to sign) that cut the vertex.
  std::size_t orientations = 0;
  for (std::size_t i = 0; i < cones.size(); ++i) {
    bool repeated = false;
    for (std::size_t j = 0; j < i && !repeated; ++j)
      repeated = std::abs(glm::dot(cones[i].plane->normal, cones[j].plane->normal)) > 1 - 1e-12;
    orientations += !repeated;
  }
  auto height = [&](double spacings) {
    return orientations > 0 ? std::sin(std::min(kHalfPi, spacings * (kTwoPi / 2) / double(orientations)))
                            : 1.0;
  };
  const LinkHeights heights{height(kLinkHeightInSpacings), height(kSeenLinkHeightInSpacings)};
  const Sightings sightings{cones, b.wedges, b.cone_begin, side_normal};
  const int k = static_cast<int>(b.wedges.size());
  std::vector<int>& parent = b.parent;
  parent.resize(k);
  std::iota(parent.begin(), parent.end(), 0);
  for (int i = 0; i < k; ++i)
    for (int j = i + 1; j < k; ++j)
      if (find_root(parent, i) != find_root(parent, j) &&
          same_region(b.wedges[i], b.wedges[j], heights, sightings))
        parent[find_root(parent, i)] = find_root(parent, j);
  // 3. One piece per group (see build_piece); groups whose pieces overlap are merged and rebuilt, so the
  //    pieces of a cone are disjoint and their integrals add up.
  b.group_of.resize(k);
  b.roots.clear();
  for (int i = 0; i < k; ++i) {
    b.group_of[i] = find_root(parent, i);
    if (b.group_of[i] == i) b.roots.push_back(i);
  }
  // Piece r with its vector irradiance and solid angle (each computed once per build).
  auto build = [&](std::size_t r) {
    b.members.clear();
    for (int i = 0; i < k; ++i)
      if (b.group_of[i] == b.roots[r]) b.members.push_back(&b.wedges[i]);
    b.piece_irradiance[r] = build_piece(b.members, side_normal, b.keep, b.order, b.pieces[r]);
    b.piece_solid_angle[r] = solid_angle(b.pieces[r], b.piece_irradiance[r]);
    b.piece_cap[r] = bounding_cap(b.pieces[r], b.piece_solid_angle[r]);
  };
  if (b.pieces.size() < b.roots.size()) b.pieces.resize(b.roots.size());
  b.piece_solid_angle.resize(b.roots.size());
  b.piece_irradiance.resize(b.roots.size());
  b.piece_cap.resize(b.roots.size());
  for (std::size_t r = 0; r < b.roots.size(); ++r) build(r);
  std::size_t count = b.roots.size();
  for (bool merged = count > 1; merged;) {
    merged = false;
    for (std::size_t i = 0; i < count && !merged; ++i)
      for (std::size_t j = i + 1; j < count && !merged; ++j)
        if (pieces_overlap(b.pieces[i], b.piece_solid_angle[i], b.piece_cap[i], b.pieces[j],
                           b.piece_solid_angle[j], b.piece_cap[j])) {
          for (int& g : b.group_of)
            if (g == b.roots[j]) g = b.roots[i];
          build(i);
          for (std::size_t t = j; t + 1 < count; ++t) {  // drop j, keep order
            std::swap(b.pieces[t], b.pieces[t + 1]);
            std::swap(b.piece_solid_angle[t], b.piece_solid_angle[t + 1]);
            std::swap(b.piece_irradiance[t], b.piece_irradiance[t + 1]);
            std::swap(b.piece_cap[t], b.piece_cap[t + 1]);
          }
          b.roots.erase(b.roots.begin() + static_cast<long>(j));
          --count;
          merged = true;
        }
  }
  // 4. A piece should not hold directions the planes saw blocked. Where the pieces hold gaps between two of a
  //    plane's visible arcs (holds_gaps), a group surrounds a blocked region — a ring of sky round a fold
  //    that fills the middle of the view, as inside a sleeve's cuff — and a polygon about the group's centre
  //    cannot leave that region out: the nearest-circle rule, which keeps every plane's samples whatever
  //    their shape, rebuilds the cone.
  if (count > 0 && holds_gaps(cones, b, count)) {
    if (!b.nearest_circle)
      b.nearest_circle = cone_reconstruction_rule(ConeReconstruction::NearestCircle).make();
    b.nearest_circle->assemble(cones, side_normal, half_spaces, result, measures);
    return;
  }
  std::size_t out = 0;
  MeasureSums sums;
  for (std::size_t i = 0; i < count; ++i) {
    if (b.pieces[i].size() < 3) continue;
    if (result.pieces.size() <= out) result.pieces.emplace_back();
    result.pieces[out].assign(b.pieces[i].begin(), b.pieces[i].end());
    if (measures) sums.add(b.pieces[i], b.piece_irradiance[i], b.piece_solid_angle[i], side_normal);
    ++out;
  }
  result.pieces.resize(out);
  if (measures) *measures = sums.measures(side_normal);
}

class GroupedReconstructor final : public ConeReconstructor {
 public:
  void assemble(std::span<const PlanarCone> cones, const glm::dvec3& side_normal,
                std::span<const glm::dvec3> half_spaces, VisibilityCone& result,
                ConeMeasures* measures) override {
    assemble_grouped(cones, side_normal, m_buffers, result, measures, half_spaces);
  }

 private:
  ConeAssemblyScratch::Buffers m_buffers;
};

}  // namespace

namespace rules {
extern const ConeReconstructionRule kGrouped{
    "grouped",
    "the paper's: wedges that cross or come close grouped, each group one polygon about its mean direction",
    [] { return std::unique_ptr<ConeReconstructor>(std::make_unique<GroupedReconstructor>()); }};
}  // namespace rules

VisibilityCone assemble_cone(std::span<const PlanarCone> cones, const glm::dvec3& side_normal) {
  ConeAssemblyScratch scratch;
  VisibilityCone result;
  assemble_cone(cones, side_normal, scratch, result);
  return result;
}

ConeMeasures measure_cone(const VisibilityCone& cone, const glm::dvec3& side_normal) {
  // The pieces lie in the side's closed hemisphere and are counter-clockwise about it (assemble_cone), so
  // Lambert's formula applies to them directly; clip_to_hemisphere would only add rounding trouble for
  // vertices that lie on the horizon.
  MeasureSums sums;
  for (const auto& piece : cone.pieces) {
    const glm::dvec3 irradiance = vector_irradiance(piece);
    sums.add(piece, irradiance, solid_angle(piece, irradiance), side_normal);
  }
  return sums.measures(side_normal);
}

}  // namespace pleat
