// Certificate polynomials (kinetic/certificate_polynomial.hpp) against direct exact geometry: at rational
// times the orientation polynomial equals W1 W2 W3 times the exact orientation of the three slice points
// computed from the moving 3D positions; its interval enclosure holds the exact coefficients; events found by
// root isolation are real collinearities and none is missed on a rational grid. Degenerate motions: a flat
// sheet (collinear for all t), vertices exactly on the plane at t = 0 and t = 1, simultaneous events from
// different certificates (equal times), plane crossings at rational times. The no-event path does not
// allocate.
#include "kinetic/certificate_polynomial.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <new>

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

using Vec = std::array<Rational, 3>;

Vec exact(const glm::dvec3& p) { return {Rational(p.x), Rational(p.y), Rational(p.z)}; }
Rational dot(const glm::dvec3& a, const Vec& p) {
  return Rational(a.x) * p[0] + Rational(a.y) * p[1] + Rational(a.z) * p[2];
}
/// p0 + t (p1 - p0), exactly.
Vec at(const glm::dvec3& p0, const glm::dvec3& p1, const Rational& t) {
  const Vec a = exact(p0), b = exact(p1);
  return {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])};
}

struct Point2 {
  Rational x, y;
  Rational w;  ///< W = s_a - s_b (the homogeneous denominator)
};

/// The slice point at time t computed directly: the 3D crossing point of the edge, then its (u, w)
/// coordinates. Precondition: s_a != s_b at t.
Point2 slice_point(const SlicingPlane& plane, const SliceVertexMotion& m, const Rational& t) {
  const Vec a = at(m.above0, m.above1, t), b = at(m.below0, m.below1, t);
  const Rational sa = dot(plane.normal, a) - Rational(plane.offset);
  const Rational sb = dot(plane.normal, b) - Rational(plane.offset);
  const Rational den = sa - sb;
  Vec x;
  for (int i = 0; i < 3; ++i) x[i] = (sa * b[i] - sb * a[i]) / den;
  return {dot(plane.u, x), dot(plane.w, x), den};
}

Rational orient(const Point2& p, const Point2& q, const Point2& r) {
  return (q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x);
}

/// det[...] at t computed directly: W1 W2 W3 orient(p1, p2, p3). nullopt when some W is 0.
std::optional<Rational> direct_det(const SlicingPlane& plane, const std::array<SliceVertexMotion, 3>& v,
                                   const Rational& t) {
  std::array<Point2, 3> p;
  for (int i = 0; i < 3; ++i) {
    const Vec a = at(v[i].above0, v[i].above1, t), b = at(v[i].below0, v[i].below1, t);
    if (dot(plane.normal, a) == dot(plane.normal, b)) return std::nullopt;
    p[i] = slice_point(plane, v[i], t);
  }
  return p[0].w * p[1].w * p[2].w * orient(p[0], p[1], p[2]);
}

int direct_sign(const SlicingPlane& plane, const std::array<SliceVertexMotion, 3>& v, const Rational& t) {
  const auto d = direct_det(plane, v, t);
  RC_ASSERT(d.has_value());
  return static_cast<int>(CGAL::sign(*d));
}

