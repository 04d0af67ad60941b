// Orientation certificates of slice points that move linearly between two frames (DESIGN.md §3).
//
// Motion model. The kinetic layer must end every interval in exactly the state a static recompute builds
// for the next frame, and static_core decides on the slice points as it computes them: doubles, rounded
// once from the mesh positions. So each slice vertex moves on the straight segment from its double point at
// frame k to its double point at frame k+1, p(t) = (1 - t) p0 + t p1. At t = 0 and t = 1 every certificate
// is then exactly the static engine's predicate on the same points; between frames the path differs from
// the intersection of linearly moving mesh edges by O(h^2) in the frame step h, which no sampled cache can
// resolve anyway. Slice vertices appear and vanish only at frame times (a mesh vertex crossing the plane is
// applied as a local edit at the end of the interval it happens in; see kinetic_slice.hpp).
//
// The orientation of three such points is a quadratic in t with homogeneous-Bernstein coefficients
// (B0, 2 B1, B2) on [0, 1]: B0 = u0 x v0, B2 = u1 x v1, 2 B1 = u0 x v1 + u1 x v0, where u = b - a and
// v = c - a at t = 0 and 1. All three strictly positive proves "positive on [0, 1]": the filter, in interval
// arithmetic. Otherwise the certificate goes to root_isolation: interval subdivision, exact only when needed.
// Internal to pleat::kinetic.
#pragma once

#include <array>
#include <glm/vec2.hpp>
#include <optional>

#include "kinetic/root_isolation.hpp"

namespace pleat::kinetic {

/// A slice point on its segment: at t = 0 and at t = 1.
struct MovingPoint {
  glm::dvec2 from{0.0};
  glm::dvec2 to{0.0};
  glm::dvec2 at(double t) const { return from + t * (to - from); }
};

/// True when interval arithmetic proves orient(a(t), b(t), c(t)) > 0 for every t in [0, 1]. No allocation.
/// Precondition: a CGAL::Protect_FPU_rounding<true> guard is alive (rounding towards +infinity).
bool certainly_positive(const MovingPoint& a, const MovingPoint& b, const MovingPoint& c);

/// The exact signs (-1, 0, 1) of the Bernstein coefficients (B0, B1, B2) of orient(a(t), b(t), c(t)) on [0,
/// 1] (CGAL::Mpzf: exact, no allocation for these sizes, no rational arithmetic). All zero: the points stay
/// collinear; all non-negative: the orientation is non-negative on [0, 1], zero in (0, 1] at most at t = 1
/// (when B2 = 0). The exact decision for certificates the interval filter leaves undecided, mostly degenerate
/// ones (collinear slice points of flat or ruled cloth).
std::array<int, 3> bernstein_signs(const MovingPoint& a, const MovingPoint& b, const MovingPoint& c);

/// orient(a(t), b(t), c(t)) as a certificate: its interval enclosure (no allocation), the exact polynomial on
/// demand. root_isolation decides most roots on the enclosure (interval subdivision) without exact
/// arithmetic.
CertificatePolynomial orientation_certificate(const MovingPoint& a, const MovingPoint& b,
                                              const MovingPoint& c);

/// orient(a(t), b(t), c(t)) as an exact polynomial of degree <= 2 (allocates).
ExactPolynomial orientation_polynomial(const MovingPoint& a, const MovingPoint& b, const MovingPoint& c);

/// Where a certificate orient(a(t), b(t), c(t)) >= 0, watched from t0, first needs the kinetic layer. For a
/// `triangle` it must also stay nonzero (a flat triangle is repaired: collinear for all t, it fails at once,
/// and a flip at t = 1 must not leave it flat there); a hull corner may stay flat.
struct CertificateFailure {
  enum class DecidedBy { filter, exact_signs, intervals, rationals };
  std::optional<RootTime> time;  ///< none: it holds on (t0, 1]; else the time of its event (t0: fails now)
  /// Known to fail at `time` (negative just after it, flat for all t, or a triangle flat at t = 1), so the
  /// event needs no exact sign test; false when that is left to the event (a touch is possible).
  bool fails = false;
  DecidedBy decided_by = DecidedBy::filter;
  CertificatePolynomial certificate;  ///< built unless the filter decided
};

/// Cheapest decision first: the interval filter (positive on [0, 1]); at t0 = 0 the exact Bernstein signs;
/// the certificate's interval sign at t0 and interval subdivision for its first zero; rational arithmetic
/// only where intervals cannot decide. Exact in every case.
CertificateFailure first_failure(const std::array<MovingPoint, 3>& p, const RootTime& t0, bool triangle);

}  // namespace pleat::kinetic
