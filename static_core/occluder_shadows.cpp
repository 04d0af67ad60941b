#include "static_core/internal/occluder_shadows.hpp"

#include <CGAL/convex_hull_2.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <numeric>

#include "static_core/internal/cgal_types.hpp"
#include "static_core/union_find.hpp"

namespace pleat {
namespace {

using cgal::Point2;

CGAL::Orientation orient(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
  return cgal::orientation(cgal::to_point(a), cgal::to_point(b), cgal::to_point(c));
}

/// Whether p lies strictly outside the convex polygon `hull` (counter-clockwise, at least three vertices).
bool strictly_outside(std::span<const glm::dvec2> hull, const glm::dvec2& p) {
  for (std::size_t i = 0; i < hull.size(); ++i)
    if (orient(hull[i], hull[(i + 1) % hull.size()], p) == CGAL::RIGHT_TURN) return true;
  return false;
}

double distance2(const glm::dvec2& a, const glm::dvec2& b) { return glm::dot(a - b, a - b); }

/// p's tangent to the convex polygon `hull` (p strictly outside it) on the clockwise side (`clockwise`) or
/// the counter-clockwise one: the vertex every other one lies left of (right of) as seen from p, of several
/// in that direction the nearer (a funnel's apex there, hence the wedge's reach). Walks from `from`: seen
/// from a point outside, a convex polygon's vertices turn one way and then back, so a local extreme is the
/// one.
std::uint32_t tangent(std::span<const glm::dvec2> hull, const glm::dvec2& p, std::uint32_t from,
                      bool clockwise) {
  const std::uint32_t k = static_cast<std::uint32_t>(hull.size());
  const CGAL::Orientation beyond = clockwise ? CGAL::RIGHT_TURN : CGAL::LEFT_TURN;
  auto better = [&](std::uint32_t j, std::uint32_t i) {
    const CGAL::Orientation o = orient(p, hull[i], hull[j]);
    return o == beyond || (o == CGAL::COLLINEAR && distance2(p, hull[j]) < distance2(p, hull[i]));
  };
  std::uint32_t t = from % k;
  for (std::uint32_t steps = 0; steps < k; ++steps) {
    const std::uint32_t next = (t + 1) % k, previous = (t + k - 1) % k;
    if (better(next, t))
      t = next;
    else if (better(previous, t))
      t = previous;
    else
      break;
  }
  return t;
}

/// Appends to `out` the parts of wedge w (start in [0, 2pi)) outside wedge b (start in [0, 2pi), width below
/// a full turn): up to two, each end at w's or b's end with its reach; parts up to kAngleTolerance wide are
/// dropped.
void subtract_wedge(const Wedge& w, const Wedge& b, std::vector<Wedge>& out) {
  double d = b.start - w.start;  // where b starts, counter-clockwise from w's start
  if (d < 0) d += kTwoPi;
  const double b_end = d + b.width;           // in w's frame; past 2pi, b covers w's start too
  if (w.width >= kTwoPi - kAngleTolerance) {  // a full turn: what b leaves is one wedge
    if (kTwoPi - b.width > kAngleTolerance)
      out.push_back({wrap_angle(b.end()), kTwoPi - b.width, b.end_reach, b.start_reach});
    return;
  }
  const double lo = b_end > kTwoPi ? b_end - kTwoPi : 0.0;  // w's start is hidden up to lo
  const double before = std::min(w.width, d);               // the part before b: [lo, before]
  if (before - lo > kAngleTolerance)
    out.push_back({lo > 0 ? wrap_angle(b.end()) : w.start, before - lo, lo > 0 ? b.end_reach : w.start_reach,
                   d < w.width ? b.start_reach : w.end_reach});
  if (b_end < w.width && w.width - b_end > kAngleTolerance)  // the part after b: [b_end, w.width]
    out.push_back({wrap_angle(b.end()), w.width - b_end, b.end_reach, w.end_reach});
}

/// Whether wedge b (start in [0, 2pi)) overlaps one of `wedges` (united) by more than a point.
bool overlaps(const Wedge& b, std::span<const Wedge> wedges) {
  for (const Wedge& w : wedges) {
    double d = b.start - w.start;  // where b starts, counter-clockwise from w's start
    if (d < 0) d += kTwoPi;
    if (d < w.width || d + b.width > kTwoPi) return true;
  }
  return false;
}

bool off_box(const OccluderChains::Chain& chain, const glm::dvec2& p, double margin = 0.0) {
  return p.x < chain.lo.x - margin || p.x > chain.hi.x + margin || p.y < chain.lo.y - margin ||
         p.y > chain.hi.y + margin;
}

std::span<const glm::dvec2> hull_of(const OccluderChains& chains, const OccluderChains::Chain& chain) {
  return {chains.hull.data() + chain.hull_begin, chains.hull.data() + chain.hull_end};
}

enum class Inside { No, Yes, On };

/// Where p lies against a closed chain's loop: on a segment, or inside by the parity of the loop's
/// crossings of the ray from p towards +x. Exact: orientation tests and comparisons of input coordinates.
Inside inside_loop(std::span<const std::array<glm::dvec2, 2>> segments, const glm::dvec2& p) {
  bool inside = false;
  for (const auto& [a, b] : segments) {
    const bool a_up = a.y > p.y, b_up = b.y > p.y;
    if (a_up == b_up) {  // not across p's line: p can only lie on it if it runs along that line
      if (a.y == p.y && b.y == p.y && std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x))
        return Inside::On;
      continue;
    }
    const CGAL::Orientation o = orient(a, b, p);
    if (o == CGAL::COLLINEAR) return Inside::On;           // on its line, between its ends' heights
    if ((o == CGAL::LEFT_TURN) == b_up) inside = !inside;  // crosses the ray to p's right
  }
  return inside ? Inside::Yes : Inside::No;
}

/// The nearest point to p of the segments of `chains` for which `take(chain)` holds, no farther than
/// sqrt(best.d2) on entry (at that distance only if none was found before).
struct Nearest {
  double d2 = INFINITY;
  std::int32_t chain = -1;
  std::uint32_t segment = 0;
  double t = 0.0;
};
template <class Take>
void nearest_segment(const OccluderChains& chains, const glm::dvec2& p, Take take, Nearest& best) {
  for (std::size_t c = 0; c < chains.chains.size(); ++c) {
    const OccluderChains::Chain& chain = chains.chains[c];
    if (!take(chain) || off_box(chain, p, std::sqrt(best.d2))) continue;
    for (std::uint32_t i = chain.segments_begin; i < chain.segments_end; ++i) {
      const auto& [a, b] = chains.segments[i];
      const glm::dvec2 ab = b - a;
      const double length2 = glm::dot(ab, ab);
      const double t = length2 > 0 ? std::clamp(glm::dot(p - a, ab) / length2, 0.0, 1.0) : 0.0;
      const double d2 = distance2(p, a + t * ab);
      if (d2 < best.d2 || (best.chain < 0 && d2 == best.d2)) best = {d2, static_cast<std::int32_t>(c), i, t};
    }
  }
}

Viewpoint viewpoint_at(const OccluderChains& chains, const Nearest& nearest) {
  const auto& [a, b] = chains.segments[nearest.segment];
  Viewpoint v;
  v.chain = nearest.chain;
  v.open = !chains.chains[std::size_t(nearest.chain)].closed;
  v.segment = nearest.segment;
  v.end = nearest.t <= 0.0 ? 0 : nearest.t >= 1.0 ? 1 : -1;
  v.point = v.end == 0 ? a : v.end == 1 ? b : a + nearest.t * (b - a);
  return v;
}

/// Whether segment i of chain c passes through the viewpoint, which then sees nothing of it.
bool through_viewpoint(const OccluderChains& chains, std::size_t c, std::uint32_t i, const Viewpoint& from) {
  if (from.chain != static_cast<std::int32_t>(c)) return false;
  if (i == from.segment) return true;
  if (from.end < 0) return false;
  const glm::dvec2& end = chains.segments[from.segment][std::size_t(from.end)];
  return chains.segments[i][0] == end || chains.segments[i][1] == end;
}

/// What the segment (a, b) blocks seen from a point q on it, on its front: the half-plane behind it, from
/// the direction of a round to that of b, with their reaches.
Wedge back_half_plane(const std::array<glm::dvec2, 2>& segment, const glm::dvec2& q) {
  const auto& [a, b] = segment;
  return {wrap_angle(std::atan2(b.y - a.y, b.x - a.x) + 0.5 * kTwoPi), 0.5 * kTwoPi,
          static_cast<float>(glm::length(a - q)), static_cast<float>(glm::length(b - q))};
}

}  // namespace

