#include "static_core/filtered_predicates.hpp"

namespace pleat::cgal {

namespace {

// Error-free transformations (Shewchuk 1997, §2): a + b = s + e and a * b = p + e exactly, in round-to-
// nearest double arithmetic without overflow or underflow.

/// s = fl(a + b) and its rounding error e, so that a + b = s + e.
void two_sum(double a, double b, double& s, double& e) {
  s = a + b;
  const double b_virtual = s - a;
  const double a_virtual = s - b_virtual;
  e = (a - a_virtual) + (b - b_virtual);
}

/// Whether fl(a - b) is a - b exactly.
bool exact_difference(double a, double b) {
  const double d = a - b;
  const double b_virtual = a - d;
  const double a_virtual = d + b_virtual;
  return a - a_virtual == 0.0 && b_virtual - b == 0.0;
}

/// a = high + low with each half of at most 26 significant bits (Veltkamp's split).
void split(double a, double& high, double& low) {
  const double c = 134217729.0 * a;  // 2^27 + 1
  high = c - (c - a);
  low = a - high;
}

/// p = fl(a * b) and its rounding error e, so that a * b = p + e (Dekker's product; no FMA needed).
void two_product(double a, double b, double& p, double& e) {
  p = a * b;
  double ah = 0, al = 0, bh = 0, bl = 0;
  split(a, ah, al);
  split(b, bh, bl);
  e = al * bl - (((p - ah * bh) - al * bh) - ah * bl);
}

/// Zero, or a magnitude whose products and their errors stay normal doubles and whose split cannot overflow.
bool moderate(double d) {
  const double m = std::abs(d);
  return m == 0.0 || (m >= 0x1p-400 && m <= 0x1p+400);
}

}  // namespace

std::optional<CGAL::Orientation> orientation_of_exact_differences(double ax, double ay, double bx, double by,
                                                                  double cx, double cy) {
  if (!exact_difference(ax, cx) || !exact_difference(ay, cy) || !exact_difference(bx, cx) ||
      !exact_difference(by, cy))
    return std::nullopt;
  const double acx = ax - cx, acy = ay - cy, bcx = bx - cx, bcy = by - cy;
  if (!moderate(acx) || !moderate(acy) || !moderate(bcx) || !moderate(bcy)) return std::nullopt;
  // acx * bcy - acy * bcx = (l1 + l0) - (r1 + r0) exactly; grown into a nonoverlapping expansion (Shewchuk's
  // Grow-Expansion: components in increasing magnitude, zeros aside), whose sign is its largest component's.
  double l1 = 0, l0 = 0, r1 = 0, r0 = 0;
  two_product(acx, bcy, l1, l0);
  two_product(acy, bcx, r1, r0);
  double h[4] = {l0, l1, 0.0, 0.0};
  std::size_t size = 2;
  for (const double b : {-r0, -r1}) {
    double q = b;
    for (std::size_t i = 0; i < size; ++i) two_sum(q, h[i], q, h[i]);
    h[size++] = q;
  }
  for (std::size_t i = size; i-- > 0;)
    if (h[i] != 0.0) return h[i] > 0.0 ? CGAL::LEFT_TURN : CGAL::RIGHT_TURN;
  return CGAL::COLLINEAR;
}

CGAL::Orientation orientation_beyond_filter(const CGAL::Epick::Point_2& p, const CGAL::Epick::Point_2& q,
                                            const CGAL::Epick::Point_2& r) {
  if (const auto exact = orientation_of_exact_differences(p.x(), p.y(), q.x(), q.y(), r.x(), r.y()))
    return *exact;
  return CGAL::orientation(p, q, r);
}

CGAL::Oriented_side side_of_oriented_circle_beyond_filter(const CGAL::Epick::Point_2& p,
                                                          const CGAL::Epick::Point_2& q,
                                                          const CGAL::Epick::Point_2& r,
                                                          const CGAL::Epick::Point_2& t) {
  return CGAL::side_of_oriented_circle(p, q, r, t);
}

}  // namespace pleat::cgal
