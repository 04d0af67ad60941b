// The kinetic layer's orientation certificates of linearly moving slice points
// (kinetic/moving_orientation.hpp) against exact oracles: the certificate's exact polynomial equals the
// orientation of the interpolated points (Gmpq) at rational times; its interval enclosure holds the exact
// Bernstein coefficients; bernstein_signs are their exact signs; and first_failure — the cheap staged
// decision the engine uses (filter, exact signs, intervals, rationals) — gives exactly the event the
// all-rational decision gives, on random and degenerate motions (points on a small integer grid: collinear,
// coincident, touching zero at the ends) and from start times 0, 1, rationals and an algebraic time.
#include "kinetic/moving_orientation.hpp"

#include <CGAL/FPU.h>
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <array>
#include <sstream>

namespace pleat::kinetic {
namespace {

/// A coordinate: mostly on a coarse grid (exact degeneracies are frequent), sometimes an arbitrary double.
double gen_coordinate() {
  if (*rc::gen::inRange(0, 4) == 0) return *rc::gen::inRange(-1000000, 1000001) / 977.0;
  return *rc::gen::inRange(-3, 4) * 0.5;
}

MovingPoint gen_point() {
  MovingPoint p{{gen_coordinate(), gen_coordinate()}, {gen_coordinate(), gen_coordinate()}};
  if (*rc::gen::inRange(0, 4) == 0) p.to = p.from;  // standing still
  return p;
}

std::array<MovingPoint, 3> gen_triple() {
  std::array<MovingPoint, 3> t{gen_point(), gen_point(), gen_point()};
  switch (*rc::gen::inRange(0, 5)) {
    case 0:  // c stays on the line through a and b at both ends: collinear for all t when it moves rigidly
      t[2].from = t[0].from + 2.0 * (t[1].from - t[0].from);
      t[2].to = t[0].to + 2.0 * (t[1].to - t[0].to);
      break;
    case 1:  // two points coincide at t = 0
      t[1].from = t[0].from;
      break;
    default:
      break;
  }
  return t;
}

Rational exact_orientation_at(const std::array<MovingPoint, 3>& p, const Rational& t) {
  auto at = [&](const MovingPoint& m, int k) {
    const Rational from(k == 0 ? m.from.x : m.from.y), to(k == 0 ? m.to.x : m.to.y);
    return from + t * (to - from);
  };
  const Rational ux = at(p[1], 0) - at(p[0], 0), uy = at(p[1], 1) - at(p[0], 1);
  const Rational vx = at(p[2], 0) - at(p[0], 0), vy = at(p[2], 1) - at(p[0], 1);
  return ux * vy - uy * vx;
}

/// The start times of the test: 0, 1, a rational in (0, 1), an algebraic time (a root of t^2 - c), or a lazy
/// one (the engine's common case: an event time isolated by interval subdivision, its polynomial not built).
RootTime gen_start() {
  switch (*rc::gen::inRange(0, 5)) {
    case 4:
      for (int attempt = 0; attempt < 100; ++attempt) {
        const std::array<MovingPoint, 3> q{gen_point(), gen_point(), gen_point()};
        IsolationStage stage = IsolationStage::filter;
        const std::optional<RootTime> t =
            first_root_after(orientation_certificate(q[0], q[1], q[2]), RootTime::zero(), &stage);
        if (t && stage == IsolationStage::subdivision) return *t;
      }
      return RootTime::zero();
    case 0:
      return RootTime::zero();
    case 1:
      return RootTime::one();
    case 2:
      return RootTime::rational(Rational(*rc::gen::inRange(1, 64), 64));
    default: {
      const Rational c(*rc::gen::inRange(1, 98) * 2 + 1, 199);
      return *first_root_after(ExactPolynomial({-c, Rational(0), Rational(1)}), RootTime::zero());
    }
  }
}

std::string text(const std::optional<RootTime>& t) {
  std::ostringstream out;
  if (t)
    out << *t;
  else
    out << "none";
  return out.str();
}

RC_GTEST_PROP(MovingOrientation, ExactPolynomialIsTheOrientationOfTheInterpolatedPoints, ()) {
  const std::array<MovingPoint, 3> p = gen_triple();
  const ExactPolynomial poly = orientation_polynomial(p[0], p[1], p[2]);
  RC_ASSERT(poly.degree() <= 2);
  for (int k = 0; k <= 8; ++k) {
    const Rational t(k, 8);
    RC_ASSERT(poly.evaluate(t) == exact_orientation_at(p, t));
  }
}

RC_GTEST_PROP(MovingOrientation, EnclosureAndBernsteinSignsAreExact, ()) {
  const std::array<MovingPoint, 3> p = gen_triple();
  const ExactPolynomial poly = orientation_polynomial(p[0], p[1], p[2]);
  const std::vector<Rational> h = poly.homogeneous_bernstein(2);  // (B0, 2 B1, B2)
  const CertificatePolynomial c = orientation_certificate(p[0], p[1], p[2]);
  const std::array<int, 3> signs = bernstein_signs(p[0], p[1], p[2]);
  for (int k = 0; k < 3; ++k) {
    RC_ASSERT(Rational(c.enclosure()[k].inf()) <= h[k]);
    RC_ASSERT(h[k] <= Rational(c.enclosure()[k].sup()));
    RC_ASSERT(signs[k] == static_cast<int>(CGAL::sign(h[k])));
  }
  CGAL::Protect_FPU_rounding<true> rounding;
  RC_ASSERT(certainly_positive(p[0], p[1], p[2]) == false ||
            (h[0] > Rational(0) && h[1] > Rational(0) && h[2] > Rational(0)));
}

RC_GTEST_PROP(MovingOrientation, FirstFailureEqualsTheAllRationalDecision, ()) {
  const std::array<MovingPoint, 3> p = gen_triple();
  const RootTime t0 = gen_start();
  const bool triangle = *rc::gen::arbitrary<bool>();
  // The oracle: the exact polynomial, rational arithmetic only.
  const ExactPolynomial poly = orientation_polynomial(p[0], p[1], p[2]);
  std::optional<RootTime> expected;
  if (poly.is_zero()) {
    if (triangle) expected = t0;
  } else if (sign_after(poly, t0) < 0 || (triangle && t0 == RootTime::one() && sign_at(poly, t0) == 0)) {
    expected = t0;
  } else {
    expected = first_root_after(poly, t0);
  }
  const CertificateFailure got = first_failure(p, t0, triangle);
  RC_TAG(static_cast<int>(got.decided_by), !got.time         ? "holds"
                                           : *got.time == t0 ? "fails now"
                                                             : "event later");
  RC_LOG() << "t0 " << t0 << ", triangle " << triangle << ": expected " << text(expected) << ", got "
           << text(got.time) << "\n";
  RC_ASSERT(got.time.has_value() == expected.has_value());
  if (expected) RC_ASSERT(*got.time == *expected);
  // A failure claimed without an exact test is real: flat for all t, negative just after, or (a triangle)
  // flat at t = 1.
  if (got.fails)
    RC_ASSERT(poly.is_zero() || sign_after(poly, *got.time) < 0 ||
              (triangle && *got.time == RootTime::one() && sign_at(poly, *got.time) == 0));
}

// The common case costs nothing exact: a triangle positive over the interval is decided by the filter.
TEST(MovingOrientation, PositiveTriangleIsDecidedByTheFilter) {
  const std::array<MovingPoint, 3> p{MovingPoint{{0, 0}, {0.01, 0}}, MovingPoint{{1, 0}, {1, 0.01}},
                                     MovingPoint{{0, 1}, {0, 1.01}}};
  const CertificateFailure f = first_failure(p, RootTime::zero(), true);
  EXPECT_FALSE(f.time.has_value());
  EXPECT_EQ(f.decided_by, CertificateFailure::DecidedBy::filter);
  // A triangle turned inside out by t = 1 fails at its zero, t = 1/2.
  const std::array<MovingPoint, 3> q{MovingPoint{{0, 0}, {0, 0}}, MovingPoint{{1, 0}, {1, 0}},
                                     MovingPoint{{0, 1}, {0.3, -1}}};
  const CertificateFailure g = first_failure(q, RootTime::zero(), true);
  ASSERT_TRUE(g.time.has_value());
  EXPECT_EQ(*g.time, RootTime::rational(Rational(1, 2)));
}

}  // namespace
}  // namespace pleat::kinetic
