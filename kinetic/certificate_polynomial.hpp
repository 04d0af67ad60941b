// Certificate polynomials of the kinetic layer (DESIGN.md §3): a certificate's truth value over one frame
// interval t in [0, 1] is the sign of a polynomial P(t), held as an interval enclosure for the filters and
// built as an exact rational polynomial only where intervals cannot decide.
//
// The engine's certificates (kinetic_slice.hpp: triangle orientation, hull convexity) are orientations of
// three slice points that each move on the straight segment from their double point at frame k to their
// double point at frame k+1 (the motion model, and why it is this one: moving_orientation.hpp). Such an
// orientation is a quadratic in t: planar_orientation_certificate.
//
// Representation: the "homogeneous Bernstein" coefficients H_k of P(t) = sum_k H_k t^k (1 - t)^(n - k), i.e.
// H_k = C(n, k) b_k with b_k the Bernstein coefficients on [0, 1]. For the orientation they are
// (B0, 2 B1, B2), cross products of the points' differences at t = 0 and 1
// (planar_orientation_coefficients), so H is computed from the inputs with no conversion. Two versions of the
// same expression:
//   * an enclosure in interval arithmetic (CGAL::Interval_nt, outward rounding) for the filter and the
//     interval stages of root_isolation; no allocation;
//   * the exact polynomial, built on demand in CGAL::Gmpzf (ring operations on doubles are exact there, no
//     gcd per operation) and handed out as CGAL::Gmpq.
// Measured (bench/root_isolation_bench.cpp, one core of a shared machine, the drape's certificates): a
// certificate built from its six points and passed through root_isolation's filter ~50 ns, the filter alone
// on a built one ~6 ns, the exact polynomial ~7 us. The engine builds a certificate only where
// moving_orientation's certainly_positive (the same enclosure, not kept) cannot decide: 0.8% of them on the
// drape (samples 40 -> 41).
// Exactness: doubles are rationals, and the coefficients are those of the exact motion of the double inputs.
//
// ExactPolynomial is the exact arithmetic root_isolation needs (division, gcd, squarefree part, Bernstein
// coefficients on any interval). CertificatePolynomial::from_exact makes a certificate of any polynomial of
// degree <= kMaxCertificateDegree: root isolation is not limited to the engine's quadratics, and its tests
// use degrees up to 5.
//
// Internal to pleat::kinetic (CGAL number types appear here; they do not leave the kinetic module).
#pragma once

#include <CGAL/Gmpq.h>
#include <CGAL/Interval_nt.h>

#include <array>
#include <glm/vec2.hpp>
#include <variant>
#include <vector>

namespace pleat::kinetic {

using Rational = CGAL::Gmpq;
/// Interval arithmetic without per-operation rounding-mode switches: callers of the interval code below run
/// under CGAL::Protect_FPU_rounding<true> (the functions of this module set it themselves).
using Interval = CGAL::Interval_nt<false>;

/// The highest degree a CertificatePolynomial holds (root_isolation's interval stages are generic up to
/// it); the engine's orientation certificates have degree 2.
inline constexpr int kMaxCertificateDegree = 5;

/// A polynomial in t with exact rational coefficients, monomial basis (coefficient i multiplies t^i).
/// Normalized: no trailing zero coefficients; the zero polynomial has none and degree -1. Allocates.
class ExactPolynomial {
 public:
  ExactPolynomial() = default;
  explicit ExactPolynomial(std::vector<Rational> coefficients);
  /// c * prod_i (t - roots[i]).
  static ExactPolynomial from_roots(const std::vector<Rational>& roots, const Rational& c = Rational(1));
  /// sum_k h[k] t^k (1 - t)^(n - k), n = h.size() - 1.
  static ExactPolynomial from_homogeneous_bernstein(const std::vector<Rational>& h);

  int degree() const { return static_cast<int>(m_c.size()) - 1; }
  bool is_zero() const { return m_c.empty(); }
  const std::vector<Rational>& coefficients() const { return m_c; }
  /// Coefficient of t^i (0 beyond the degree).
  Rational coefficient(int i) const;

  Rational evaluate(const Rational& t) const;
  int sign_at(const Rational& t) const;
  ExactPolynomial derivative() const;
  /// P(a + (b - a) x) as a polynomial in x.
  ExactPolynomial compose_affine(const Rational& a, const Rational& b) const;
  /// Bernstein coefficients of degree max(degree, 0) on [a, b] (b_0 = P(a), b_n = P(b)).
  std::vector<Rational> bernstein(const Rational& a, const Rational& b) const;
  /// H_k = C(n, k) b_k on [0, 1] for Bernstein degree n >= degree().
  std::vector<Rational> homogeneous_bernstein(int n) const;

