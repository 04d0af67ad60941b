// The two exact predicates of the slices' planar structure — orientation of three points and in-circle of
// four — with a cheaper floating-point filter in front of CGAL's.
//
// Each evaluates its determinant once in double precision and compares it with Shewchuk's a-priori error
// bound (stage A of orient2d and incircle: J. R. Shewchuk, "Adaptive precision floating-point arithmetic
// and fast robust geometric predicates", Discrete Comput. Geom. 18, 1997, §4.2-4.3): beyond the bound the
// sign of the rounded determinant is the exact sign. Where it is not, the call goes to CGAL's filtered
// predicate (EPICK: semi-static filter, interval arithmetic, then exact arithmetic), so every answer is the
// exact one; the filter only decides sooner (no maxima, no sorting, no range checks) on the many calls that
// are far from degenerate. Sums below 1e-250 (where underflow could spoil the bound) go to CGAL too.
// Both have a second stage before CGAL. Orientation sums its 2x2 determinant of the rounded differences
// exactly from error-free products (Shewchuk's stage B), which is the answer where the differences are
// exact, as between nearby points, and adds the differences' rounding errors with a bound where they are
// not (his stage C). The in-circle test takes its three 2x2 determinants so (with the differences' errors
// to first order) and bounds the rest. Nearly collinear points (a flat stretch of cloth cut by a plane) are
// then decided without interval or multiprecision arithmetic.
// tests/filtered_predicates_test.cpp compares both with CGAL on random, near-degenerate and degenerate
// input.
#pragma once

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <cmath>

namespace pleat::cgal {

namespace predicates_detail {
inline constexpr double kEpsilon = 1.1102230246251565e-16;  // 2^-53: half an ulp of 1
inline constexpr double kOrientBound = (3.0 + 16.0 * kEpsilon) * kEpsilon;
inline constexpr double kInCircleBound = (10.0 + 96.0 * kEpsilon) * kEpsilon;
inline constexpr double kSmallestSum = 1e-250;
}  // namespace predicates_detail

/// Where the first stages cannot decide (out of line, so that the filters inline at every call):
/// the second stage (filtered_predicates.cpp), then CGAL.
CGAL::Orientation orientation_beyond_filter(const CGAL::Epick::Point_2& p, const CGAL::Epick::Point_2& q,
                                            const CGAL::Epick::Point_2& r);
CGAL::Oriented_side side_of_oriented_circle_beyond_filter(const CGAL::Epick::Point_2& p,
                                                          const CGAL::Epick::Point_2& q,
                                                          const CGAL::Epick::Point_2& r,
                                                          const CGAL::Epick::Point_2& t);

/// CGAL::orientation(p, q, r), exactly: LEFT_TURN when p, q, r turn counter-clockwise.
inline CGAL::Orientation orientation(const CGAL::Epick::Point_2& p, const CGAL::Epick::Point_2& q,
                                     const CGAL::Epick::Point_2& r) {
  using namespace predicates_detail;
  const double left = (p.x() - r.x()) * (q.y() - r.y());
  const double right = (p.y() - r.y()) * (q.x() - r.x());
  const double det = left - right;
  const double sum = std::abs(left) + std::abs(right);
  const double bound = kOrientBound * sum;
  if (sum >= kSmallestSum) {  // false for NaN and infinite sums too: CGAL decides those
    if (det > bound) return CGAL::LEFT_TURN;
    if (-det > bound) return CGAL::RIGHT_TURN;
  }
  return orientation_beyond_filter(p, q, r);
}

/// CGAL::side_of_oriented_circle(p, q, r, t), exactly: ON_POSITIVE_SIDE when t lies inside the circle
/// through p, q, r and they turn counter-clockwise (or outside it and they turn clockwise).
inline CGAL::Oriented_side side_of_oriented_circle(const CGAL::Epick::Point_2& p,
                                                   const CGAL::Epick::Point_2& q,
                                                   const CGAL::Epick::Point_2& r,
                                                   const CGAL::Epick::Point_2& t) {
  using namespace predicates_detail;
  const double adx = p.x() - t.x(), ady = p.y() - t.y();
  const double bdx = q.x() - t.x(), bdy = q.y() - t.y();
  const double cdx = r.x() - t.x(), cdy = r.y() - t.y();
  const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  const double cdxady = cdx * ady, adxcdy = adx * cdy;
  const double adxbdy = adx * bdy, bdxady = bdx * ady;
  const double alift = adx * adx + ady * ady;
  const double blift = bdx * bdx + bdy * bdy;
  const double clift = cdx * cdx + cdy * cdy;
  const double det = alift * (bdxcdy - cdxbdy) + blift * (cdxady - adxcdy) + clift * (adxbdy - bdxady);
  const double permanent = (std::abs(bdxcdy) + std::abs(cdxbdy)) * alift +
                           (std::abs(cdxady) + std::abs(adxcdy)) * blift +
                           (std::abs(adxbdy) + std::abs(bdxady)) * clift;
  const double bound = kInCircleBound * permanent;
  if (permanent >= kSmallestSum) {
    if (det > bound) return CGAL::ON_POSITIVE_SIDE;
    if (-det > bound) return CGAL::ON_NEGATIVE_SIDE;
  }
  return side_of_oriented_circle_beyond_filter(p, q, r, t);
}

/// EPICK with the two predicates above: the geometric traits of the slices' triangulations (every other
/// predicate and construction is EPICK's own).
struct FilteredKernel : CGAL::Epick {
  struct Orientation_2 {
    using result_type = CGAL::Orientation;
    CGAL::Orientation operator()(const Point_2& p, const Point_2& q, const Point_2& r) const {
      return orientation(p, q, r);
    }
  };
  struct Side_of_oriented_circle_2 {
    using result_type = CGAL::Oriented_side;
    CGAL::Oriented_side operator()(const Point_2& p, const Point_2& q, const Point_2& r,
                                   const Point_2& t) const {
      return side_of_oriented_circle(p, q, r, t);
    }
  };
  Orientation_2 orientation_2_object() const { return {}; }
  Side_of_oriented_circle_2 side_of_oriented_circle_2_object() const { return {}; }
};

}  // namespace pleat::cgal