void hulls_outside(const OccluderChains& chains, const glm::dvec2& p, std::vector<char>& outside) {
  outside.resize(chains.chains.size());
  for (std::size_t c = 0; c < chains.chains.size(); ++c) {
    const OccluderChains::Chain& chain = chains.chains[c];
    const std::span<const glm::dvec2> hull = hull_of(chains, chain);
    outside[c] = hull.size() >= 3   ? off_box(chain, p) || strictly_outside(hull, p)
                 : hull.size() == 2 ? orient(hull[0], hull[1], p) != CGAL::COLLINEAR
                                    : false;
  }
}

Viewpoint contact_viewpoint(const OccluderChains& chains, const glm::dvec2& p, std::span<const char> outside,
                            double tolerance) {
  // Inside the solids: the parity over the closed chains that may hold p (a loop inside another, a cavity,
  // cancels it), or on one of them.
  bool inside = false;
  for (std::size_t c = 0; c < chains.chains.size(); ++c) {
    const OccluderChains::Chain& chain = chains.chains[c];
    if (!chain.closed || off_box(chain, p) || outside[c]) continue;
    const Inside where = inside_loop(
        {chains.segments.data() + chain.segments_begin, chains.segments.data() + chain.segments_end}, p);
    if (where == Inside::On) {
      inside = true;
      break;
    }
    inside = inside != (where == Inside::Yes);
  }
  Nearest nearest;
  if (inside) {
    nearest_segment(
        chains, p, [](const OccluderChains::Chain& c) { return c.closed; }, nearest);
    return viewpoint_at(chains, nearest);
  }
  // On or behind an open surface (on its back, the right of its oriented segments), within a tolerance (none:
  // an open surface is taken as it is, a point on it seeing both ways).
  if (tolerance > 0) {
    nearest.d2 = tolerance * tolerance;
    nearest_segment(
        chains, p, [](const OccluderChains::Chain& c) { return !c.closed; }, nearest);
    if (nearest.chain >= 0) {
      const auto& [a, b] = chains.segments[nearest.segment];
      if (orient(a, b, p) != CGAL::LEFT_TURN) return viewpoint_at(chains, nearest);
    }
  }
  Viewpoint self;
  self.point = p;
  return self;
}

