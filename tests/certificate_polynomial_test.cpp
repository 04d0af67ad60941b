// Certificate polynomials (kinetic/certificate_polynomial.hpp) as the kinetic engine uses them: orientation
// certificates of slice points moving linearly in their plane (planar_orientation_certificate, through
// moving_orientation.hpp). Simultaneous events of different certificates (rational and irrational times)
// compare equal; collinearity exactly at the ends of the interval; a certificate given by an exact polynomial
// keeps it and encloses its Bernstein coefficients; the no-event path does not allocate. (That the polynomial
// is the orientation of the interpolated points, its enclosure and exact Bernstein signs, and the engine's
// staged decision against an all-rational one: tests/moving_orientation_test.cpp.)
#include "kinetic/certificate_polynomial.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <glm/vec2.hpp>
#include <new>

#include "kinetic/moving_orientation.hpp"
#include "kinetic/root_isolation.hpp"

// Allocation counter for the no-allocation check (counts only while enabled, on any thread).
namespace {
std::atomic<bool> g_count_allocations{false};
std::atomic<long> g_allocations{0};
}  // namespace

#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void* operator new(std::size_t size) {
  if (g_count_allocations.load(std::memory_order_relaxed)) g_allocations.fetch_add(1);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace pleat::kinetic {
namespace {

MovingPoint moving(glm::dvec2 from, glm::dvec2 to) { return {from, to}; }

// ---- Simultaneous events ----------------------------------------------------------------------------------

TEST(CertificatePolynomial, SimultaneousEventsHaveEqualTimes) {
  // A = (0,0), B = (1,0) fixed; C and D reach the line AB at t = 1/3 (y = 1 - 3t and 2 - 6t).
  const MovingPoint a = moving({0, 0}, {0, 0}), b = moving({1, 0}, {1, 0});
  const MovingPoint c = moving({2, 1}, {2.5, -2}), d = moving({-1, 2}, {3, -4});
  const auto t1 = first_root_after(orientation_certificate(a, b, c), RootTime::zero());
  const auto t2 = first_root_after(orientation_certificate(a, b, d), RootTime::zero());
  ASSERT_TRUE(t1 && t2);
  EXPECT_EQ(compare(*t1, *t2), 0);
  EXPECT_EQ(compare(*t1, RootTime::rational(Rational(1, 3))), 0);

  // An irrational simultaneous event: B moves, A fixed at the origin, D = 2 C (so A, C, D are collinear for
  // all t: that certificate is identically zero). orient(A, B, C) = x_B y_C - y_B x_C.
  const MovingPoint bm = moving({1, 0}, {1, 1}), cm = moving({0.5, 0.25}, {1.5, -0.5});
  const MovingPoint dm = moving({1, 0.5}, {3, -1});
  const auto u1 = first_root_after(orientation_certificate(a, bm, cm), RootTime::zero());
  const auto u2 = first_root_after(orientation_certificate(a, bm, dm), RootTime::zero());
  const auto u3 = first_root_after(orientation_certificate(bm, cm, dm), RootTime::zero());
  ASSERT_TRUE(u1 && u2 && u3);
  EXPECT_FALSE(u1->is_rational());
  EXPECT_EQ(compare(*u1, *u2), 0);
  EXPECT_EQ(compare(*u1, *u3), 0);
  EXPECT_TRUE(orientation_certificate(a, cm, dm).exact().is_zero());
  EXPECT_FALSE(first_root_after(orientation_certificate(a, cm, dm), RootTime::zero()).has_value());
}

/// Every event of a certificate in (0, 1], in order (repeated first_root_after from the previous event).
std::vector<RootTime> all_events(const CertificatePolynomial& c) {
  std::vector<RootTime> out;
  RootTime t = RootTime::zero();
  while (const auto next = first_root_after(c, t)) {
    RC_ASSERT(compare(*next, t) > 0);
    out.push_back(*next);
    t = *next;
    RC_ASSERT(out.size() <= 2u);  // a quadratic
  }
  return out;
}

RC_GTEST_PROP(CertificatePolynomial, RandomSimultaneousEventsCompareEqual, ()) {
  // A, B, C, D all move, and at tau = 1/k they lie on one line. Positions at t = 1 are P0 + k (P_tau - P0),
  // exact in doubles.
  const int k = *rc::gen::element(3, 5, 6, 7);
  const auto dyadic = [] { return *rc::gen::inRange(-16, 17) / 8.0; };
  const glm::dvec2 a_tau(dyadic(), dyadic()), b_tau(dyadic(), dyadic());
  RC_PRE(a_tau != b_tau);
  const double lambda = *rc::gen::element(-1.0, 0.5, 2.0, 3.0), mu = *rc::gen::element(-2.0, 1.5, 4.0);
  const auto gen = [&](glm::dvec2 at_tau) {
    const glm::dvec2 p0(dyadic(), dyadic());
    return moving(p0, p0 + double(k) * (at_tau - p0));
  };
  const MovingPoint a = gen(a_tau), b = gen(b_tau);
  const MovingPoint c = gen(a_tau + lambda * (b_tau - a_tau)), d = gen(a_tau + mu * (b_tau - a_tau));
  const RootTime tau = RootTime::rational(Rational(1, k));
  std::vector<std::optional<RootTime>> at_tau;
  for (const auto& cert : {orientation_certificate(a, b, c), orientation_certificate(a, b, d),
                           orientation_certificate(b, c, d), orientation_certificate(a, c, d)}) {
    if (cert.exact().is_zero()) continue;  // collinear for all t (e.g. the motions happen to be parallel)
    std::optional<RootTime> hit;
    for (const RootTime& e : all_events(cert))
      if (compare(e, tau) == 0) {
        RC_ASSERT(!hit.has_value());  // distinct events are distinct times
        hit = e;
      }
    RC_ASSERT(hit.has_value());
    at_tau.push_back(hit);
  }
  RC_CLASSIFY(std::any_of(at_tau.begin(), at_tau.end(), [](const auto& t) { return !t->is_rational(); }),
              "algebraic times compared");
  for (const auto& x : at_tau)
    for (const auto& y : at_tau) RC_ASSERT(compare(*x, *y) == 0);
}

// ---- The ends of the interval ---------------------------------------------------------------------------

TEST(CertificatePolynomial, CollinearAtTheEndsOfTheInterval) {
  // Three points that reach the line y = x at t = 1: collinear there, an event at exactly 1.
  const MovingPoint a = moving({0, 1}, {0, 0}), b = moving({1, 0}, {1, 1}), c = moving({2, 3}, {2, 2});
  const auto t = first_root_after(orientation_certificate(a, b, c), RootTime::zero());
  ASSERT_TRUE(t.has_value());
  EXPECT_EQ(compare(*t, RootTime::one()), 0);
  EXPECT_TRUE(t->is_rational());
  // Run backwards (frames swapped): collinear at t = 0, so no event in (0, 1]; the sign just after 0 is the
  // certificate's sign for the interval.
  const auto back = [](const MovingPoint& p) { return moving(p.to, p.from); };
  const CertificatePolynomial r = orientation_certificate(back(a), back(b), back(c));
  EXPECT_EQ(r.exact().sign_at(Rational(0)), 0);
  EXPECT_FALSE(first_root_after(r, RootTime::zero()).has_value());
  EXPECT_NE(sign_after(r.exact(), RootTime::zero()), 0);
}

// ---- Certificates of exact polynomials -------------------------------------------------------------------

RC_GTEST_PROP(CertificatePolynomial, FromExactKeepsThePolynomialAndEnclosesItsBernsteinForm, ()) {
  const int n = *rc::gen::inRange(0, kMaxCertificateDegree + 1);
  std::vector<Rational> c;
  for (int i = 0; i <= n; ++i)
    c.push_back(Rational(*rc::gen::inRange(-1000, 1001), *rc::gen::element(1, 3, 7, 1024)));
  const ExactPolynomial p(c);
  const CertificatePolynomial cert = CertificatePolynomial::from_exact(p);
  RC_ASSERT(cert.exact() == p);
  RC_ASSERT(cert.degree() == std::max(p.degree(), 0));
  const std::vector<Rational> h = p.homogeneous_bernstein(cert.degree());
  for (int k = 0; k <= cert.degree(); ++k) {
    RC_ASSERT(Rational(cert.enclosure()[k].inf()) <= h[k]);
    RC_ASSERT(h[k] <= Rational(cert.enclosure()[k].sup()));
  }
  RC_ASSERT(ExactPolynomial::from_homogeneous_bernstein(h) == p);
}

// ---- The common case ------------------------------------------------------------------------------------

TEST(CertificatePolynomial, NoEventPathDoesNotAllocate) {
  // A small triangle of slice points drifting slowly: a positive orientation throughout.
  const std::array<MovingPoint, 3> p{moving({0, 0}, {0.01, 0}), moving({0.5, 0}, {0.5, 0.01}),
                                     moving({0, 0.5}, {0.01, 0.51})};
  long events = 0;
  g_allocations = 0;
  g_count_allocations = true;
  for (int k = 0; k < 1000; ++k) {
    events += first_failure(p, RootTime::zero(), true).time.has_value();
    events += first_root_after(orientation_certificate(p[0], p[1], p[2]), RootTime::zero()).has_value();
  }
  g_count_allocations = false;
  EXPECT_EQ(events, 0);
  EXPECT_EQ(g_allocations.load(), 0);
  EXPECT_TRUE(certainly_no_root(orientation_certificate(p[0], p[1], p[2])));
  // The counter does count: the exact path allocates.
  g_count_allocations = true;
  (void)orientation_certificate(p[0], p[1], p[2]).exact();
  g_count_allocations = false;
  EXPECT_GT(g_allocations.load(), 0);
}

}  // namespace
}  // namespace pleat::kinetic
