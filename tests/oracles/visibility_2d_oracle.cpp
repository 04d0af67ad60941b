#include "oracles/visibility_2d_oracle.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace pleat::oracle {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using P = K::Point_2;

P point(const Slice& s, Index v) { return {s.vertices[v].point.x, s.vertices[v].point.y}; }
glm::dvec2 dir(const P& a, const P& b) { return {b.x() - a.x(), b.y() - a.y()}; }

int next_distinct(const Slice& s, Index x, bool forward) {
  const P at = point(s, x);
  Index y = x;
  for (std::size_t steps = 0; steps <= s.vertices.size(); ++steps) {
    const std::int32_t e = forward ? s.out_edge[y] : s.in_edge[y];
    if (e < 0) return -1;
    y = forward ? s.edges[e].to : s.edges[e].from;
    if (point(s, y) != at) return static_cast<int>(y);
  }
  return -1;
}

}  // namespace

std::vector<std::array<AngularSet, 2>> brute_force_slice_cones(const Slice& slice) {
  std::vector<std::array<AngularSet, 2>> result(slice.vertices.size());
  for (Index x = 0; x < slice.vertices.size(); ++x) {
    const P X = point(slice, x);
    std::vector<P> incident;  // the far ends of chain edges leaving X
    std::vector<Wedge> blocked;
    for (const SliceEdge& e : slice.edges) {
      const P a = point(slice, e.from), b = point(slice, e.to);
      if (a == b) continue;
      if (a == X || b == X) {
        incident.push_back(a == X ? b : a);
        continue;
      }
      const CGAL::Orientation o = CGAL::orientation(X, a, b);
      if (o == CGAL::COLLINEAR) {
        if (CGAL::collinear_are_strictly_ordered_along_line(a, X, b)) {  // the edge passes through X
          incident.push_back(a);
          incident.push_back(b);
        }
        continue;  // otherwise seen edge-on: a single direction
      }
      blocked.push_back(o == CGAL::LEFT_TURN ? thin_wedge_between(dir(X, a), dir(X, b))
                                             : thin_wedge_between(dir(X, b), dir(X, a)));
    }
    const AngularSet visible = AngularSet::from_wedges(blocked).complement();
    // Ranges between chain edges, decided exactly (two arms 1e-16 apart are distinct edges): the first
    // incident direction counter-clockwise (or clockwise) of the one through F, other than F's own.
    auto same_direction = [&](const P& p, const P& q) {
      return CGAL::orientation(X, p, q) == CGAL::COLLINEAR && CGAL::angle(p, X, q) == CGAL::ACUTE;
    };
    // Strict order of directions counter-clockwise from F: F's half-turn [F, -F) first, then the rest.
    auto ccw_before = [&](const P& F, const P& p, const P& q) {
      auto half = [&](const P& d) {
        const CGAL::Orientation o = CGAL::orientation(X, F, d);
        return o == CGAL::LEFT_TURN || (o == CGAL::COLLINEAR && same_direction(F, d)) ? 0 : 1;
      };
      const int hp = half(p), hq = half(q);
      if (hp != hq) return hp < hq;
      return CGAL::orientation(X, p, q) == CGAL::LEFT_TURN;
    };
    // The wedge counter-clockwise from the direction of p to that of q (q = p's direction: the full turn).
    auto wedge_from_to = [&](const P& p, const P& q) -> Wedge {
      switch (CGAL::orientation(X, p, q)) {
        case CGAL::LEFT_TURN:
          return thin_wedge_between(dir(X, p), dir(X, q));
        case CGAL::RIGHT_TURN:
          return wedge_between(dir(X, p), dir(X, q));
        default:
          return {direction_angle(dir(X, p)), same_direction(p, q) ? kTwoPi : kTwoPi / 2};
      }
    };
    auto range_ccw_of = [&](const P& F) {
      const P* best = nullptr;
      for (const P& q : incident)
        if (!same_direction(F, q) && (!best || ccw_before(F, q, *best))) best = &q;
      return AngularSet::from_wedges({best ? wedge_from_to(F, *best) : Wedge{0.0, kTwoPi}});
    };
    auto range_cw_of = [&](const P& T) {
      const P* best = nullptr;
      for (const P& q : incident)
        if (!same_direction(T, q) && (!best || ccw_before(T, *best, q)))
          best = &q;  // the last ccw = first cw
      return AngularSet::from_wedges({best ? wedge_from_to(*best, T) : Wedge{0.0, kTwoPi}});
    };
    const int next = next_distinct(slice, x, true), prev = next_distinct(slice, x, false);
    for (Side side : kBothSides) {
      const int ccw_of = side == Side::Front ? next : prev;
      const int cw_of = side == Side::Front ? prev : next;
      AngularSet range = AngularSet::full();
      if (ccw_of >= 0)
        range = range_ccw_of(point(slice, ccw_of));
      else if (cw_of >= 0)
        range = range_cw_of(point(slice, cw_of));
      result[x][static_cast<int>(side)] = range.intersect(visible);
    }
  }
  return result;
}

double angular_difference(const AngularSet& a, const AngularSet& b) {
  return a.subtract(b).measure() + b.subtract(a).measure();
}

std::string first_mismatch(const Slice& slice, const SliceCones& cones,
                           const std::vector<std::array<AngularSet, 2>>& expected, const std::string& who) {
  auto describe = [](const AngularSet& set) {
    std::ostringstream out;
    for (const Wedge& w : set.wedges()) out << "[" << w.start << " +" << w.width << "] ";
    return out.str();
  };
  for (Index x = 0; x < slice.vertices.size(); ++x)
    for (Side side : kBothSides) {
      const auto span = cones.cone(x, side);
      const AngularSet fast = AngularSet::from_wedges({span.begin(), span.end()});
      const AngularSet& slow = expected[x][static_cast<int>(side)];
      if (angular_difference(fast, slow) > 1e-9) {
        std::ostringstream out;
        out << "slice vertex " << x << " at (" << slice.vertices[x].point.x << ", "
            << slice.vertices[x].point.y << ") side " << static_cast<int>(side) << ": " << who << " "
            << describe(fast) << " oracle " << describe(slow) << " (" << slice.vertices.size()
            << " vertices, " << slice.edges.size() << " edges)";
        return out.str();
      }
    }
  return {};
}

}  // namespace pleat::oracle
