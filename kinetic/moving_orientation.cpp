#include "kinetic/moving_orientation.hpp"

#include <CGAL/Interval_nt.h>

namespace pleat::kinetic {
namespace {

template <class N>
N cross(const N& ax, const N& ay, const N& bx, const N& by) {
  return ax * by - ay * bx;
}

}  // namespace

bool certainly_positive(const MovingPoint& a, const MovingPoint& b, const MovingPoint& c) {
  using I = Interval;
  const I u0x = I(b.from.x) - I(a.from.x), u0y = I(b.from.y) - I(a.from.y);
  const I v0x = I(c.from.x) - I(a.from.x), v0y = I(c.from.y) - I(a.from.y);
  const I u1x = I(b.to.x) - I(a.to.x), u1y = I(b.to.y) - I(a.to.y);
  const I v1x = I(c.to.x) - I(a.to.x), v1y = I(c.to.y) - I(a.to.y);
  const I b0 = cross(u0x, u0y, v0x, v0y);
  if (!(b0.inf() > 0)) return false;
  const I b2 = cross(u1x, u1y, v1x, v1y);
  if (!(b2.inf() > 0)) return false;
  const I b1 = cross(u0x, u0y, v1x, v1y) + cross(u1x, u1y, v0x, v0y);
  return b1.inf() > 0;
}

ExactPolynomial orientation_polynomial(const MovingPoint& a, const MovingPoint& b, const MovingPoint& c) {
  using Q = Rational;
  const Q u0x = Q(b.from.x) - Q(a.from.x), u0y = Q(b.from.y) - Q(a.from.y);
  const Q v0x = Q(c.from.x) - Q(a.from.x), v0y = Q(c.from.y) - Q(a.from.y);
  const Q u1x = Q(b.to.x) - Q(a.to.x), u1y = Q(b.to.y) - Q(a.to.y);
  const Q v1x = Q(c.to.x) - Q(a.to.x), v1y = Q(c.to.y) - Q(a.to.y);
  return ExactPolynomial::from_homogeneous_bernstein(
      {cross(u0x, u0y, v0x, v0y), cross(u0x, u0y, v1x, v1y) + cross(u1x, u1y, v0x, v0y), cross(u1x, u1y, v1x, v1y)});
}

}  // namespace pleat::kinetic
