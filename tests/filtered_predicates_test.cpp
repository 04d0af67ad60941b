// cgal::orientation and cgal::side_of_oriented_circle (static_core/filtered_predicates.hpp) against CGAL's
// EPICK predicates, the oracle: the same sign on random points at every scale, on nearly degenerate input
// (points a few ulps off a line or a circle, where the filter must hand over), on exactly degenerate input
// (collinear and cocircular points on a grid, repeated points) and on points of the real cloth's scale far
// from the origin, where differences are inexact. A filter that decided one sign wrongly fails here.
#include "static_core/internal/filtered_predicates.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <vector>

namespace pleat {
namespace {

using Point = CGAL::Epick::Point_2;

/// A double of random magnitude (2^-40 .. 2^40) and sign, or 0.
double any_double() {
  const int exponent = *rc::gen::inRange(-40, 41);
  const double mantissa = *rc::gen::inRange(-(1 << 26), 1 << 26) / double(1 << 26);
  return std::ldexp(mantissa, exponent);
}

/// A point at a random offset of up to `spread` around `center`, snapped to a grid of `step` when given.
Point near(const Point& center, double spread, double step = 0.0) {
  double x = center.x() + spread * (*rc::gen::inRange(-1000000, 1000001) / 1e6);
  double y = center.y() + spread * (*rc::gen::inRange(-1000000, 1000001) / 1e6);
  if (step > 0.0) x = std::round(x / step) * step, y = std::round(y / step) * step;
  return {x, y};
}

/// Moves p by a few ulps in each coordinate.
Point nudge(const Point& p) {
  double x = p.x(), y = p.y();
  for (int i = *rc::gen::inRange(0, 4); i > 0; --i)
    x = std::nextafter(x, *rc::gen::arbitrary<bool>() ? 1e300 : -1e300);
  for (int i = *rc::gen::inRange(0, 4); i > 0; --i)
    y = std::nextafter(y, *rc::gen::arbitrary<bool>() ? 1e300 : -1e300);
  return {x, y};
}

void expect_same(const Point& p, const Point& q, const Point& r) {
  RC_ASSERT(cgal::orientation(p, q, r) == CGAL::orientation(p, q, r));
  cgal::FilteredKernel kernel;
  RC_ASSERT(kernel.orientation_2_object()(p, q, r) == CGAL::orientation(p, q, r));
}

void expect_same(const Point& p, const Point& q, const Point& r, const Point& t) {
  RC_ASSERT(cgal::side_of_oriented_circle(p, q, r, t) == CGAL::side_of_oriented_circle(p, q, r, t));
  cgal::FilteredKernel kernel;
  RC_ASSERT(kernel.side_of_oriented_circle_2_object()(p, q, r, t) ==
            CGAL::side_of_oriented_circle(p, q, r, t));
}

RC_GTEST_PROP(FilteredPredicates, AgreeWithCgalOnRandomPointsAtEveryScale, ()) {
  for (int i = 0; i < 16; ++i) {
    const Point p(any_double(), any_double()), q(any_double(), any_double()), r(any_double(), any_double()),
        t(any_double(), any_double());
    expect_same(p, q, r);
    expect_same(p, q, r, t);
  }
}

RC_GTEST_PROP(FilteredPredicates, AgreeWithCgalOnNearlyCollinearPointsFarFromTheOrigin, ()) {
  // A line through a point of cloth scale (or far out), three points on it rounded, then nudged by ulps.
  const Point o(*rc::gen::inRange(-1000, 1000) + 0.1234567, *rc::gen::inRange(-1000, 1000) - 0.7654321);
  const double dx = any_double(), dy = any_double();
  auto on_line = [&](double s) { return Point(o.x() + s * dx, o.y() + s * dy); };
  const Point p = on_line(*rc::gen::inRange(-100, 100) / 7.0),
              q = on_line(*rc::gen::inRange(-100, 100) / 3.0),
              r = on_line(*rc::gen::inRange(-100, 100) / 11.0);
  for (int i = 0; i < 64; ++i) {  // many nudges per line: most triples are decided by the last bits
    const Point a = nudge(p), b = nudge(q), c = nudge(r);
    expect_same(a, b, c);
    expect_same(b, c, a);
  }
}

RC_GTEST_PROP(FilteredPredicates, AgreeWithCgalOnNearlyCollinearNearbyPoints, ()) {
  // A flat stretch of cloth cut by a plane: points a few edge lengths apart on a line at cloth scale, off it
  // by a few ulps. The coordinate differences are exact, so the second stages decide most of these.
  const Point o(*rc::gen::inRange(-1000, 1000) * 0.013 + 0.5, *rc::gen::inRange(-1000, 1000) * 0.007 - 0.25);
  const double angle = *rc::gen::inRange(0, 6283) / 1000.0;
  const double step = std::ldexp(1.0, *rc::gen::inRange(-30, -4));
  auto on_line = [&](int k) {
    return Point(o.x() + k * step * std::cos(angle), o.y() + k * step * std::sin(angle));
  };
  const Point p = on_line(*rc::gen::inRange(-8, 9)), q = on_line(*rc::gen::inRange(-8, 9)),
              r = on_line(*rc::gen::inRange(-8, 9)), t = on_line(*rc::gen::inRange(-8, 9));
  for (int i = 0; i < 64; ++i) {
    const Point a = nudge(p), b = nudge(q), c = nudge(r), d = nudge(t);
    expect_same(a, b, c);
    expect_same(c, a, b);
    expect_same(a, b, c, d);  // four points nearly on a line: the in-circle test's hardest case
  }
}

RC_GTEST_PROP(FilteredPredicates, AgreeWithCgalOnLatticePointsWithInexactDifferences, ()) {
  // Two points far out (about 2^57, on a lattice of 256) on a line through the origin, and a third near the
  // origin, off that line by a lattice step or none: the differences are rounded, and the determinant,
  // 256 (n - m) cross(d, r), can be as small as eps^2 times its products, where only a correct bound on the
  // rounding errors keeps the second stage exact.
  const double dx = *rc::gen::inRange(-5, 6), dy = *rc::gen::inRange(1, 6);
  const double m = std::ldexp(1.0, 48) + *rc::gen::inRange(0, 1 << 20);
  const double n = m + *rc::gen::inRange(-4, 5);
  const double k = *rc::gen::inRange(-100, 101);
  const double l = m + *rc::gen::inRange(-4, 5);
  const Point p(256.0 * m * dx, 256.0 * m * dy), q(256.0 * n * dx, 256.0 * n * dy),
      s(256.0 * l * dx + 256.0 * *rc::gen::inRange(-1, 2), 256.0 * l * dy);
  const Point r(k * dx + *rc::gen::inRange(-1, 2), k * dy + *rc::gen::inRange(-1, 2));
  expect_same(p, q, r);
  expect_same(q, r, p);
  expect_same(r, p, q);
  expect_same(p, q, s, r);  // four points nearly on a line, three far out: the in-circle test's second stage
  expect_same(r, p, q, s);
}

RC_GTEST_PROP(FilteredPredicates, AgreeWithCgalOnNearlyCocircularPoints, ()) {
  // Four points on a circle (angles rounded), nudged by ulps: the in-circle sign hangs on the last bits.
  const Point c(*rc::gen::inRange(-1000, 1000) * 0.37, *rc::gen::inRange(-1000, 1000) * 0.91);
  const double radius = std::ldexp(1.0 + *rc::gen::inRange(0, 1000) / 1000.0, *rc::gen::inRange(-20, 10));
  std::vector<Point> points;
  for (int i = 0; i < 4; ++i) {
    const double angle = *rc::gen::inRange(0, 6283) / 1000.0;
    points.emplace_back(c.x() + radius * std::cos(angle), c.y() + radius * std::sin(angle));
  }
  for (int i = 0; i < 64; ++i) {  // many nudges per circle
    const Point a = nudge(points[0]), b = nudge(points[1]), d = nudge(points[2]), e = nudge(points[3]);
    expect_same(a, b, d, e);
    expect_same(a, b, d);
  }
}

RC_GTEST_PROP(FilteredPredicates, AgreeWithCgalOnExactlyDegenerateGridPoints, ()) {
  // Points on a coarse grid: collinear triples, cocircular quadruples and repeated points are common.
  const double step = std::ldexp(1.0, *rc::gen::inRange(-30, 10));
  const Point o(std::round(*rc::gen::inRange(-50, 50) * 1.37) * step, *rc::gen::inRange(-50, 50) * step);
  const Point p = near(o, 3 * step, step), q = near(o, 3 * step, step), r = near(o, 3 * step, step),
              t = near(o, 3 * step, step);
  expect_same(p, q, r);
  expect_same(p, q, r, t);
  expect_same(p, p, q);
  expect_same(p, q, p, r);
}

TEST(FilteredPredicates, DecideKnownCases) {
  const Point a(0, 0), b(1, 0), c(0, 1), d(1, 1), e(0.25, 0.25), f(2, 2);
  EXPECT_EQ(cgal::orientation(a, b, c), CGAL::LEFT_TURN);
  EXPECT_EQ(cgal::orientation(a, c, b), CGAL::RIGHT_TURN);
  EXPECT_EQ(cgal::orientation(a, d, f), CGAL::COLLINEAR);
  EXPECT_EQ(cgal::side_of_oriented_circle(a, b, c, e), CGAL::ON_POSITIVE_SIDE);
  EXPECT_EQ(cgal::side_of_oriented_circle(a, b, c, f), CGAL::ON_NEGATIVE_SIDE);
  EXPECT_EQ(cgal::side_of_oriented_circle(a, b, c, d), CGAL::ON_ORIENTED_BOUNDARY);
  EXPECT_EQ(cgal::side_of_oriented_circle(a, c, b, e), CGAL::ON_NEGATIVE_SIDE);
  // Far from the origin, 0.1 apart: the differences are rounded, the decisions still exact.
  const Point g(1e6 + 0.1, 1e6), h(1e6 + 0.2, 1e6 + 0.1), k(1e6 + 0.3, 1e6 + 0.2);
  EXPECT_EQ(cgal::orientation(g, h, k), CGAL::orientation(g, h, k));
  // Tiny sums go to CGAL.
  const Point s(1e-200, 0), u(0, 1e-200);
  EXPECT_EQ(cgal::orientation(a, s, u), CGAL::LEFT_TURN);
}

}  // namespace
}  // namespace pleat
