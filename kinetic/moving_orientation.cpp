#include "kinetic/moving_orientation.hpp"

#include <CGAL/Interval_nt.h>

#include <array>

namespace pleat::kinetic {
namespace {

/// The homogeneous-Bernstein coefficients (B0, 2 B1, B2) of orient(a(t), b(t), c(t)) in the number type N
/// (Interval for the filter, Rational for the exact polynomial); the doubles convert exactly into either.
template <class N>
std::array<N, 3> orientation_coefficients(const MovingPoint& a, const MovingPoint& b, const MovingPoint& c) {
  auto cross = [](const N& ux, const N& uy, const N& vx, const N& vy) { return ux * vy - uy * vx; };
  const N u0x = N(b.from.x) - N(a.from.x), u0y = N(b.from.y) - N(a.from.y);
  const N v0x = N(c.from.x) - N(a.from.x), v0y = N(c.from.y) - N(a.from.y);
  const N u1x = N(b.to.x) - N(a.to.x), u1y = N(b.to.y) - N(a.to.y);
  const N v1x = N(c.to.x) - N(a.to.x), v1y = N(c.to.y) - N(a.to.y);
  return {cross(u0x, u0y, v0x, v0y), cross(u0x, u0y, v1x, v1y) + cross(u1x, u1y, v0x, v0y), cross(u1x, u1y, v1x, v1y)};
}

}  // namespace

bool certainly_positive(const MovingPoint& a, const MovingPoint& b, const MovingPoint& c) {
  const auto h = orientation_coefficients<Interval>(a, b, c);
  return h[0].inf() > 0 && h[1].inf() > 0 && h[2].inf() > 0;
}

ExactPolynomial orientation_polynomial(const MovingPoint& a, const MovingPoint& b, const MovingPoint& c) {
  const auto h = orientation_coefficients<Rational>(a, b, c);
  return ExactPolynomial::from_homogeneous_bernstein({h[0], h[1], h[2]});
}

}  // namespace pleat::kinetic
