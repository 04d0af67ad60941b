#include "kinetic/moving_orientation.hpp"

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

CertificatePolynomial orientation_certificate(const MovingPoint& a, const MovingPoint& b, const MovingPoint& c) {
  return planar_orientation_certificate(as_points(a, b, c));
}

ExactPolynomial orientation_polynomial(const MovingPoint& a, const MovingPoint& b, const MovingPoint& c) {
  return orientation_certificate(a, b, c).exact();
}

}  // namespace pleat::kinetic
