// ConeLighting: per-light irradiance through a clipped visibility cone (see header).
#include "shading/cone_lighting.hpp"

#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <limits>
#include <utility>

namespace pleat {

namespace {
constexpr double kPi = 3.14159265358979323846;

double total_projection(const SphericalPolygonList& list, const glm::dvec3& axis) {
  double sum = 0.0;
  for (std::size_t k = 0; k < list.size; ++k) sum += projected_solid_angle(list[k], axis);
  return sum;
}

/// An orthonormal pair (e1, e2) orthogonal to unit l.
void plane_frame(const glm::dvec3& l, glm::dvec3& e1, glm::dvec3& e2) {
  const glm::dvec3 helper = std::abs(l.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  e1 = glm::normalize(glm::cross(helper, l));
  e2 = glm::cross(l, e1);
}

/// Winding number about l of the orthographic projection of the piece onto the plane (e1, e2) orthogonal
/// to l (Sunday's crossing rule, no trigonometry); `ambiguous` is set when l lies on the great circle of an
/// edge crossing the reference ray (the count is then unreliable).
int projected_winding(const SphericalPolygon& piece, const glm::dvec3& e1, const glm::dvec3& e2,
                      bool& ambiguous) {
  const std::size_t count = piece.size();
  int winding = 0;
  ambiguous = false;
  double ax = glm::dot(piece[count - 1], e1), ay = glm::dot(piece[count - 1], e2);
  for (std::size_t i = 0; i < count; ++i) {
    const double bx = glm::dot(piece[i], e1), by = glm::dot(piece[i], e2);
    const double cross = ax * by - ay * bx;
    if (ay <= 0.0) {
      if (by > 0.0) {
        if (cross == 0.0) ambiguous = true;
        if (cross > 0.0) ++winding;
      }
    } else if (by <= 0.0) {
      if (cross == 0.0) ambiguous = true;
      if (cross < 0.0) --winding;
    }
    ax = bx;
    ay = by;
  }
  return winding;
}

/// Whether unit direction l lies in `piece`, knowing that -l does not (the pieces are clipped to the
/// hemisphere of the axis and axis.l > 0). The winding number about l of the piece's orthographic
/// projection onto the plane (e1, e2) orthogonal to l is winding(l) - winding(-l) (a minor arc projects to
/// less than half an ellipse centred on the origin, so its chord leaves the origin on the same side); if the
/// origin is on the line of a crossing edge (l on that edge's great circle) the exact fan test decides.
bool contains_given_antipode_outside(const SphericalPolygon& piece, const glm::dvec3& l, const glm::dvec3& e1,
                                     const glm::dvec3& e2) {
  if (piece.size() < 3) return false;
  bool ambiguous = false;
  const int winding = projected_winding(piece, e1, e2, ambiguous);
  if (ambiguous) return contains_direction(piece, l);
  return winding > 0;
}

/// Whether HemisphereClipper::clip(piece, axis) would return the piece itself: every vertex in the closed
/// hemisphere and the piece not holding -axis (projected winding 0 or 1, unambiguous). (e1, e2) ⊥ axis.
bool lies_in_hemisphere(const SphericalPolygon& piece, const glm::dvec3& axis, const glm::dvec3& e1,
                        const glm::dvec3& e2) {
  if (piece.size() < 3) return false;
  for (const glm::dvec3& v : piece)
    if (!(glm::dot(axis, v) >= 0.0)) return false;
  bool ambiguous = false;
  const int winding = projected_winding(piece, e1, e2, ambiguous);
  return !ambiguous && (winding == 0 || winding == 1);
}

/// A piece in the hemisphere of axis holds the whole open hemisphere of -up (or of up) only if axis = -up
/// (axis = up): below this margin of axis.up from -1 (1) the cloudy sky's shortcuts are not taken.
constexpr double kOppositeMargin = 1e-9;

}  // namespace

ConeLighting::ConeLighting(const Lighting& lighting) : m_lighting(&lighting) {
  m_needs_pieces = !(lighting.cloudy_skies.empty() && lighting.directional.empty() &&
                     lighting.points.empty() && lighting.areas.empty() && lighting.environments.empty());
}

bool ConeLighting::prepare(const VisibilityCone& cone, const glm::dvec3& axis, bool copy) {
  m_axis = axis;
  m_clipped.clear();
  m_pieces.clear();
  m_in_place.assign(cone.pieces.size(), 0);
  bool all_in_place = !copy;
  if (!copy) {
    glm::dvec3 e1, e2;
    plane_frame(axis, e1, e2);
    for (std::size_t k = 0; k < cone.pieces.size(); ++k) {
      m_in_place[k] = lies_in_hemisphere(cone.pieces[k], axis, e1, e2);
      all_in_place = all_in_place && m_in_place[k];
    }
  }
  // Clip first (m_clipped may grow), then take pointers.
  for (std::size_t k = 0; k < cone.pieces.size(); ++k)
    if (!m_in_place[k]) m_clipper.clip(cone.pieces[k], axis, m_clipped);
  for (std::size_t k = 0; k < cone.pieces.size(); ++k)
    if (m_in_place[k]) m_pieces.push_back(&cone.pieces[k]);
  for (std::size_t k = 0; k < m_clipped.size; ++k) m_pieces.push_back(&m_clipped[k]);
  m_piece_projected.assign(m_pieces.size(), std::numeric_limits<double>::quiet_NaN());
  m_all_in_place = all_in_place;
  return all_in_place;
}

double ConeLighting::piece_projection(std::size_t k) {
  if (std::isnan(m_piece_projected[k])) m_piece_projected[k] = projected_solid_angle(*m_pieces[k], m_axis);
  return m_piece_projected[k];
}

double ConeLighting::set_cone(const VisibilityCone& cone, const glm::dvec3& axis) {
  prepare(cone, axis, /*copy=*/true);
  m_projected = 0.0;
  for (std::size_t k = 0; k < m_pieces.size(); ++k) m_projected += piece_projection(k);
  return m_projected / kPi;
}

ConeIrradiance ConeLighting::evaluate(const VisibilityCone& cone, const glm::dvec3& position,
                                      const glm::dvec3& axis, const ConeMeasures* measures) {
  ConeIrradiance out;
  m_axis = axis;
  if (cone.pieces.empty()) {
    m_pieces.clear();
    m_projected = 0.0;
    return out;
  }
  const bool pieces_needed = m_needs_pieces || measures == nullptr;
  if (pieces_needed) prepare(cone, axis, /*copy=*/false);
  if (measures != nullptr && (!pieces_needed || m_all_in_place)) {
    m_projected = kPi * measures->sky_visibility;  // Lambert's formula on the same pieces (measure_cone)
  } else {
    m_projected = 0.0;
    for (std::size_t k = 0; k < m_pieces.size(); ++k) m_projected += piece_projection(k);
  }
  out.sky_visibility = m_projected / kPi;
  const Lighting& lighting = *m_lighting;
  for (const auto& l : lighting.skies) out.irradiance += uniform_sky(l);
  if (!pieces_needed || m_pieces.empty()) return out;
  for (const auto& l : lighting.cloudy_skies) out.irradiance += hemisphere_sky(l);
  for (const auto& l : lighting.directional) out.irradiance += directional(l);
  for (const auto& l : lighting.points) out.irradiance += point(l, position);
  for (const auto& l : lighting.areas) out.irradiance += area(l, position);
  for (const auto& l : lighting.environments) out.irradiance += environment(l);
  return out;
}

glm::dvec3 ConeLighting::uniform_sky(const UniformSkyLight& light) const {
  return m_projected * light.radiance;
}

glm::dvec3 ConeLighting::hemisphere_sky(const HemisphereSkyLight& light) {
  const double facing = glm::dot(m_axis, light.up);
  const bool may_take_above = facing > -1.0 + kOppositeMargin;
  const bool may_take_below = facing < 1.0 - kOppositeMargin;
  double sum = 0.0;
  bool whole_cone = true;  // every piece entirely above the up horizon
  m_work_a.clear();
  for (std::size_t k = 0; k < m_pieces.size(); ++k) {
    const SphericalPolygon& piece = *m_pieces[k];
    bool above = true, below = true;
    for (const glm::dvec3& v : piece) {
      const double d = glm::dot(light.up, v);
      above = above && d >= 0.0;
      below = below && d <= 0.0;
    }
    if (above && may_take_above) continue;  // added below, all at once when possible
    whole_cone = false;
    if (below && may_take_below) continue;
    m_clipper.clip(piece, light.up, m_work_a);
  }
  if (whole_cone && m_all_in_place) {
    sum = m_projected;  // the cone's own Lambert integral (measures or the pieces' sum)
  } else {
    for (std::size_t k = 0; k < m_pieces.size(); ++k) {
      const SphericalPolygon& piece = *m_pieces[k];
      bool above = true;
      for (const glm::dvec3& v : piece) above = above && glm::dot(light.up, v) >= 0.0;
      if (above && may_take_above) sum += piece_projection(k);
    }
    sum += total_projection(m_work_a, m_axis);
  }
  return sum * light.radiance;
}

bool ConeLighting::sees(const glm::dvec3& l) const {
  // l is above the horizon of the axis, where the clipped pieces and the cone coincide.
  glm::dvec3 e1, e2;
  plane_frame(l, e1, e2);
  for (const SphericalPolygon* piece : m_pieces)
    if (contains_given_antipode_outside(*piece, l, e1, e2)) return true;
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
  if (count < 3 || m_pieces.empty()) return glm::dvec3(0.0);
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
  const SphericalPolygonList* source = nullptr;  // null: the pieces themselves
  for (std::size_t i = 0; i < count; ++i) {
    const glm::dvec3 g = glm::cross(m_light[i], m_light[(i + 1) % count]);
    const double len = glm::length(g);
    if (!(len > 0.0)) continue;  // a vanishing edge (the light is a point from here)
    SphericalPolygonList& target = source == &m_work_a ? m_work_b : m_work_a;
    target.clear();
    if (source == nullptr) {
      for (const SphericalPolygon* piece : m_pieces) m_clipper.clip(*piece, g / len, target);
    } else {
      for (std::size_t k = 0; k < source->size; ++k) m_clipper.clip((*source)[k], g / len, target);
    }
    source = &target;
    if (target.size == 0) return glm::dvec3(0.0);
  }
  if (source == nullptr) return glm::dvec3(0.0);  // every edge vanished: no solid angle
  return total_projection(*source, m_axis) * light.radiance;
}

glm::dvec3 ConeLighting::environment(const EnvironmentLight& light) const {
  glm::dvec3 sum(0.0);
  for (const SphericalPolygon* piece : m_pieces) sum += light.map.integrate_cosine(*piece, m_axis);
  return light.scale * glm::max(sum, glm::dvec3(0.0));
}

}  // namespace pleat