void gather_occluder_chains(const Slice& occluders, ShadowScratch& s, OccluderChains& out) {
  out.chains.clear();
  out.segments.clear();
  out.hull.clear();
  // The chains as connected sets of edges (whatever their directions: a mesh wound inconsistently, or
  // several chains meeting at a point, still gives one connected set), numbered by their first vertex.
  const std::size_t n = occluders.vertices.size();
  s.parent.resize(n);
  std::iota(s.parent.begin(), s.parent.end(), 0);
  s.degree.assign(n, 0);
  for (const SliceEdge& e : occluders.edges) {
    s.parent[find_root(s.parent, int(e.from))] = find_root(s.parent, int(e.to));
    ++s.degree[e.from];
    ++s.degree[e.to];
  }
  s.chain_of.assign(n, -1);
  std::size_t chains = 0;
  for (Index x = 0; x < n; ++x) {
    const int root = find_root(s.parent, int(x));
    if (s.chain_of[root] < 0) s.chain_of[root] = static_cast<int>(chains++);
    s.chain_of[x] = s.chain_of[root];
  }
  // Vertices and edges grouped by chain, in their order within each (a counting sort).
  auto group = [&](std::size_t count, auto chain_of_item, std::vector<Index>& order) {
    s.first.assign(chains + 1, 0);
    for (std::size_t i = 0; i < count; ++i) ++s.first[chain_of_item(i) + 1];
    for (std::size_t c = 0; c < chains; ++c) s.first[c + 1] += s.first[c];
    order.resize(count);
    for (std::size_t i = 0; i < count; ++i) order[s.first[chain_of_item(i)]++] = static_cast<Index>(i);
  };
  group(
      n, [&](std::size_t x) { return std::size_t(s.chain_of[x]); }, s.order);
  group(
      occluders.edges.size(), [&](std::size_t i) { return std::size_t(s.chain_of[occluders.edges[i].from]); },
      s.edge_order);
  std::size_t v = 0, e = 0;
  for (std::size_t c = 0; c < chains; ++c) {
    OccluderChains::Chain chain;
    chain.segments_begin = static_cast<std::uint32_t>(out.segments.size());
    for (; e < s.edge_order.size() && std::size_t(s.chain_of[occluders.edges[s.edge_order[e]].from]) == c;
         ++e) {
      const SliceEdge& edge = occluders.edges[s.edge_order[e]];
      out.segments.push_back({occluders.vertices[edge.from].point, occluders.vertices[edge.to].point});
    }
    s.points.clear();
    chain.closed = true;
    for (; v < n && std::size_t(s.chain_of[s.order[v]]) == c; ++v) {
      s.points.push_back(occluders.vertices[s.order[v]].point);
      chain.closed = chain.closed && s.degree[s.order[v]] == 2;
    }
    chain.segments_end = static_cast<std::uint32_t>(out.segments.size());
    chain.closed = chain.closed && chain.segments_end - chain.segments_begin >= 3;
    chain.lo = chain.hi = s.points.front();
    for (const glm::dvec2& q : s.points) {
      chain.lo = glm::min(chain.lo, q);
      chain.hi = glm::max(chain.hi, q);
    }
    chain.hull_begin = static_cast<std::uint32_t>(out.hull.size());
    s.cgal_points.clear();
    for (const glm::dvec2& q : s.points) s.cgal_points.push_back(cgal::to_point(q));
    s.cgal_hull.clear();
    CGAL::convex_hull_2(s.cgal_points.begin(), s.cgal_points.end(), std::back_inserter(s.cgal_hull));
    const std::vector<Point2>& hull = s.cgal_hull;
    for (const Point2& q : hull) out.hull.emplace_back(q.x(), q.y());
    chain.hull_end = static_cast<std::uint32_t>(out.hull.size());
    // Where the tangent walks start: the hull's vertices by polar angle about its centre (increasing from
    // the one at the smallest, a convex polygon's vertices being in angular order about an inner point).
    out.polar.resize(out.hull.size());
    if (hull.size() >= 3) {
      chain.centre = glm::dvec2(0.0);
      for (std::uint32_t i = chain.hull_begin; i < chain.hull_end; ++i) chain.centre += out.hull[i];
      chain.centre /= double(hull.size());
      chain.radius = 0.0;
      for (std::uint32_t i = chain.hull_begin; i < chain.hull_end; ++i) {
        out.polar[i] = pseudo_angle(out.hull[i].x - chain.centre.x, out.hull[i].y - chain.centre.y);
        chain.radius += glm::length(out.hull[i] - chain.centre) / double(hull.size());
        if (out.polar[i] < out.polar[chain.hull_begin + chain.polar_first])
          chain.polar_first = i - chain.hull_begin;
      }
    }
    out.chains.push_back(chain);
  }
}

