// ConeLighting: per-light irradiance through a clipped visibility cone (see header).
#include "shading/cone_lighting.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <cmath>
#include <utility>

namespace pleat {

namespace {
constexpr double kPi = 3.14159265358979323846;

double total_projection(const SphericalPolygonList& list, const glm::dvec3& axis) {
  double sum = 0.0;
  for (std::size_t k = 0; k < list.size; ++k) sum += projected_solid_angle(list[k], axis);
  return sum;
}
/// Whether unit direction l lies in `piece`, knowing that -l does not (the pieces are clipped to the
/// hemisphere of the axis and axis.l > 0). The winding number about l of the piece's orthographic
/// projection onto the plane orthogonal to l is winding(l) - winding(-l) (a minor arc projects to less
/// than half an ellipse centred on the origin, so its chord leaves the origin on the same side), computed
/// by Sunday's crossing rule without trigonometry; if the origin is on the line of a crossing edge (l on
/// that edge's great circle) the exact fan test decides.
bool contains_given_antipode_outside(const SphericalPolygon& piece, const glm::dvec3& l) {
  const std::size_t count = piece.size();
  if (count < 3) return false;
  const glm::dvec3 helper = std::abs(l.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 e1 = glm::normalize(glm::cross(helper, l));
  const glm::dvec3 e2 = glm::cross(l, e1);
  int winding = 0;
  double ax = glm::dot(piece[count - 1], e1), ay = glm::dot(piece[count - 1], e2);
  for (std::size_t i = 0; i < count; ++i) {
    const double bx = glm::dot(piece[i], e1), by = glm::dot(piece[i], e2);
    const double cross = ax * by - ay * bx;
    if (ay <= 0.0) {
      if (by > 0.0) {
        if (cross == 0.0) return contains_direction(piece, l);
        if (cross > 0.0) ++winding;
      }
    } else if (by <= 0.0) {
      if (cross == 0.0) return contains_direction(piece, l);
      if (cross < 0.0) --winding;
    }
    ax = bx;
    ay = by;
  }
  return winding > 0;
}

}  // namespace

double ConeLighting::set_cone(const VisibilityCone& cone, const glm::dvec3& axis) {
  m_axis = axis;
  m_clipped.clear();
  for (const SphericalPolygon& piece : cone.pieces) m_clipper.clip(piece, axis, m_clipped);
  m_projected = total_projection(m_clipped, axis);
  return m_projected / kPi;
}

ConeIrradiance ConeLighting::evaluate(const VisibilityCone& cone, const glm::dvec3& position, const glm::dvec3& axis) {
  ConeIrradiance out;
  out.sky_visibility = set_cone(cone, axis);
  if (m_clipped.size == 0) return out;
  const Lighting& lighting = *m_lighting;
  for (const auto& l : lighting.skies) out.irradiance += uniform_sky(l);
  for (const auto& l : lighting.cloudy_skies) out.irradiance += hemisphere_sky(l);
  for (const auto& l : lighting.directional) out.irradiance += directional(l);
  for (const auto& l : lighting.points) out.irradiance += point(l, position);
  for (const auto& l : lighting.areas) out.irradiance += area(l, position);
  for (const auto& l : lighting.environments) out.irradiance += environment(l);
  return out;
}

glm::dvec3 ConeLighting::uniform_sky(const UniformSkyLight& light) const { return m_projected * light.radiance; }

glm::dvec3 ConeLighting::hemisphere_sky(const HemisphereSkyLight& light) {
  m_work_a.clear();
  for (std::size_t k = 0; k < m_clipped.size; ++k) m_clipper.clip(m_clipped[k], light.up, m_work_a);
  return total_projection(m_work_a, m_axis) * light.radiance;
}

bool ConeLighting::sees(const glm::dvec3& l) const {
  // l is above the horizon of the axis, where the clipped pieces and the cone coincide.
  for (std::size_t k = 0; k < m_clipped.size; ++k)
    if (contains_given_antipode_outside(m_clipped[k], l)) return true;
  return false;
}

glm::dvec3 ConeLighting::directional(const DirectionalLight& light) const {
  const glm::dvec3 l = -light.direction;
  const double cosine = glm::dot(m_axis, l);
  if (!(cosine > 0.0) || !sees(l)) return glm::dvec3(0.0);
  return cosine * light.irradiance;
}

glm::dvec3 ConeLighting::point(const PointLight& light, const glm::dvec3& position) const {
  const glm::dvec3 d = light.position - position;
  const double d2 = glm::dot(d, d);
  if (!(d2 > 0.0)) return glm::dvec3(0.0);
  const glm::dvec3 l = d / std::sqrt(d2);
  const double cosine = glm::dot(m_axis, l);
  if (!(cosine > 0.0) || !sees(l)) return glm::dvec3(0.0);
  return (cosine / d2) * light.intensity;
}

glm::dvec3 ConeLighting::area(const AreaLight& light, const glm::dvec3& position) {
  const std::size_t count = light.polygon.size();
  if (count < 3 || m_clipped.size == 0) return glm::dvec3(0.0);
  const double facing = glm::dot(position - light.polygon[0], light.normal);
  if (facing == 0.0 || (!light.two_sided && facing < 0.0)) return glm::dvec3(0.0);
  // The light as seen from x, counter-clockwise about its interior (seen from outside the unit sphere):
  // the vertex order is right-handed about the light's normal, which appears clockwise from its front.
  m_light.clear();
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t j = facing > 0.0 ? count - 1 - i : i;
    const glm::dvec3 d = light.polygon[j] - position;
    m_light.push_back(d / glm::length(d));
  }
  // Clip every piece by the half-spaces of the light's edges in turn.
  const SphericalPolygonList* source = &m_clipped;
  for (std::size_t i = 0; i < count; ++i) {
    const glm::dvec3 g = glm::cross(m_light[i], m_light[(i + 1) % count]);
    const double len = glm::length(g);
    if (!(len > 0.0)) continue;  // a vanishing edge (the light is a point from here)
    SphericalPolygonList& target = source == &m_work_a ? m_work_b : m_work_a;
    target.clear();
    for (std::size_t k = 0; k < source->size; ++k) m_clipper.clip((*source)[k], g / len, target);
    source = &target;
    if (target.size == 0) return glm::dvec3(0.0);
  }
  if (source == &m_clipped) return glm::dvec3(0.0);  // every edge vanished: no solid angle
  return total_projection(*source, m_axis) * light.radiance;
}

glm::dvec3 ConeLighting::environment(const EnvironmentLight& light) const {
  glm::dvec3 sum(0.0);
  for (std::size_t k = 0; k < m_clipped.size; ++k) sum += light.map.integrate_cosine(m_clipped[k], m_axis);
  return light.scale * glm::max(sum, glm::dvec3(0.0));
}

}  // namespace pleat
