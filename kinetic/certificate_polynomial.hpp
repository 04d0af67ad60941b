// Certificate polynomials of the kinetic layer (DESIGN.md §3; Stewart 1999 §6 "future work").
//
// Between two frames every mesh vertex moves linearly, p(t) = p0 (1 - t) + p1 t for t in [0, 1], and the
// slicing planes stay fixed. A slice vertex on the mesh edge (a = above, b = below) has homogeneous 2D
// coordinates X = s_a U_b - s_b U_a, Y = s_a V_b - s_b V_a, W = s_a - s_b with s = n.p - d, U = u.p,
// V = w.p, all linear in t. The orientation of three slice vertices is det[[X_i, Y_i, W_i]] / (W1 W2 W3), a
// polynomial of degree <= 5 over a positive denominator (W > 0 while a is on or above and b below the
// plane). Every orientation certificate of the kinetic layer (triangle orientation, hull convexity, SPT
// tautness of grandparent/parent/node) is this polynomial; a mesh vertex's side of a plane is the linear
// s(t).
//
// Representation: the "homogeneous Bernstein" coefficients H_k of P(t) = sum_k H_k t^k (1 - t)^(n - k),
// i.e. H_k = C(n, k) b_k with b_k the Bernstein coefficients on [0, 1]. Products of such forms are plain
// convolutions and every product in det[...] has total degree 5, so H is computed from the inputs with no
// conversion and no constant other than small integers. Two versions of the same expression:
//   * an enclosure in interval arithmetic (CGAL::Interval_nt, outward rounding) for the fast filter:
//     no allocation; measured (bench/root_isolation_bench.cpp, one core): a SliceVertexTrack ~140 ns, an
//     orientation certificate from three tracks ~135 ns, from raw positions ~500 ns, a plane side ~37 ns;
//   * the exact rational polynomial, built on demand in CGAL::Gmpzf (ring operations on doubles are exact
//     there, no gcd per operation) and handed out as CGAL::Gmpq: ~38 us; only when the filter fails.
// Exactness: doubles are rationals; n.p - d, u.p, w.p and the products are evaluated in Gmpq, so the
// coefficients are those of the true motion of the double inputs (no rounding of the slice points).
//
// Note: static_core rounds slice points to doubles before its exact predicates; near-degenerate
// configurations may therefore be decided differently there than by these (truly exact) certificates.
//
// Internal to pleat::kinetic (CGAL number types appear here; they do not leave the kinetic module).
#pragma once

#include <CGAL/Gmpq.h>
#include <CGAL/Interval_nt.h>

#include <array>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <variant>
#include <vector>

#include "static_core/slicing_plan.hpp"

namespace pleat::kinetic {

using Rational = CGAL::Gmpq;
/// Interval arithmetic without per-operation rounding-mode switches: callers of the interval code below run
/// under CGAL::Protect_FPU_rounding<true> (the functions of this module set it themselves).
using Interval = CGAL::Interval_nt<false>;

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

/// A slice vertex's mesh edge at the two frames: `above` is the endpoint on or above the plane, `below` the
/// one strictly below (mesh_slicer's SliceVertex::above/below), so that W(t) = s_a - s_b > 0 while it exists.
struct SliceVertexMotion {
  glm::dvec3 above0{0.0}, above1{0.0};  ///< the upper endpoint at t = 0 and t = 1
  glm::dvec3 below0{0.0}, below1{0.0};  ///< the lower endpoint at t = 0 and t = 1
};

/// A slice vertex's homogeneous coordinates as interval homogeneous-Bernstein polynomials (X, Y degree 2,
/// W degree 1), computed once per slice vertex and frame interval and shared by every certificate using it.
struct SliceVertexTrack {
  SliceVertexMotion motion;
  std::array<Interval, 3> x, y;
  std::array<Interval, 2> w;
};

/// A certificate's polynomial: interval enclosure of its homogeneous Bernstein coefficients (always), and
/// what is needed to build the exact polynomial on demand. A plain value; building one does not allocate
/// (except from_exact).
class CertificatePolynomial {
 public:
  CertificatePolynomial() = default;
  /// Degree of the Bernstein form (5 for orientations, 1 for plane sides; the exact degree may be lower).
  int degree() const { return m_degree; }
  /// Enclosures of H_0..H_degree (H_k = C(n, k) b_k); sign(H_k) = sign(b_k).
  const std::array<Interval, kMaxCertificateDegree + 1>& enclosure() const { return m_h; }
  /// The exact polynomial (monomial basis). Allocates; costs a few microseconds for an orientation.
  ExactPolynomial exact() const;