  friend ExactPolynomial operator+(const ExactPolynomial& a, const ExactPolynomial& b);
  friend ExactPolynomial operator-(const ExactPolynomial& a, const ExactPolynomial& b);
  friend ExactPolynomial operator*(const ExactPolynomial& a, const ExactPolynomial& b);
  friend bool operator==(const ExactPolynomial& a, const ExactPolynomial& b) { return a.m_c == b.m_c; }

  /// Euclidean division; precondition: divisor not zero.
  static void divide(const ExactPolynomial& a, const ExactPolynomial& divisor, ExactPolynomial& quotient,
                     ExactPolynomial& remainder);
  /// Monic greatest common divisor (zero only when both are zero).
  static ExactPolynomial gcd(ExactPolynomial a, ExactPolynomial b);
  /// P / gcd(P, P'): the same roots, all simple. The zero polynomial maps to itself.
  ExactPolynomial squarefree_part() const;
  /// P / (t - r); precondition: P(r) == 0.
  ExactPolynomial deflate(const Rational& r) const;

 private:
  void normalize();
  std::vector<Rational> m_c;
};

/// A certificate's polynomial: interval enclosure of its homogeneous Bernstein coefficients (always), and
/// what is needed to build the exact polynomial on demand: the six points of an orientation, or the
/// polynomial itself (from_exact). A plain value; building one does not allocate (except from_exact).
class CertificatePolynomial {
 public:
  CertificatePolynomial() = default;
  /// Degree of the Bernstein form (2 for the orientation certificates; the exact degree may be lower).
  int degree() const { return m_degree; }
  /// Enclosures of H_0..H_degree (H_k = C(n, k) b_k); sign(H_k) = sign(b_k).
  const std::array<Interval, kMaxCertificateDegree + 1>& enclosure() const { return m_h; }
  /// The exact polynomial (monomial basis). Allocates.
  ExactPolynomial exact() const;

  /// A certificate given by an exact polynomial (tests, and certificates of other shapes). Degree <= 5.
  static CertificatePolynomial from_exact(const ExactPolynomial& p);

 private:
  struct PlanarOrientation {
    std::array<glm::dvec2, 6> points;
  };
  friend CertificatePolynomial planar_orientation_certificate(const std::array<glm::dvec2, 6>&);

  // m_degree last: Interval is 16-byte aligned, so an int before m_h would add 12 bytes of padding to
  // every queued event.
  std::array<Interval, kMaxCertificateDegree + 1> m_h{};
  std::variant<std::monostate, PlanarOrientation, ExactPolynomial> m_source;
  int m_degree = -1;
};

/// The homogeneous-Bernstein coefficients (B0, 2 B1, B2) of orient(a(t), b(t), c(t)) for points moving
/// linearly in a plane, p(t) = (1 - t) p0 + t p1, given as {a0, a1, b0, b1, c0, c1}: B0 = u0 x v0, B2 = u1 x
/// v1, 2 B1 = u0 x v1 + u1 x v0 with u = b - a, v = c - a at t = 0 and 1 (kinetic/moving_orientation.hpp). N:
/// any ring the doubles convert into exactly (an interval type for enclosures, an exact type).
template <class N>
std::array<N, 3> planar_orientation_coefficients(const std::array<glm::dvec2, 6>& p) {
  auto cross = [](const N& ux, const N& uy, const N& vx, const N& vy) { return ux * vy - uy * vx; };
  const N u0x = N(p[2].x) - N(p[0].x), u0y = N(p[2].y) - N(p[0].y);
  const N v0x = N(p[4].x) - N(p[0].x), v0y = N(p[4].y) - N(p[0].y);
  const N u1x = N(p[3].x) - N(p[1].x), u1y = N(p[3].y) - N(p[1].y);
  const N v1x = N(p[5].x) - N(p[1].x), v1y = N(p[5].y) - N(p[1].y);
  return {cross(u0x, u0y, v0x, v0y), cross(u0x, u0y, v1x, v1y) + cross(u1x, u1y, v0x, v0y),
          cross(u1x, u1y, v1x, v1y)};
}

/// The orientation certificate of three points moving linearly in a plane (degree 2; the points as in
/// planar_orientation_coefficients): an interval enclosure now, the exact polynomial on demand (CGAL::Gmpzf).
CertificatePolynomial planar_orientation_certificate(const std::array<glm::dvec2, 6>& points);

}  // namespace pleat::kinetic
