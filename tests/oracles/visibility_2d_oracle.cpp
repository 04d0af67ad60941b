#include "oracles/visibility_2d_oracle.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cmath>

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
    std::vector<double> incident;  // angles of chain edges leaving X
    std::vector<Wedge> blocked;
    for (const SliceEdge& e : slice.edges) {
      const P a = point(slice, e.from), b = point(slice, e.to);
      if (a == b) continue;
      if (a == X || b == X) {
        incident.push_back(direction_angle(dir(X, a == X ? b : a)));
        continue;
      }
      const CGAL::Orientation o = CGAL::orientation(X, a, b);
      if (o == CGAL::COLLINEAR) {
        if (CGAL::collinear_are_strictly_ordered_along_line(a, X, b)) {  // the edge passes through X
          incident.push_back(direction_angle(dir(X, a)));
          incident.push_back(direction_angle(dir(X, b)));
        }
        continue;  // otherwise seen edge-on: a single direction
      }
      blocked.push_back(o == CGAL::LEFT_TURN ? thin_wedge_between(dir(X, a), dir(X, b)) : thin_wedge_between(dir(X, b), dir(X, a)));
    }
    const AngularSet visible = AngularSet::from_wedges(blocked).complement();
    // The range counter-clockwise of angle `from`, up to the next incident chain edge.
    auto range_ccw_of = [&](double from) {
      double best = kTwoPi;
      for (double a : incident) {
        double d = wrap_angle(a - from);
        if (d > kAngleTolerance && d < best) best = d;
      }
      return AngularSet::from_wedges({{from, best}});
    };
    auto range_cw_of = [&](double to) {
      double best = kTwoPi;
      for (double a : incident) {
        double d = wrap_angle(to - a);
        if (d > kAngleTolerance && d < best) best = d;
      }
      return AngularSet::from_wedges({{wrap_angle(to - best), best}});
    };
    const int next = next_distinct(slice, x, true), prev = next_distinct(slice, x, false);
    for (Side side : kBothSides) {
      const int ccw_of = side == Side::Front ? next : prev;
      const int cw_of = side == Side::Front ? prev : next;
      AngularSet range = AngularSet::full();
      if (ccw_of >= 0) range = range_ccw_of(direction_angle(dir(X, point(slice, ccw_of))));
      else if (cw_of >= 0) range = range_cw_of(direction_angle(dir(X, point(slice, cw_of))));
      result[x][static_cast<int>(side)] = range.intersect(visible);
    }
  }
  return result;
}

}  // namespace pleat::oracle
