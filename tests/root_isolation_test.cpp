// Root isolation of certificate polynomials (kinetic/root_isolation.hpp) against exact oracles:
// polynomials built from known rational roots (double roots, roots at exactly 0 and 1, clusters 1e-12 and
// 1e-30 apart), random-coefficient polynomials against a Sturm-sequence count with exact bisection and an
// exact sign scan on a rational grid, exact comparison of equal and nearly equal event times from different
// polynomials, and the sign_before/sign_after multiplicity rule.
#include "kinetic/root_isolation.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <sstream>

namespace pleat::kinetic {
namespace {

using Poly = ExactPolynomial;

Rational pow10(int k) {
  Rational r(1);
  for (int i = 0; i < k; ++i) r *= Rational(10);
  return r;
}

Rational pow2(int k) {
  Rational r(1);
  for (int i = 0; i < std::abs(k); ++i) r *= Rational(2);
  return k >= 0 ? r : Rational(1) / r;
}

std::string str(const Rational& r) {
  std::ostringstream out;
  out << r << " (~" << CGAL::to_double(r) << ")";
  return out.str();
}

/// Random roots: general rationals around [0, 1], dyadics, exactly 0 and 1, duplicates (double roots) and
/// clusters 1e-12 or 1e-30 away from the previous root.
std::vector<Rational> gen_roots() {
  const int count = *rc::gen::inRange(0, 6);
  std::vector<Rational> roots;
  for (int i = 0; i < count; ++i) {
    const int kind = roots.empty() ? *rc::gen::inRange(0, 4) : *rc::gen::inRange(0, 7);
    switch (kind) {
      case 0: {
        const int den = *rc::gen::inRange(1, 2000);
        roots.push_back(Rational(*rc::gen::inRange(-den / 4, den + den / 4 + 1), den));
        break;
      }
      case 1:
        roots.push_back(Rational(*rc::gen::element(0, 1)));
        break;
      case 2:
        roots.push_back(Rational(*rc::gen::inRange(0, 1 << 20)) / pow2(20));
        break;
      case 3:
        roots.push_back(Rational(*rc::gen::inRange(1, 999), 1000) + Rational(1, 3));
        break;
      case 4:
        roots.push_back(roots.back());
        break;
      case 5:
        roots.push_back(roots.back() + Rational(*rc::gen::element(1, -1)) / pow10(12));
        break;
      default:
        roots.push_back(roots.back() + Rational(1) / pow10(30));
        break;
    }
  }
  return roots;
}

Rational gen_scale() {
  const Rational s = Rational(*rc::gen::inRange(1, 1000)) * pow2(*rc::gen::inRange(-40, 41));
  return *rc::gen::arbitrary<bool>() ? s : -s;
}

/// A start time t0 and an independent exact test "r > t0" for rationals r.
struct StartTime {
  RootTime time;
  std::function<bool(const Rational&)> before;  ///< before(r): t0 < r
  std::string text;
};

StartTime gen_start(const std::vector<Rational>& roots) {
  const int kind = *rc::gen::inRange(0, 5);
  if (kind == 0) return {RootTime::zero(), [](const Rational& r) { return r > Rational(0); }, "0"};
  if (kind == 4) {
    // sqrt(c) for a non-square c in (0, 1): an algebraic start time.
    const Rational c(*rc::gen::inRange(1, 97) * 2 + 1,
                     199);  // 199 prime: c*199 odd < 199, not a square ratio
    const auto t = first_root_after(Poly({-c, Rational(0), Rational(1)}), RootTime::zero());
    RC_ASSERT(t.has_value());
    RC_ASSERT(!t->is_rational());
    return {*t, [c](const Rational& r) { return r > Rational(0) && r * r > c; }, "sqrt(" + str(c) + ")"};
  }
  Rational t0;
  if (kind == 3 && !roots.empty()) {
    t0 = *rc::gen::elementOf(roots);
    if (t0 < Rational(0) || t0 > Rational(1)) t0 = Rational(1, 2);
  } else {
    t0 = Rational(*rc::gen::inRange(0, 1000), 1000);
  }
  return {RootTime::rational(t0), [t0](const Rational& r) { return r > t0; }, str(t0)};
}

/// The oracle for a product of known roots: the least root in (t0, 1].
std::optional<Rational> expected_first(const std::vector<Rational>& roots, const StartTime& t0) {
  std::optional<Rational> best;
  for (const Rational& r : roots)
    if (t0.before(r) && r <= Rational(1) && (!best || r < *best)) best = r;
  return best;
}

void check_result(const std::optional<RootTime>& got, const std::optional<Rational>& expected,
                  const std::string& what) {
  if (got) RC_LOG() << what << ": got " << *got << "\n";
  RC_ASSERT(got.has_value() == expected.has_value());
  if (!got) return;
  RC_ASSERT(compare(*got, RootTime::rational(*expected)) == 0);
  // Independently of compare(): the double enclosure holds the exact root.
  RC_ASSERT(Rational(got->lower_bound()) <= *expected);
  RC_ASSERT(*expected <= Rational(got->upper_bound()));
  if (got->is_rational()) RC_ASSERT(got->rational_value() == *expected);
  // Narrowed: a few ulps when the exact polynomial was built, interval-evaluation accuracy otherwise.
  RC_ASSERT(got->upper_bound() - got->lower_bound() <= 1e-9);
  RC_ASSERT(std::abs(got->approximate() - CGAL::to_double(*expected)) <=
            std::max(1e-15, got->upper_bound() - got->lower_bound()));
}

RC_GTEST_PROP(RootIsolation, FirstRootOfKnownRootsIsExact, ()) {
  for (int round = 0; round < 10; ++round) {
    const std::vector<Rational> roots = gen_roots();
    const Rational scale = gen_scale();
    const Poly p = Poly::from_roots(roots, scale);
    const StartTime t0 = gen_start(roots);
    const std::optional<Rational> expected = expected_first(roots, t0);
    RC_LOG() << "roots:";
    for (const Rational& r : roots) RC_LOG() << " " << str(r);
    RC_LOG() << "; scale " << str(scale) << "; t0 " << t0.text << " = " << t0.time << "; expected "
             << (expected ? str(*expected) : "none") << "\n";
    const auto got = first_root_after(CertificatePolynomial::from_exact(p), t0.time);
    check_result(got, expected, "certificate");
    check_result(first_root_after(p, t0.time), expected, "exact");
  }
}

// ---- Random coefficients against Sturm sequences --------------------------------------------------------

/// Sturm sequence of p (p, p', -rem, ...).
std::vector<Poly> sturm_sequence(const Poly& p) {
  std::vector<Poly> seq{p, p.derivative()};
  while (!seq.back().is_zero()) {
    Poly q, r;
    Poly::divide(seq[seq.size() - 2], seq.back(), q, r);
    seq.push_back(Poly() - r);
  }
  seq.pop_back();
  return seq;
}

int sign_variations_at(const std::vector<Poly>& seq, const Rational& x) {
  int v = 0, last = 0;
  for (const Poly& q : seq) {
    const int s = q.sign_at(x);
    if (s == 0) continue;
    if (last != 0 && s != last) ++v;
    last = s;
  }
  return v;
}

/// Number of distinct roots in (a, b]; precondition p(a) != 0.
int count_roots(const std::vector<Poly>& seq, const Rational& a, const Rational& b) {
  return sign_variations_at(seq, a) - sign_variations_at(seq, b);
}

Poly gen_random_polynomial() {
  const int n = *rc::gen::inRange(1, 6);
  std::vector<Rational> h;
  const int range = *rc::gen::element(3, 20, 1000);
  for (int k = 0; k <= n; ++k) h.push_back(Rational(*rc::gen::inRange(-range, range + 1)));
  return Poly::from_homogeneous_bernstein(h);  // many sign changes on [0, 1]
}

RC_GTEST_PROP(RootIsolation, RandomPolynomialsAgreeWithSturmAndGrid, ()) {
  for (int round = 0; round < 10; ++round) {
    const Poly p = gen_random_polynomial();
    if (p.is_zero()) continue;
    const Rational t0(*rc::gen::inRange(0, 1000), 1000);
    const auto got = first_root_after(CertificatePolynomial::from_exact(p), RootTime::rational(t0));
    // Oracle: remove the roots at t0, then Sturm counts on (t0, x].
    Poly q = p;
    while (q.sign_at(t0) == 0) q = q.deflate(t0);
    const std::vector<Poly> seq = sturm_sequence(q);
    const int total = t0 < Rational(1) ? count_roots(seq, t0, Rational(1)) : 0;
    RC_ASSERT(got.has_value() == (total > 0));
    // Brute force: exact signs on a rational grid; the first grid point with a zero or a sign change bounds
    // the first root from above.
    int last = q.sign_at(t0);
    std::optional<Rational> bound;
    for (int k = 1; k <= 512 && !bound; ++k) {
      const Rational x = t0 + (Rational(1) - t0) * Rational(k, 512);
      const int s = q.sign_at(x);
      if (s != last) bound = x;
    }
    if (!got) {
      RC_ASSERT(!bound.has_value());
      continue;
    }
    if (bound) RC_ASSERT(compare(*got, RootTime::rational(*bound)) <= 0);
    // The result is a root, and none lies in (t0, result): exact bisection with Sturm counts.
    RC_ASSERT(sign_at(p, *got) == 0);
    Rational lo = t0, hi(1);
    for (int i = 0; i < 90; ++i) {
      const Rational m = (lo + hi) / Rational(2);
      if (count_roots(seq, t0, m) >= 1)
        hi = m;
      else
        lo = m;
    }
    // The first root lies in (lo, hi], 2^-90 wide.
    RC_ASSERT(compare(*got, RootTime::rational(lo)) > 0);
    RC_ASSERT(compare(*got, RootTime::rational(hi)) <= 0);
  }
}

// ---- Exact comparison of event times --------------------------------------------------------------------

/// A factor whose roots are outside [0, 1] (or none).
Poly gen_outside_factor() {
  std::vector<Rational> roots;
  const int count = *rc::gen::inRange(0, 3);
  for (int i = 0; i < count; ++i) {
    const Rational r(*rc::gen::inRange(101, 400), 100);
    roots.push_back(*rc::gen::arbitrary<bool>() ? r : -r);
  }
  return Poly::from_roots(roots, gen_scale());
}

RC_GTEST_PROP(RootIsolation, EqualTimesFromDifferentPolynomialsCompareEqual, ()) {
  for (int round = 0; round < 10; ++round) {
    // The shared root: a rational, or sqrt(c) (irrational), in (0, 1).
    Poly base;
    const bool irrational = *rc::gen::arbitrary<bool>();
    Rational r;
    if (irrational) {
      const Rational c(*rc::gen::inRange(1, 97) * 2 + 1, 199);
      base = Poly({-c, Rational(0), Rational(1)});
    } else {
      r = Rational(*rc::gen::inRange(1, 3000), 3001);
      base = Poly::from_roots({r});
    }
    const Poly p1 = base * gen_outside_factor(), p2 = base * gen_outside_factor() * gen_outside_factor();
    // A CertificatePolynomial holds degree <= 5; beyond, the exact stage alone.
    const auto isolate = [](const Poly& p) {
      return p.degree() <= 5 ? first_root_after(CertificatePolynomial::from_exact(p), RootTime::zero())
                             : first_root_after(p, RootTime::zero());
    };
    const auto a = isolate(p1);
    const auto b = isolate(p2);
    RC_ASSERT(a.has_value() && b.has_value());
    RC_ASSERT(compare(*a, *b) == 0);
    RC_ASSERT(compare(*b, *a) == 0);
    if (!irrational) RC_ASSERT(compare(*a, RootTime::rational(r)) == 0);
    // A time 1e-30 later is strictly later, from either side.
    const auto later = first_root_after(
        Poly::from_roots({irrational ? Rational(0) : r}) * Poly::from_roots({}, Rational(1)) +
            Poly({irrational ? Rational(0) : -Rational(1) / pow10(30)}),
        RootTime::zero());
    if (!irrational) {
      RC_ASSERT(later.has_value());
      RC_ASSERT(compare(*a, *later) < 0);
      RC_ASSERT(compare(*later, *b) > 0);
    } else {
      // sqrt(c) against rationals within 1e-25 of it (y < sqrt(c) iff y^2 < c).
      const Rational c = -base.coefficient(0);
      for (const int k : {-2, -1, 1, 2}) {
        const Rational y = Rational(a->approximate()) + Rational(k) / pow10(k % 2 == 0 ? 18 : 25);
        RC_ASSERT(compare(*a, RootTime::rational(y)) == (y * y < c ? 1 : -1));
      }
    }
  }
}

RC_GTEST_PROP(RootIsolation, ComparisonIsATotalOrderMatchingTheOracle, ()) {
  // Rational roots r_i = k_i / 997 + tiny_i (tiny in {0, 1e-13, 1e-31}), each found from its own polynomial.
  std::vector<std::pair<Rational, RootTime>> times;
  const int count = *rc::gen::inRange(2, 12);
  for (int i = 0; i < count; ++i) {
    const Rational r = Rational(*rc::gen::inRange(1, 20), 21) +
                       Rational(*rc::gen::element(0, 1, 2)) / pow10(*rc::gen::element(13, 31));
    const Poly p = Poly::from_roots({r}) * gen_outside_factor() * Poly::from_roots({r + Rational(7, 3)});
    const auto t = first_root_after(CertificatePolynomial::from_exact(p), RootTime::zero());
    RC_ASSERT(t.has_value());
    times.emplace_back(r, *t);
  }
  for (const auto& [ra, ta] : times)
    for (const auto& [rb, tb] : times) {
      const int expected = ra < rb ? -1 : (rb < ra ? 1 : 0);
      RC_ASSERT(compare(ta, tb) == expected);
    }
}

// ---- Fixed cases
// --------------------------------------------------------------------------------------------

TEST(RootIsolation, FlatCertificateHasNoEvent) {
  EXPECT_FALSE(first_root_after(CertificatePolynomial::from_exact(Poly()), RootTime::zero()).has_value());
  EXPECT_FALSE(first_root_after(Poly(), RootTime::zero()).has_value());
}

TEST(RootIsolation, RootsAtTheEndsOfTheInterval) {
  const Poly p = Poly::from_roots({Rational(0), Rational(1)});  // t (t - 1)
  auto r = first_root_after(CertificatePolynomial::from_exact(p), RootTime::zero());
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(compare(*r, RootTime::one()), 0);
  EXPECT_FALSE(first_root_after(CertificatePolynomial::from_exact(p), RootTime::one()).has_value());
}

TEST(RootIsolation, TouchingZeroIsAnEventThatKeepsTheSign) {
  const Rational r(1, 3);
  const Poly touch = Poly::from_roots({r, r}, Rational(-2));  // -2 (t - 1/3)^2 <= 0
  const auto t = first_root_after(CertificatePolynomial::from_exact(touch), RootTime::zero());
  ASSERT_TRUE(t.has_value());
  EXPECT_EQ(compare(*t, RootTime::rational(r)), 0);
  EXPECT_EQ(sign_at(touch, *t), 0);
  EXPECT_EQ(sign_before(touch, *t), -1);
  EXPECT_EQ(sign_after(touch, *t), -1);
  const Poly cross = Poly::from_roots({r, r, r});
  EXPECT_EQ(sign_before(cross, *t), -1);
  EXPECT_EQ(sign_after(cross, *t), 1);
  // After the event, the next one: none for the touch.
  EXPECT_FALSE(first_root_after(CertificatePolynomial::from_exact(touch), *t).has_value());
}

TEST(RootIsolation, SignsAtAnIrrationalTime) {
  const Poly q({Rational(-1, 2), Rational(0), Rational(1)});  // sqrt(1/2)
  const auto t = first_root_after(q, RootTime::zero());
  ASSERT_TRUE(t.has_value());
  EXPECT_FALSE(t->is_rational());
  const Poly doubled = q * q * Poly::from_roots({Rational(1, 5)});  // (t - 1/5)(t^2 - 1/2)^2
  EXPECT_EQ(sign_at(doubled, *t), 0);
  EXPECT_EQ(sign_before(doubled, *t), 1);
  EXPECT_EQ(sign_after(doubled, *t), 1);
  EXPECT_EQ(sign_at(Poly::from_roots({Rational(7071, 10000)}), *t), 1);  // 0.7071 < sqrt(1/2)
  EXPECT_EQ(sign_at(Poly::from_roots({Rational(7072, 10000)}), *t), -1);
  // The event after t of (t - 1/5)(t^2 - 1/2)^2 (t - 0.9): 0.9.
  const auto next = first_root_after(doubled * Poly::from_roots({Rational(9, 10)}), *t);  // degree 6: exact
  ASSERT_TRUE(next.has_value());
  EXPECT_EQ(compare(*next, RootTime::rational(Rational(9, 10))), 0);
}

TEST(RootIsolation, RationalTimeOfALinearCertificateIsExact) {
  const auto t = first_root_after(CertificatePolynomial::from_exact(Poly({Rational(1), Rational(-3)})),
                                  RootTime::zero());  // 1 - 3t
  ASSERT_TRUE(t.has_value());
  ASSERT_TRUE(t->is_rational());
  EXPECT_EQ(t->rational_value(), Rational(1, 3));
}

TEST(RootIsolation, EachStageDecidesItsCases) {
  IsolationStage stage;
  const Poly p = Poly::from_roots({Rational(-1, 2), Rational(3, 2), Rational(2)}, Rational(5));
  EXPECT_FALSE(first_root_after(CertificatePolynomial::from_exact(p), RootTime::zero(), &stage).has_value());
  EXPECT_EQ(stage, IsolationStage::filter);
  // A root before t0 only: decided by the interval subdivision, no exact arithmetic.
  const Poly q = Poly::from_roots({Rational(1, 10), Rational(3, 2)});
  EXPECT_FALSE(first_root_after(CertificatePolynomial::from_exact(q), RootTime(0.5), &stage).has_value());
  EXPECT_EQ(stage, IsolationStage::subdivision);
  // A simple root well inside: found by the subdivision (exactly one certain sign change).
  const auto r = first_root_after(CertificatePolynomial::from_exact(q), RootTime::zero(), &stage);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(stage, IsolationStage::subdivision);
  EXPECT_EQ(compare(*r, RootTime::rational(Rational(1, 10))), 0);
  // A double root: only the exact stage can isolate it.
  const Poly d = Poly::from_roots({Rational(2, 7), Rational(2, 7), Rational(-1)});
  const auto s = first_root_after(CertificatePolynomial::from_exact(d), RootTime::zero(), &stage);
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(stage, IsolationStage::exact);
  EXPECT_EQ(compare(*s, RootTime::rational(Rational(2, 7))), 0);
}

}  // namespace
}  // namespace pleat::kinetic