  /// A certificate given by an exact polynomial (tests, and certificates of other shapes). Degree <= 5.
  static CertificatePolynomial from_exact(const ExactPolynomial& p);

 private:
  struct Orientation {
    SlicingPlane plane;
    std::array<SliceVertexMotion, 3> vertices;
  };
  struct PlaneSide {
    SlicingPlane plane;
    glm::dvec3 p0, p1;
  };
  struct PlanarOrientation {
    std::array<glm::dvec2, 6> points;
  };
  friend CertificatePolynomial orientation_certificate(const SlicingPlane&, const SliceVertexTrack&,
                                                       const SliceVertexTrack&, const SliceVertexTrack&);
  friend CertificatePolynomial plane_side_certificate(const SlicingPlane&, const glm::dvec3&,
                                                      const glm::dvec3&);
  friend CertificatePolynomial planar_orientation_certificate(const std::array<glm::dvec2, 6>&);

  int m_degree = -1;
  std::array<Interval, kMaxCertificateDegree + 1> m_h{};
  std::variant<std::monostate, Orientation, PlaneSide, PlanarOrientation, ExactPolynomial> m_source;
};

/// Interval homogeneous coordinates of one slice vertex (about 90 interval operations, no allocation).
SliceVertexTrack track_slice_vertex(const SlicingPlane& plane, const SliceVertexMotion& motion);

/// The orientation certificate of slice vertices (a, b, c) in the plane's (u, w) frame: its polynomial is
/// det[[X_a, Y_a, W_a], [X_b, Y_b, W_b], [X_c, Y_c, W_c]], of degree <= 5, whose sign is the sign of the
/// orientation (counterclockwise positive) while the three slice vertices exist (W > 0). Used for triangle
/// orientation, hull convexity (prev, v, next) and SPT tautness (grandparent, parent, node).
CertificatePolynomial orientation_certificate(const SlicingPlane& plane, const SliceVertexTrack& a,
                                              const SliceVertexTrack& b, const SliceVertexTrack& c);
CertificatePolynomial orientation_certificate(const SlicingPlane& plane, const SliceVertexMotion& a,
                                              const SliceVertexMotion& b, const SliceVertexMotion& c);

/// The side certificate of a mesh vertex moving from p0 to p1: s(t) = n.p(t) - d (degree 1). Its root is the
/// rational -s(0) / (s(1) - s(0)). Under the slicer's symbolic perturbation s = 0 counts as above.
CertificatePolynomial plane_side_certificate(const SlicingPlane& plane, const glm::dvec3& p0,
                                             const glm::dvec3& p1);

/// The homogeneous-Bernstein coefficients (B0, 2 B1, B2) of orient(a(t), b(t), c(t)) for points moving linearly
/// in a plane, p(t) = (1 - t) p0 + t p1, given as {a0, a1, b0, b1, c0, c1}: B0 = u0 x v0, B2 = u1 x v1,
/// 2 B1 = u0 x v1 + u1 x v0 with u = b - a, v = c - a at t = 0 and 1 (kinetic/moving_orientation.hpp). N: any
/// ring the doubles convert into exactly (an interval type for enclosures, an exact type).
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

/// Exact homogeneous-Bernstein coefficients H_0..H_5 of the orientation polynomial (test and debug aid).
std::array<Rational, 6> exact_orientation_coefficients(const SlicingPlane& plane, const SliceVertexMotion& a,
                                                       const SliceVertexMotion& b,
                                                       const SliceVertexMotion& c);

}  // namespace pleat::kinetic