void blocked_by_chain(const OccluderChains& chains, std::size_t c, const Viewpoint& from, bool outside_hull,
                      ShadowScratch& s, std::vector<Wedge>& out) {
  const OccluderChains::Chain& chain = chains.chains[c];
  const std::span<const glm::dvec2> hull = hull_of(chains, chain);
  const glm::dvec2& p = from.point;
  // On an open chain the viewpoint lies on it, on its front: its segment blocks what lies behind it,
  // whichever side of the chain's line rounding put the point.
  const bool own = from.chain == static_cast<std::int32_t>(c), on_open = own && from.open;
  if (outside_hull && !on_open) {
    // The walks start where a circle's tangents would touch (a circle of the hull's mean radius about its
    // centre), the exact walks go on from there.
    std::uint32_t from_r = 0, from_l = 0;
    if (hull.size() >= 3) {
      // The circle's tangent points from p, turned from the direction to p by +-acos(radius / |d|).
      const glm::dvec2 d = p - chain.centre;
      const double cosine = std::min(1.0, chain.radius / glm::length(d)),
                   sine = std::sqrt(1 - cosine * cosine);
      const std::span<const double> polar(chains.polar.data() + chain.hull_begin, hull.size());
      auto nearest = [&](const glm::dvec2& direction) {
        const double angle = pseudo_angle(direction.x, direction.y);
        std::uint32_t lo = 0, hi = static_cast<std::uint32_t>(polar.size());  // in the rotated order
        while (lo < hi) {
          const std::uint32_t mid = (lo + hi) / 2;
          if (polar[(chain.polar_first + mid) % polar.size()] < angle)
            lo = mid + 1;
          else
            hi = mid;
        }
        return static_cast<std::uint32_t>((chain.polar_first + lo) % polar.size());
      };
      from_r = nearest({d.x * cosine - d.y * sine, d.x * sine + d.y * cosine});
      from_l = nearest({d.x * cosine + d.y * sine, d.y * cosine - d.x * sine});
    }
    const std::uint32_t r = tangent(hull, p, from_r, true), l = tangent(hull, p, from_l, false);
    out.push_back(thin_wedge_between(hull[r] - p, hull[l] - p));
    return;
  }
  if (hull.size() < 2) return;  // a chain on one point blocks no range
  s.blocked.clear();
  if (on_open) s.blocked.push_back(back_half_plane(chains.segments[from.segment], p));
  for (std::uint32_t i = chain.segments_begin; i < chain.segments_end; ++i) {
    if (own && through_viewpoint(chains, c, i, from)) continue;
    const auto& [a, b] = chains.segments[i];
    switch (orient(p, a, b)) {
      case CGAL::LEFT_TURN:
        s.blocked.push_back(thin_wedge_between(a - p, b - p));
        break;
      case CGAL::RIGHT_TURN:
        s.blocked.push_back(thin_wedge_between(b - p, a - p));
        break;
      default:  // along p's line: no range
        break;
    }
  }
  unite_wedges(s.blocked, s.intervals, out);
}

