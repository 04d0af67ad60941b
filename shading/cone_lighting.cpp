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

}  // namespace

double total_projection(const SphericalPolygonList& list, const glm::dvec3& axis) {
  double sum = 0.0;
  for (std::size_t k = 0; k < list.size; ++k) sum += projected_solid_angle(list[k], axis);
  return sum;
}

ConeLighting::ConeLighting(const Lighting& lighting) : m_lighting(&lighting) {
  m_needs_pieces = false;
  lighting.for_each([&](const auto& light) { m_needs_pieces = m_needs_pieces || light.kNeedsPieces; });
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
  // Kind by kind (Lighting::for_each); a kind that reads the pieces adds nothing without them.
  const bool pieces = pieces_needed && !m_pieces.empty();
  m_lighting->for_each([&](const auto& light) {
    if (pieces || !light.kNeedsPieces) out.irradiance += light.cone_irradiance(*this, position);
  });
  return out;
}

bool ConeLighting::sees(const glm::dvec3& l) const {
  // l is above the horizon of the axis, where the clipped pieces and the cone coincide.
  glm::dvec3 e1, e2;
  plane_frame(l, e1, e2);
  for (const SphericalPolygon* piece : m_pieces)
    if (contains_given_antipode_outside(*piece, l, e1, e2)) return true;
  return false;
}

}  // namespace pleat
