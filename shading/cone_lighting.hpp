// ConeLighting: the direct irradiance reaching one (vertex, side) through its visibility cone, under every
// light of a Lighting (docs/method.md §10; Stewart 1999 §4: once the cones exist, any lighting is a cheap
// pass).
//
// Per call: the cone's pieces are clipped to the hemisphere of the side axis m = side * n(v) (great-circle
// Sutherland–Hodgman with horizon stitching, static_core/spherical_polygon.hpp), then each light adds
//   uniform sky L            E = L * sum_k proj(piece_k, m)                        (Lambert's formula)
//   cloudy sky L about up    E = L * sum_k proj(piece_k cap hemisphere(up), m)
//   directional E0 along d   E = E0 * (m.l) if l = -d is inside a piece (m.l > 0)
//   point I at p             E = I * (m.l) / |p - x|^2 if l = (p - x)/|p - x| is inside a piece
//   area polygon, L          E = L * sum proj(piece_k cap light, m): the light as seen from x is a convex
//                            spherical polygon; each (possibly non-convex) piece is clipped by the great
//                            circles of its edges in turn (Sutherland–Hodgman is exact for a convex clipper)
//   environment map          E = scale * sum_k integral_{piece_k} L(w) (m.w) dw (environment_map.hpp)
// and the sky visibility A = sum_k proj(piece_k, m) / pi (docs/method.md §1).
// Inside-cone test: a winding number, valid for any simple piece, star-shaped or not. Since the clipped
// pieces lie in the hemisphere of m and m.l > 0, -l is in no piece, so the winding about l of the piece's
// orthographic projection onto the plane orthogonal to l (Sunday's crossing rule, no trigonometry) is
// exact; when l lies on the great circle of a crossing edge, contains_direction (a Van Oosterom–Strackee
// fan from -l, exact for any polygon) decides.
// Limitation: a cone says which directions escape to infinity; a point or area light closer than an
// occluder in that direction is still treated as blocked (use light-specific slicing plans for that).
// Fast paths (exact, no accuracy lost): the cones of compute_visibility already lie in the closed hemisphere
// of their side axis (assemble_cone), so clipping them is the identity; a piece is used in place (no copy,
// no clip) when all its vertices have axis.v >= 0 and its projected winding about the axis is 0 or 1 (the
// clipper's own test), and clipped otherwise. Given the cone's ConeMeasures (measure_cone: Lambert's
// formula on the same pieces), A and the uniform sky's E = pi L A cost nothing per edge, and a lighting of
// skies only never looks at the pieces. The cloudy sky clips a piece by the up hemisphere only when the piece
// straddles its horizon: a piece with every vertex above (below) lies in it (outside it) entirely, since a
// region within the axis hemisphere cannot hold the whole opposite up-hemisphere unless axis = -up (checked
// with a margin), so it adds its unclipped Lambert integral (nothing).
// Cost: O(cone edges x (#lights + light edges)) at most; skies O(1) with measures; environment maps add
// O(map columns spanned by the edges). Allocation: none once each scratch list has grown to its working
// size. One instance per thread.
#pragma once

#include <glm/vec3.hpp>
#include <span>
#include <vector>

#include "shading/lights.hpp"
#include "static_core/spherical_polygon.hpp"
#include "static_core/visibility_cone.hpp"

namespace pleat {

struct ConeIrradiance {
  glm::dvec3 irradiance{0.0};   ///< direct irradiance from all lights, linear RGB
  double sky_visibility = 0.0;  ///< A: cosine-weighted visible fraction of the hemisphere about the axis
};

/// The sum of proj(piece, axis) over `list`.
double total_projection(const SphericalPolygonList& list, const glm::dvec3& axis);

class ConeLighting {
 public:
  /// `lighting` must outlive this object.
  explicit ConeLighting(const Lighting& lighting);

  /// All lights through `cone` at `position`, for the side axis `axis` (unit, side * n(v)). `measures`, if
  /// given, must be measure_cone(cone, axis) (FrameVisibility::measures): A is then read from it, not
  /// recomputed. The cone must outlive the call only.
  ConeIrradiance evaluate(const VisibilityCone& cone, const glm::dvec3& position, const glm::dvec3& axis,
                          const ConeMeasures* measures = nullptr);

  // The steps of evaluate(), usable one by one (tests, tools): clip first, then any light.
  /// Clips the cone to the hemisphere of `axis` (a copy: the cone need not outlive the call); returns A.
  /// The per-light functions below use that clip.
  double set_cone(const VisibilityCone& cone, const glm::dvec3& axis);
  /// The pieces the per-light functions integrate over (the cone clipped to the axis hemisphere).
  std::size_t num_pieces() const { return m_pieces.size(); }
  const SphericalPolygon& piece(std::size_t k) const { return *m_pieces[k]; }

  /// One light through the set cone at `position` (its kind's cone_irradiance, shading/light_kind.hpp).
  template <class Kind>
  glm::dvec3 irradiance(const Kind& light, const glm::dvec3& position = glm::dvec3(0.0)) {
    return light.cone_irradiance(*this, position);
  }

  // What the kinds of light read (shading/light_kind.hpp), for the cone set last.
  const glm::dvec3& axis() const { return m_axis; }
  /// proj(cone, axis): the sum of the pieces' projected solid angles (or the measures' pi A).
  double projected() const { return m_projected; }
  /// Whether the pieces are the cone's own (none clipped): projected() is then their sum.
  bool all_in_place() const { return m_all_in_place; }
  std::span<const SphericalPolygon* const> pieces() const { return m_pieces; }
  /// proj(piece k, axis), computed once per cone.
  double piece_projection(std::size_t k);
  /// Whether unit direction l (with axis.l > 0) lies in one of the cone's pieces.
  bool sees(const glm::dvec3& l) const;
  HemisphereClipper& clipper() { return m_clipper; }
  /// Two lists and a polygon of scratch memory, reused from call to call.
  SphericalPolygonList& scratch(int i) { return i == 0 ? m_work_a : m_work_b; }
  SphericalPolygon& scratch_polygon() { return m_light; }

 private:
  /// Sets m_pieces: the cone's pieces that lie in the axis hemisphere in place, the others clipped into
  /// m_clipped (or, with copy, every piece clipped into m_clipped). Returns whether all were in place.
  bool prepare(const VisibilityCone& cone, const glm::dvec3& axis, bool copy);

  const Lighting* m_lighting;
  bool m_needs_pieces = true;  // some light whose kind reads the pieces
  glm::dvec3 m_axis{0.0, 0.0, 1.0};
  double m_projected = 0.0;     // sum of proj(piece_k, axis)
  bool m_all_in_place = false;  // m_pieces are the cone's own pieces (so m_projected is their sum)
  std::vector<const SphericalPolygon*> m_pieces;
  std::vector<double> m_piece_projected;  // per piece; NaN until computed
  std::vector<char> m_in_place;
  HemisphereClipper m_clipper;
  SphericalPolygonList m_clipped;
  SphericalPolygonList m_work_a, m_work_b;
  SphericalPolygon m_light;
};

}  // namespace pleat