SlicingPlane make_test_plane(const glm::dvec3& normal_dir, double offset) {
  SlicingPlane p;
  p.normal = glm::normalize(normal_dir);
  const glm::dvec3 axis = std::abs(p.normal.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  p.u = glm::normalize(glm::cross(axis, p.normal));
  p.w = glm::cross(p.normal, p.u);
  p.offset = offset;
  return p;
}

double gen_coord(int scale) { return *rc::gen::inRange(-scale, scale + 1) / static_cast<double>(scale); }

SlicingPlane gen_plane() {
  switch (*rc::gen::inRange(0, 3)) {
    case 0:
      return make_test_plane({0, 0, 1}, gen_coord(8));  // axis-aligned: exact ties are easy to hit
    case 1:
      return make_test_plane({1, 1, 0}, gen_coord(8));
    default: {
      const glm::dvec3 n(gen_coord(1000), gen_coord(1000), gen_coord(1000));
      return make_test_plane(glm::length(n) > 0.1 ? n : glm::dvec3(0, 1, 0), gen_coord(1000) * 0.3);
    }
  }
}

/// A point on the given side of the plane (exactly checked): a random point pushed along the normal, or,
/// on an axis-aligned plane, sometimes exactly on it (then "above" by the symbolic perturbation).
glm::dvec3 gen_endpoint(const SlicingPlane& plane, bool above) {
  for (;;) {
    glm::dvec3 p(gen_coord(64), gen_coord(64), gen_coord(64));
    p -= (glm::dot(plane.normal, p) - plane.offset) * plane.normal;  // near the plane
    const bool on_plane = above && plane.normal == glm::dvec3(0, 0, 1) && *rc::gen::inRange(0, 4) == 0;
    if (on_plane)
      p.z = plane.offset;
    else
      p += (above ? 1.0 : -1.0) * (*rc::gen::inRange(1, 64) / 32.0) * plane.normal;
    const Rational s = dot(plane.normal, exact(p)) - Rational(plane.offset);
    if (above ? CGAL::sign(s) >= 0 : CGAL::sign(s) < 0) return p;
  }
}

SliceVertexMotion gen_motion(const SlicingPlane& plane) {
  return {gen_endpoint(plane, true), gen_endpoint(plane, true), gen_endpoint(plane, false),
          gen_endpoint(plane, false)};
}

void check_orientation_identity();

RC_GTEST_PROP(CertificatePolynomial, OrientationEqualsDirectExactGeometry, ()) {
  for (int round = 0; round < 5; ++round) check_orientation_identity();
}

void check_orientation_identity() {
  const SlicingPlane plane = gen_plane();
  const std::array<SliceVertexMotion, 3> v{gen_motion(plane), gen_motion(plane), gen_motion(plane)};
  const CertificatePolynomial c = orientation_certificate(plane, v[0], v[1], v[2]);
  const ExactPolynomial p = c.exact();
  // The enclosure holds the exact homogeneous Bernstein coefficients.
  const std::vector<Rational> h = p.homogeneous_bernstein(5);
  for (int k = 0; k <= 5; ++k) {
    RC_ASSERT(Rational(c.enclosure()[k].inf()) <= h[k]);
    RC_ASSERT(h[k] <= Rational(c.enclosure()[k].sup()));
  }
  // P(t) equals the directly computed determinant at rational times, including both ends.
  for (int k = 0; k <= 8; ++k) {
    const Rational t = k == 8 ? Rational(*rc::gen::inRange(0, 10007), 10007) : Rational(k, 7);
    if (t > Rational(1)) continue;
    const auto d = direct_det(plane, v, t);
    RC_ASSERT(d.has_value());  // W > 0 by construction
    RC_ASSERT(p.evaluate(t) == *d);
  }
}

RC_GTEST_PROP(CertificatePolynomial, EventsAreRealAndNoneIsMissedOnAGrid, ()) {
  const SlicingPlane plane = gen_plane();
  const std::array<SliceVertexMotion, 3> v{gen_motion(plane), gen_motion(plane), gen_motion(plane)};
  const CertificatePolynomial c = orientation_certificate(plane, v[0], v[1], v[2]);
  const Rational t0(*rc::gen::inRange(0, 4), 4);
  IsolationStage stage;
  const auto got = first_root_after(c, RootTime::rational(t0), &stage);
  RC_CLASSIFY(got.has_value(), "event");
  RC_CLASSIFY(stage == IsolationStage::filter, "filter");
  RC_CLASSIFY(stage == IsolationStage::subdivision, "subdivision");
  RC_CLASSIFY(stage == IsolationStage::exact, "exact");
  if (c.exact().is_zero()) {
    RC_ASSERT(!got.has_value());
    return;
  }
  // Brute force: exact signs of the direct determinant on a rational grid; the first zero or sign change
  // bounds the first event from above.
  std::optional<Rational> bound;
  int last = sign_after(c.exact(), RootTime::rational(t0));
  for (int k = 1; k <= 256 && !bound; ++k) {
    const Rational x = t0 + (Rational(1) - t0) * Rational(k, 256);
    const int s = direct_sign(plane, v, x);
    if (s != last) bound = x;
  }
  if (bound) RC_ASSERT(got.has_value());
  if (!got) return;
  RC_ASSERT(compare(*got, RootTime::rational(t0)) > 0);
  RC_ASSERT(compare(*got, RootTime::one()) <= 0);
  if (bound) RC_ASSERT(compare(*got, RootTime::rational(*bound)) <= 0);
  // A real collinearity: a rational root makes the direct determinant 0; an algebraic one is bracketed by a
  // sign change of the direct determinant, or is a touching zero (then P and P' vanish there).
  if (got->is_rational()) {
    RC_ASSERT(direct_sign(plane, v, got->rational_value()) == 0);
  } else {
    const int lo = direct_sign(plane, v, got->isolating_lower());
    const int hi = direct_sign(plane, v, got->isolating_upper());
    RC_ASSERT(lo * hi < 0 || sign_at(c.exact().derivative(), *got) == 0);
  }
  RC_ASSERT(sign_at(c.exact(), *got) == 0);
}

// ---- Degenerate motions ---------------------------------------------------------------------------------

/// A vertical edge over (x, y) crossing z = 0 (plane z = 0): its slice point is exactly (x, y), W = 2.
SliceVertexMotion vertical(glm::dvec2 p0, glm::dvec2 p1) {
  return {{p0.x, p0.y, 1.0}, {p1.x, p1.y, 1.0}, {p0.x, p0.y, -1.0}, {p1.x, p1.y, -1.0}};
}

RC_GTEST_PROP(CertificatePolynomial, FlatSheetIsCollinearForAllTimeAndHasNoEvent, ()) {
  // Every endpoint in z = 0, the plane oblique: the slice points lie on the line (z = 0) ∩ plane, exactly.
  const glm::dvec3 normal(gen_coord(100), gen_coord(100), 0.0);
  RC_PRE(glm::length(normal) > 0.1);
  const SlicingPlane plane = make_test_plane(normal, gen_coord(100) * 0.2);
  std::array<SliceVertexMotion, 3> v;
  for (auto& m : v) {
    const auto flat = [&](bool above) {
      glm::dvec3 p = gen_endpoint(plane, above);
      for (int tries = 0; tries < 100; ++tries) {
        glm::dvec3 q = p;
        q.z = 0.0;
        const Rational s = dot(plane.normal, exact(q)) - Rational(plane.offset);
        if (above ? CGAL::sign(s) >= 0 : CGAL::sign(s) < 0) return q;
        p += (above ? 0.25 : -0.25) * plane.normal;
      }
      RC_DISCARD("no flat point on that side");
      return p;
    };
    m = {flat(true), flat(true), flat(false), flat(false)};
  }
  const CertificatePolynomial c = orientation_certificate(plane, v[0], v[1], v[2]);
  RC_ASSERT(c.exact().is_zero());
  RC_ASSERT(!first_root_after(c, RootTime::zero()).has_value());
}

TEST(CertificatePolynomial, VertexOnThePlaneAtTheEndsOfTheInterval) {
  const SlicingPlane plane = make_test_plane({0, 0, 1}, 0.5);
  // Three slice vertices whose upper endpoints reach the plane at t = 1 on the line y = x: collinear at 1.
  const auto edge = [](glm::dvec3 a0, glm::dvec3 a1, glm::dvec3 b) {
    return SliceVertexMotion{a0, a1, b, b};
  };
  const std::array<SliceVertexMotion, 3> v{edge({0, 1, 1}, {0, 0, 0.5}, {0, 0, 0}),
                                           edge({1, 0, 1}, {1, 1, 0.5}, {1, 1, 0}),
                                           edge({2, 3, 1}, {2, 2, 0.5}, {3, 2, 0})};
  const CertificatePolynomial c = orientation_certificate(plane, v[0], v[1], v[2]);
  const auto t = first_root_after(c, RootTime::zero());
  ASSERT_TRUE(t.has_value());
  EXPECT_EQ(compare(*t, RootTime::one()), 0);
  EXPECT_TRUE(t->is_rational());
  // Run backwards (the same vertices, frames swapped): collinear at t = 0, so no event in (0, 1]; the sign
  // just after 0 is the certificate's sign for the interval.
  std::array<SliceVertexMotion, 3> back = v;
  for (auto& m : back) {
    std::swap(m.above0, m.above1);
    std::swap(m.below0, m.below1);
  }
  const CertificatePolynomial r = orientation_certificate(plane, back[0], back[1], back[2]);
  EXPECT_EQ(r.exact().sign_at(Rational(0)), 0);
  EXPECT_FALSE(first_root_after(r, RootTime::zero()).has_value());
  EXPECT_NE(sign_after(r.exact(), RootTime::zero()), 0);

  // Plane side of a vertex: on the plane at t = 0 moving down (an event at t0 itself, seen by sign_after),
  // and reaching the plane at t = 1 (an event at exactly 1).
  const CertificatePolynomial down = plane_side_certificate(plane, {0, 0, 0.5}, {0, 0, 0});
  EXPECT_FALSE(first_root_after(down, RootTime::zero()).has_value());
  EXPECT_EQ(sign_after(down.exact(), RootTime::zero()), -1);
  const CertificatePolynomial up = plane_side_certificate(plane, {0, 0, 0}, {0, 0, 0.5});
  const auto reach = first_root_after(up, RootTime::zero());
  ASSERT_TRUE(reach.has_value());
  EXPECT_EQ(compare(*reach, RootTime::one()), 0);
}

TEST(CertificatePolynomial, SimultaneousEventsHaveEqualTimes) {
  const SlicingPlane plane = make_test_plane({0, 0, 1}, 0.0);
  // A = (0,0), B = (1,0) fixed; C and D reach the line AB at t = 1/3 (y = 1 - 3t and 2 - 6t).
  const SliceVertexMotion a = vertical({0, 0}, {0, 0}), b = vertical({1, 0}, {1, 0});
  const SliceVertexMotion c = vertical({2, 1}, {2.5, -2}), d = vertical({-1, 2}, {3, -4});
  const auto t1 = first_root_after(orientation_certificate(plane, a, b, c), RootTime::zero());
  const auto t2 = first_root_after(orientation_certificate(plane, a, b, d), RootTime::zero());
  ASSERT_TRUE(t1 && t2);
  EXPECT_EQ(compare(*t1, *t2), 0);
  EXPECT_EQ(compare(*t1, RootTime::rational(Rational(1, 3))), 0);
  // A mesh vertex crossing the plane at t = 1/3 as well: z = 1 - 3t.
  const auto t3 = first_root_after(plane_side_certificate(plane, {5, 5, 1}, {5, 5, -2}), RootTime::zero());
  ASSERT_TRUE(t3.has_value());
  EXPECT_TRUE(t3->is_rational());
  EXPECT_EQ(compare(*t3, *t1), 0);

  // An irrational simultaneous event: B moves, A fixed at the origin, D = 2 C (so A, C, D are collinear for
  // all t: that certificate is identically zero). orient(A, B, C) = x_B y_C - y_B x_C.
  const SliceVertexMotion bm = vertical({1, 0}, {1, 1}), cm = vertical({0.5, 0.25}, {1.5, -0.5});
  const SliceVertexMotion dm = vertical({1, 0.5}, {3, -1});
  const auto u1 = first_root_after(orientation_certificate(plane, a, bm, cm), RootTime::zero());
  const auto u2 = first_root_after(orientation_certificate(plane, a, bm, dm), RootTime::zero());
  const auto u3 = first_root_after(orientation_certificate(plane, bm, cm, dm), RootTime::zero());
  ASSERT_TRUE(u1 && u2 && u3);
  EXPECT_FALSE(u1->is_rational());
  EXPECT_EQ(compare(*u1, *u2), 0);
  EXPECT_EQ(compare(*u1, *u3), 0);
  EXPECT_FALSE(first_root_after(orientation_certificate(plane, a, cm, dm), RootTime::zero()).has_value());
}

/// Every event of a certificate in (0, 1], in order (repeated first_root_after from the previous event).
std::vector<RootTime> all_events(const CertificatePolynomial& c) {
  std::vector<RootTime> out;
  RootTime t = RootTime::zero();
  while (const auto next = first_root_after(c, t)) {
    RC_ASSERT(compare(*next, t) > 0);
    out.push_back(*next);
    t = *next;
    RC_ASSERT(out.size() <= 5u);
  }
  return out;
}

RC_GTEST_PROP(CertificatePolynomial, RandomSimultaneousEventsCompareEqual, ()) {
  // Plane z = 0 and vertical edges (slice point = (x, y)): A, B, C, D all move, and at tau = 1/k they lie on
  // one line; a mesh vertex crosses the plane at tau too. Positions at t = 1 are P0 + k (P_tau - P0), exact.
  const SlicingPlane plane = make_test_plane({0, 0, 1}, 0.0);
  const int k = *rc::gen::element(3, 5, 6, 7);
  const auto dyadic = [] { return *rc::gen::inRange(-16, 17) / 8.0; };
  const glm::dvec2 a_tau(dyadic(), dyadic()), b_tau(dyadic(), dyadic());
  RC_PRE(a_tau != b_tau);
  const double lambda = *rc::gen::element(-1.0, 0.5, 2.0, 3.0), mu = *rc::gen::element(-2.0, 1.5, 4.0);
  const auto moving = [&](glm::dvec2 at_tau) {
    const glm::dvec2 p0(dyadic(), dyadic());
    return vertical(p0, p0 + double(k) * (at_tau - p0));
  };
  const SliceVertexMotion a = moving(a_tau), b = moving(b_tau);
  const SliceVertexMotion c = moving(a_tau + lambda * (b_tau - a_tau)),
                          d = moving(a_tau + mu * (b_tau - a_tau));
  const auto crossing =
      first_root_after(plane_side_certificate(plane, {0, 0, 1}, {0, 0, 1.0 - k}), RootTime());
  RC_ASSERT(crossing.has_value());
  RC_ASSERT(crossing->rational_value() == Rational(1, k));
  std::vector<std::optional<RootTime>> at_tau;
  for (const auto& cert :
       {orientation_certificate(plane, a, b, c), orientation_certificate(plane, a, b, d),
        orientation_certificate(plane, b, c, d), orientation_certificate(plane, a, c, d)}) {
    if (cert.exact().is_zero()) continue;  // collinear for all t (e.g. the motions happen to be parallel)
    std::optional<RootTime> hit;
    for (const RootTime& e : all_events(cert))
      if (compare(e, *crossing) == 0) {
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

RC_GTEST_PROP(CertificatePolynomial, PlaneCrossingIsTheExactRationalRoot, ()) {
  const SlicingPlane plane = gen_plane();
  const glm::dvec3 p0 = gen_endpoint(plane, *rc::gen::arbitrary<bool>());
  const glm::dvec3 p1 = gen_endpoint(plane, *rc::gen::arbitrary<bool>());
  const CertificatePolynomial c = plane_side_certificate(plane, p0, p1);
  const Rational s0 = dot(plane.normal, exact(p0)) - Rational(plane.offset);
  const Rational s1 = dot(plane.normal, exact(p1)) - Rational(plane.offset);
  const auto got = first_root_after(c, RootTime::zero());
  RC_CLASSIFY(got.has_value(), "crossing");
  RC_CLASSIFY(CGAL::is_zero(s0) || CGAL::is_zero(s1), "on the plane at 0 or 1");
  if (s0 == s1 || CGAL::sign(s0) * CGAL::sign(s1) > 0 || CGAL::is_zero(s0)) {
    RC_ASSERT(!got.has_value());
    return;
  }
  RC_ASSERT(got.has_value());
  RC_ASSERT(got->is_rational());
  RC_ASSERT(got->rational_value() == s0 / (s0 - s1));
}

// ---- The common case ----------------------------------------------------------------------------------

TEST(CertificatePolynomial, NoEventPathDoesNotAllocate) {
  const SlicingPlane plane = make_test_plane({1, 2, 3}, 0.1);
  // A small triangle of slice vertices drifting slowly: a positive orientation throughout.
  std::vector<SliceVertexMotion> motions;
  for (int i = 0; i < 3; ++i) {
    const glm::dvec3 base = glm::dvec3(i == 1, i == 2, 0) * 0.5;
    const glm::dvec3 c = base - (glm::dot(plane.normal, base) - plane.offset) * plane.normal;
    motions.push_back({c + 0.3 * plane.normal, c + 0.31 * plane.normal + 0.01 * plane.u,
                       c - 0.2 * plane.normal, c - 0.21 * plane.normal + 0.01 * plane.w});
  }
  long events = 0;
  g_allocations = 0;
  g_count_allocations = true;
  for (int k = 0; k < 1000; ++k) {
    const SliceVertexTrack a = track_slice_vertex(plane, motions[0]);
    const SliceVertexTrack b = track_slice_vertex(plane, motions[1]);
    const SliceVertexTrack c = track_slice_vertex(plane, motions[2]);
    events += first_root_after(orientation_certificate(plane, a, b, c), RootTime::zero()).has_value();
    events += first_root_after(plane_side_certificate(plane, motions[0].above0, motions[0].above1),
                               RootTime::zero())
                  .has_value();
  }
  g_count_allocations = false;
  EXPECT_EQ(events, 0);
  EXPECT_EQ(g_allocations.load(), 0);
  EXPECT_TRUE(certainly_no_root(orientation_certificate(plane, motions[0], motions[1], motions[2])));
  // The counter does count: the exact path allocates.
  g_count_allocations = true;
  (void)orientation_certificate(plane, motions[0], motions[1], motions[2]).exact();
  g_count_allocations = false;
  EXPECT_GT(g_allocations.load(), 0);
}

}  // namespace
}  // namespace pleat::kinetic
