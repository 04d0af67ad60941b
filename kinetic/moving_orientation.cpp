#include "kinetic/moving_orientation.hpp"

#include <CGAL/FPU.h>
#include <CGAL/Mpzf.h>

namespace pleat::kinetic {

namespace {
std::array<glm::dvec2, 6> as_points(const MovingPoint& a, const MovingPoint& b, const MovingPoint& c) {
  return {a.from, a.to, b.from, b.to, c.from, c.to};
}
}  // namespace

bool certainly_positive(const MovingPoint& a, const MovingPoint& b, const MovingPoint& c) {
  const auto h = planar_orientation_coefficients<Interval>(as_points(a, b, c));
  return h[0].inf() > 0 && h[1].inf() > 0 && h[2].inf() > 0;
}

std::array<int, 3> bernstein_signs(const MovingPoint& a, const MovingPoint& b, const MovingPoint& c) {
  const auto h = planar_orientation_coefficients<CGAL::Mpzf>(as_points(a, b, c));
  return {static_cast<int>(h[0].sign()), static_cast<int>(h[1].sign()), static_cast<int>(h[2].sign())};
}

CertificatePolynomial orientation_certificate(const MovingPoint& a, const MovingPoint& b,
                                              const MovingPoint& c) {
  return planar_orientation_certificate(as_points(a, b, c));
}

ExactPolynomial orientation_polynomial(const MovingPoint& a, const MovingPoint& b, const MovingPoint& c) {
  return orientation_certificate(a, b, c).exact();
}

CertificateFailure first_failure(const std::array<MovingPoint, 3>& p, const RootTime& t0, bool triangle) {
  using DecidedBy = CertificateFailure::DecidedBy;
  CertificateFailure out;
  {
    CGAL::Protect_FPU_rounding<true> rounding;
    if (certainly_positive(p[0], p[1], p[2])) return out;
  }
  out.certificate = orientation_certificate(p[0], p[1], p[2]);
  if (t0.upper_bound() == 0.0) {
    // The start of the interval: the exact signs of the Bernstein coefficients settle most degenerate
    // certificates (collinear for all t, or touching zero at an end) without rational arithmetic.
    out.decided_by = DecidedBy::exact_signs;
    const std::array<int, 3> s = bernstein_signs(p[0], p[1], p[2]);
    if (s == std::array<int, 3>{0, 0, 0}) {
      if (triangle) out.time = t0, out.fails = true;
      return out;
    }
    if (s[0] >= 0 && s[1] >= 0 && s[2] >= 0) {
      if (s[2] == 0) out.time = RootTime::one();  // its one zero in (0, 1]
      return out;
    }
  }
  // Intervals: a certain sign at t0, then the first zero after t0 by interval subdivision (a simple zero
  // found there is a crossing); root_isolation falls back to rational arithmetic when they cannot decide.
  if (const int s = certain_sign_at(out.certificate, t0); s != 0) {
    out.decided_by = DecidedBy::intervals;
    if (s < 0) {
      out.time = t0, out.fails = true;
      return out;
    }
    IsolationStage stage = IsolationStage::filter;
    out.time = first_root_after(out.certificate, t0, &stage);
    // A zero found by subdivision after a certainly positive start is simple: the certificate crosses it.
    out.fails = out.time && stage == IsolationStage::subdivision;
    if (stage == IsolationStage::exact) out.decided_by = DecidedBy::rationals;
    return out;
  }
  out.decided_by = DecidedBy::rationals;
  const ExactPolynomial poly = out.certificate.exact();
  if (poly.is_zero()) {
    if (triangle) out.time = t0, out.fails = true;
    return out;
  }
  // Fails now: negative just after t0, or a triangle flat at t0 = 1 (created by a flip at the end).
  if (sign_after(poly, t0) < 0 || (triangle && t0 == RootTime::one() && sign_at(poly, t0) == 0))
    out.time = t0, out.fails = true;
  else
    out.time = first_root_after(poly, t0);
  return out;
}

}  // namespace pleat::kinetic