void cast_occluder_shadows(const Slice& slice, const OccluderChains& chains, std::span<const char> needed,
                           double contact_tolerance, ShadowScratch& s, SliceCones& cones) {
  if (chains.chains.empty()) return;
  s.wedges_out.clear();
  s.offsets_out.assign(1, 0);
  const std::size_t n = slice.vertices.size();
  for (Index x = 0; x < n; ++x) {
    for (int side = 0; side < 2; ++side) {
      const std::span<const Wedge> cone = cones.cone(x, static_cast<Side>(side));
      s.side_cone[side].assign(cone.begin(), cone.end());
    }
    const bool wanted = (needed.empty() || needed[x]) && !(s.side_cone[0].empty() && s.side_cone[1].empty());
    Viewpoint from;
    if (wanted) {
      hulls_outside(chains, slice.vertices[x].point, s.outside_hull);
      from = contact_viewpoint(chains, slice.vertices[x].point, s.outside_hull, contact_tolerance);
      if (from.chain >= 0) hulls_outside(chains, from.point, s.outside_hull);  // seen from a chain's point
    }
    for (std::size_t c = 0; wanted && c < chains.chains.size(); ++c) {
      if (s.side_cone[0].empty() && s.side_cone[1].empty()) break;
      s.united.clear();
      blocked_by_chain(chains, c, from, s.outside_hull[c] != 0, s, s.united);  // once for both sides
      if (s.united.empty()) continue;
      s.visible.clear();  // built when a side needs it: the gaps between the blocked wedges
      bool gaps_built = false;
      for (std::vector<Wedge>& cone : s.side_cone) {
        if (cone.empty() || (s.united.size() == 1 && !overlaps(s.united.front(), cone))) continue;
        if (s.united.size() == 1 && s.united.front().width > kAngleTolerance) {  // one range: cut it out
          s.out.clear();
          for (const Wedge& w : cone) subtract_wedge(w, s.united.front(), s.out);
          std::sort(s.out.begin(), s.out.end(),
                    [](const Wedge& a, const Wedge& b) { return a.start < b.start; });
          cone.swap(s.out);
          continue;
        }
        if (!gaps_built) {  // every gap between the blocked wedges (sorted; the last may wrap past 2pi)
          for (std::size_t i = 0; i < s.united.size(); ++i) {
            const Wedge& w = s.united[i];
            const Wedge& next = s.united[(i + 1) % s.united.size()];
            double gap = next.start - w.end();
            while (gap < 0) gap += kTwoPi;
            if (s.united.size() == 1) gap = kTwoPi - w.width;
            if (gap > kAngleTolerance)
              s.visible.push_back({wrap_angle(w.end()), gap, w.end_reach, next.start_reach});
          }
          gaps_built = true;
        }
        if (s.visible.empty()) {  // blocked all round
          cone.clear();
          continue;
        }
        s.out.clear();
        intersect_wedges(cone, s.visible, s.wedges, s.out);
        cone.swap(s.out);
      }
    }
    for (const std::vector<Wedge>& cone : s.side_cone) {
      s.wedges_out.insert(s.wedges_out.end(), cone.begin(), cone.end());
      s.offsets_out.push_back(static_cast<std::uint32_t>(s.wedges_out.size()));
    }
  }
  cones.wedges.swap(s.wedges_out);
  cones.offsets.swap(s.offsets_out);
}

}  // namespace pleat
