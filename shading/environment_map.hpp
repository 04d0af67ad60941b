// EnvironmentMap: an equirectangular radiance map (linear RGB), and the exact integral of L(w) (n.w) over a
// spherical polygon (a visibility-cone piece) for the shading of docs/method.md §10.
//
// Radiance model. The map is piecewise constant: texel (column c, row r) holds the mean radiance over its
// patch of directions (box reconstruction), so integrals over regions are well defined at any resolution.
// Mapping (orientation frame X', Y', U with X' x Y' = U, psi = atan2(w.Y', w.X') counter-clockwise about U):
//   u = fract((rotation - psi) / 2 pi),  v = theta / pi,  theta = acos(w.U)  (row 0 at the top, towards U).
// For up = +Z this is Blender's world mapping (u = 0.5 + atan2(w.y, -w.x) / 2 pi); `rotation` turns the map
// about U. .hdr files load as linear floats (stbi_loadf), 8-bit images (.png, .jpg) as sRGB -> linear.
//
// Integration method (exact for the piecewise-constant map up to edge-quadrature round-off). By Green's
// theorem in (psi, theta), for P counter-clockwise and not holding the bottom pole -U:
//   integral_P g dw = sum_edges integral G(psi, theta_edge(psi)) dpsi,
//   G(psi, theta) = integral_0^theta g(psi, t) sin t dt   (the region swept from the top pole U);
// a polygon in the hemisphere of n with n.U < 0 is swept from -U instead (G replaced by minus the integral
// from theta to pi), so the pole used is never inside the polygon nor on its boundary.
// With g = L (n.w), n.w = sin t (n'_x cos psi + n'_y sin psi) + n'_z cos t, and L constant per texel, G is
//   (n'_x cos psi + n'_y sin psi) S2_c(theta) + n'_z SC_c(theta),
// where S2_c, SC_c are per-column prefix sums over rows of L * integral sin^2 and L * integral sin cos (exact
// closed forms, partial rows included). Each edge (a great-circle arc, theta_edge(psi) in closed form) is
// walked column by column with 3-point Gauss–Legendre on sub-steps no taller than a row. Cost per polygon:
// O(columns spanned by its edges), independent of its area; tables: 2 x width x (height + 1) RGB floats.
// Wider maps can be box-filtered down at load (max_width) to trade detail for speed.
#pragma once

#include <filesystem>
#include <glm/vec3.hpp>
#include <vector>

#include "static_core/spherical_polygon.hpp"

namespace pleat {

struct EnvironmentOrientation {
  glm::dvec3 up{0.0, 0.0, 1.0};   ///< the map's top row looks along up
  double rotation_degrees = 0.0;  ///< turn of the map about up
};

/// Default width maps are box-filtered down to at load: one texel is 1.4 degrees, finer than the cone
/// polygons resolve, and the integral's cost grows with the columns an edge crosses (docs/benchmarks.md,
/// "Shading and relighting": about a quarter of the full width's cost).
inline constexpr int kDefaultEnvironmentWidth = 256;

class EnvironmentMap {
 public:
  EnvironmentMap() = default;
  /// From linear RGB texels, row-major from the top row; throws std::invalid_argument on bad sizes.
  EnvironmentMap(int width, int height, std::vector<glm::vec3> texels,
                 const EnvironmentOrientation& orientation = {});

  /// Loads an .hdr (linear) or 8-bit image (sRGB -> linear); box-filters down by powers of two until the
  /// width is at most max_width (0: keep). Throws InputError naming the file on failure.
  static EnvironmentMap load(const std::filesystem::path& path,
                             const EnvironmentOrientation& orientation = {},
                             int max_width = kDefaultEnvironmentWidth);

  int width() const { return m_width; }
  int height() const { return m_height; }
  bool empty() const { return m_width == 0; }
  const EnvironmentOrientation& orientation() const { return m_orientation; }

  /// The (piecewise-constant) radiance seen along unit direction w.
  glm::dvec3 radiance(const glm::dvec3& w) const;
  /// The texel (column, row) that direction w falls in.
  void texel_of(const glm::dvec3& w, int& column, int& row) const;

  /// integral over `poly` of L(w) (n.w) dw: the irradiance from the map through poly.
  /// Precondition: poly lies in the closed hemisphere of n (clip_to_hemisphere / HemisphereClipper), is
  /// simple or weakly simple, counter-clockwise, with minor-arc edges. Thread-safe (const).
  glm::dvec3 integrate_cosine(const SphericalPolygon& poly, const glm::dvec3& n) const;

  /// integral over the whole sphere of L(w) w dw (per channel: x, y, z components as three RGB vectors).
  glm::dvec3 sphere_moment(int axis) const { return m_sphere_moment[axis]; }

 private:
  void build_tables();
  glm::dvec3 to_local(const glm::dvec3& w) const;
  int column_of_psi(double psi) const;
  /// Contribution of the edge a -> b (local coordinates) to the contour integral, for local normal nl.
  /// from_bottom: G swept from the bottom pole -U instead of the top pole U.
  glm::dvec3 edge_integral(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& nl,
                           bool from_bottom) const;

  int m_width = 0;
  int m_height = 0;
  EnvironmentOrientation m_orientation;
  glm::dvec3 m_x{1, 0, 0}, m_y{0, 1, 0}, m_u{0, 0, 1};  // local frame X', Y', U
  double m_rotation = 0.0;                              // radians
  std::vector<glm::vec3> m_texels;                      // width * height, row-major from the top
  std::vector<glm::vec3> m_prefix_s2;                   // (height + 1) per column, column-major
  std::vector<glm::vec3> m_prefix_sc;
  std::vector<double> m_row_sin2, m_row_sincos;  // integral_0^t sin^2, sin cos at row boundaries t
  glm::dvec3 m_sphere_moment[3] = {glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0)};  // world axes
};

}  // namespace pleat
