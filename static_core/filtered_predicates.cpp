#include "static_core/internal/filtered_predicates.hpp"

#include <optional>

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

/// The rounding error of d = fl(a - b): a - b = d + tail exactly (Shewchuk's Two-Diff).
double difference_tail(double a, double b, double d) {
  const double b_virtual = a - d;
  const double a_virtual = d + b_virtual;
  return (a - a_virtual) + (b_virtual - b);
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

/// Zero, or a magnitude whose products (two for orientation: up to 2^±400; four for the in-circle test: up
/// to 2^±200) and their errors stay normal doubles and whose split cannot overflow.
bool moderate(double d, double limit) {
  const double m = std::abs(d);
  return m == 0.0 || (m >= 1.0 / limit && m <= limit);
}

/// a * b - c * d exactly, as a nonoverlapping expansion h[0..3] in increasing magnitude (zero components
/// kept): two error-free products grown into one (Shewchuk's Grow-Expansion, twice).
void exact_products_difference(double a, double b, double c, double d, double h[4]) {
  double y1 = 0, y0 = 0;
  two_product(a, b, h[1], h[0]);
  two_product(c, d, y1, y0);
  int size = 2;
  for (const double v : {-y0, -y1}) {
    double q = v;
    for (int i = 0; i < size; ++i) two_sum(q, h[i], q, h[i]);
    h[size++] = q;
  }
}

/// The sign of an expansion: its largest nonzero component's.
int sign_of(const double h[4]) {
  for (int i = 4; i-- > 0;)
    if (h[i] != 0.0) return h[i] > 0.0 ? 1 : -1;
  return 0;
}

/// The expansion's value, rounded: within 3.01 epsilon of it (the partial sums never exceed it much).
double approximate(const double h[4]) { return ((h[0] + h[1]) + h[2]) + h[3]; }

/// The sign of (ax - cx)(by - cy) - (ay - cy)(bx - cx), exactly, from the determinant of the rounded
/// differences summed exactly and, where a difference was rounded, its error terms bounded; std::nullopt
/// where that cannot decide.
std::optional<CGAL::Orientation> orientation_second_stage(double ax, double ay, double bx, double by,
                                                          double cx, double cy) {
  const double acx = ax - cx, acy = ay - cy, bcx = bx - cx, bcy = by - cy;
  for (const double d : {acx, acy, bcx, bcy})
    if (!moderate(d, 0x1p+400)) return std::nullopt;
  // B: the determinant of the rounded differences, exactly (Shewchuk's stage B).
  double h[4];
  exact_products_difference(acx, bcy, acy, bcx, h);
  const double acx_tail = difference_tail(ax, cx, acx), acy_tail = difference_tail(ay, cy, acy),
               bcx_tail = difference_tail(bx, cx, bcx), bcy_tail = difference_tail(by, cy, bcy);
  if (acx_tail == 0.0 && acy_tail == 0.0 && bcx_tail == 0.0 && bcy_tail == 0.0) {
    const int sign = sign_of(h);
    return sign > 0 ? CGAL::LEFT_TURN : sign < 0 ? CGAL::RIGHT_TURN : CGAL::COLLINEAR;
  }
  // Inexact differences (each difference = rounded + tail exactly, |tail| <= eps |rounded|): the exact
  // determinant is B + T1 + T2, T1 the four products of a rounded difference and a tail, |T2| <= eps^2 S
  // (S = |acx bcy| + |acy bcx|). With B rounded (3.01 eps |B|), T1 rounded (6.1 eps^2 S) and their sum
  // rounded (eps), |det - exact| <= 4.02 eps |det| + 13.3 eps^2 S: beyond twice that, det's sign is exact
  // (Shewchuk's stage C, with bounds of our own derivation). Sums so small that underflow could matter go on.
  const double sum = std::abs(acx * bcy) + std::abs(acy * bcx);
  if (!(sum >= predicates_detail::kSmallestSum)) return std::nullopt;
  const double t1 = (acx * bcy_tail + bcy * acx_tail) - (acy * bcx_tail + bcx * acy_tail);
  const double det = approximate(h) + t1;
  constexpr double eps = predicates_detail::kEpsilon;
  const double bound = 8.0 * eps * std::abs(det) + 32.0 * eps * eps * sum;
  if (det > bound) return CGAL::LEFT_TURN;
  if (-det > bound) return CGAL::RIGHT_TURN;
  return std::nullopt;
}

/// The in-circle sign, where it can be decided from the three 2x2 determinants of the rounded differences
/// summed exactly, with the differences' rounding errors to first order and a bound on the rest;
/// std::nullopt otherwise.
std::optional<CGAL::Oriented_side> side_of_oriented_circle_second_stage(const CGAL::Epick::Point_2& p,
                                                                        const CGAL::Epick::Point_2& q,
                                                                        const CGAL::Epick::Point_2& r,
                                                                        const CGAL::Epick::Point_2& t) {
  const double adx = p.x() - t.x(), ady = p.y() - t.y(), bdx = q.x() - t.x(), bdy = q.y() - t.y(),
               cdx = r.x() - t.x(), cdy = r.y() - t.y();
  for (const double d : {adx, ady, bdx, bdy, cdx, cdy})
    if (!moderate(d, 0x1p+200)) return std::nullopt;
  const double adx_tail = difference_tail(p.x(), t.x(), adx), ady_tail = difference_tail(p.y(), t.y(), ady),
               bdx_tail = difference_tail(q.x(), t.x(), bdx), bdy_tail = difference_tail(q.y(), t.y(), bdy),
               cdx_tail = difference_tail(r.x(), t.x(), cdx), cdy_tail = difference_tail(r.y(), t.y(), cdy);
  const bool exact = adx_tail == 0.0 && ady_tail == 0.0 && bdx_tail == 0.0 && bdy_tail == 0.0 &&
                     cdx_tail == 0.0 && cdy_tail == 0.0;
  // det = la ca + lb cb + lc cc: lifts la = adx^2 + ady^2 ..., and the 2x2 determinants ca = bdx cdy - cdx
  // bdy, cb = cdx ady - adx cdy, cc = adx bdy - bdx ady, where nearly collinear points cancel everything the
  // first stage had. Each 2x2 determinant of the rounded differences is summed exactly, plus its first-order
  // terms in the differences' rounding errors (|tail| <= eps |difference|); the lifts are those of the
  // rounded differences. With P_k the two products of determinant k and L_k its lift, every rounding and
  // every neglected term together is at most 11.2 eps sum |t_k| + 13.3 eps^2 sum L_k P_k (8.05 eps sum |t_k|
  // where the differences are exact): beyond twice that, det's sign is exact. Where the differences are exact
  // and all three determinants 0, so is det.
  double bc[4], ca[4], ab[4];
  exact_products_difference(bdx, cdy, cdx, bdy, bc);
  exact_products_difference(cdx, ady, adx, cdy, ca);
  exact_products_difference(adx, bdy, bdx, ady, ab);
  const double la = adx * adx + ady * ady, lb = bdx * bdx + bdy * bdy, lc = cdx * cdx + cdy * cdy;
  // t_k: lift times determinant with its first-order tail terms (exactly 0 where the differences are exact).
  const double ta =
      la * (approximate(bc) + ((bdx * cdy_tail + cdy * bdx_tail) - (cdx * bdy_tail + bdy * cdx_tail)));
  const double tb =
      lb * (approximate(ca) + ((cdx * ady_tail + ady * cdx_tail) - (adx * cdy_tail + cdy * adx_tail)));
  const double tc =
      lc * (approximate(ab) + ((adx * bdy_tail + bdy * adx_tail) - (bdx * ady_tail + ady * bdx_tail)));
  constexpr double eps = predicates_detail::kEpsilon;
  double margin = 0.0;
  if (!exact) {
    const double permanent = la * (std::abs(bdx * cdy) + std::abs(cdx * bdy)) +
                             lb * (std::abs(cdx * ady) + std::abs(adx * cdy)) +
                             lc * (std::abs(adx * bdy) + std::abs(bdx * ady));
    if (!(permanent >= predicates_detail::kSmallestSum)) return std::nullopt;  // where underflow could matter
    margin = 32.0 * eps * eps * permanent;
  }
  const double det = (ta + tb) + tc;
  const double bound = (exact ? 16.0 : 24.0) * eps * (std::abs(ta) + std::abs(tb) + std::abs(tc)) + margin;
  if (det > bound) return CGAL::ON_POSITIVE_SIDE;
  if (-det > bound) return CGAL::ON_NEGATIVE_SIDE;
  if (exact && sign_of(bc) == 0 && sign_of(ca) == 0 && sign_of(ab) == 0) return CGAL::ON_ORIENTED_BOUNDARY;
  return std::nullopt;
}

}  // namespace

CGAL::Orientation orientation_beyond_filter(const CGAL::Epick::Point_2& p, const CGAL::Epick::Point_2& q,
                                            const CGAL::Epick::Point_2& r) {
  if (const auto exact = orientation_second_stage(p.x(), p.y(), q.x(), q.y(), r.x(), r.y())) return *exact;
  return CGAL::orientation(p, q, r);
}

CGAL::Oriented_side side_of_oriented_circle_beyond_filter(const CGAL::Epick::Point_2& p,
                                                          const CGAL::Epick::Point_2& q,
                                                          const CGAL::Epick::Point_2& r,
                                                          const CGAL::Epick::Point_2& t) {
  if (const auto decided = side_of_oriented_circle_second_stage(p, q, r, t)) return *decided;
  return CGAL::side_of_oriented_circle(p, q, r, t);
}

}  // namespace pleat::cgal
