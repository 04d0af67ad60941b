// Spherical polygons and Lambert's formula (docs/method.md §9).
//
// A spherical polygon is a list of unit vectors joined by minor great-circle arcs, counter-clockwise about
// its interior (seen from outside the sphere). Lambert's formula gives its projected solid angle about a
// normal n: Omega_perp = 1/2 sum_i theta_i (n . Gamma_i), theta_i = angle(v_i, v_i+1),
// Gamma_i = normalize(v_i x v_i+1). Octant: pi/4; hemisphere: pi. Everything here is O(#vertices).
// Thread safety: pure functions; a HemisphereClipper is used by one thread at a time.
#pragma once

#include <cstddef>
#include <glm/vec3.hpp>
#include <vector>

namespace pleat {

using SphericalPolygon = std::vector<glm::dvec3>;

/// The part of `poly` in the closed hemisphere {w : n.w >= 0}; arcs along the horizon are inserted
/// (subdivided so that no arc reaches pi). n must be a unit vector.
/// When the part has several components (a polygon that dips in and out of the hemisphere more than
/// once), they are joined into one polygon by pairs of opposite bridge arcs along the horizon: zero area,
/// exact for every integral below. Use HemisphereClipper to get the components separately.
SphericalPolygon clip_to_hemisphere(const SphericalPolygon& poly, const glm::dvec3& n);

/// A reusable list of spherical polygons: the first `size` entries are valid, and storage is kept between
/// uses so that hot loops do not allocate once warmed up.
struct SphericalPolygonList {
  std::vector<SphericalPolygon> polygons;
  std::size_t size = 0;

  void clear() { size = 0; }
  /// A new empty polygon at the end (reusing old storage).
  SphericalPolygon& push() {
    if (size == polygons.size()) polygons.emplace_back();
    SphericalPolygon& p = polygons[size++];
    p.clear();
    return p;
  }
  const SphericalPolygon& operator[](std::size_t i) const { return polygons[i]; }
  SphericalPolygon& operator[](std::size_t i) { return polygons[i]; }
};

/// Great-circle Sutherland–Hodgman with horizon stitching (Weiler–Atherton pairing: each exit joins the
/// next entry counter-clockwise about n along the horizon), giving each component of poly ∩ {n.w >= 0}
/// as its own simple counter-clockwise polygon. Keeps scratch storage between calls; not thread-safe
/// (one clipper per thread). O(#vertices + k^2) for k horizon crossings (k is 2 in nearly all cases).
class HemisphereClipper {
 public:
  /// Appends the components of poly ∩ {n.w >= 0} to `out`; returns how many were appended.
  /// A polygon whose boundary lies below the horizon but which contains n yields the whole hemisphere; one
  /// whose boundary stays in the hemisphere but which holds -n yields one weakly simple polygon (the horizon,
  /// a bridge along a meridian, the polygon's boundary reversed in sense, the bridge back).
  std::size_t clip(const SphericalPolygon& poly, const glm::dvec3& n, SphericalPolygonList& out);

 private:
  struct Node {
    glm::dvec3 p;
    int kind;         // 0 vertex, 1 entry crossing, 2 exit crossing
    double azimuth;   // about n, for crossings
    int partner;      // exit -> index of its entry node
    double arc;       // exit -> counter-clockwise angle along the horizon to its entry
    glm::dvec3 a, b;  // crossing: on the arc a -> b, proportional to wa * a + wb * b (kept unrounded for
    double wa, wb;    //   the exact ordering of nearly coincident crossings)
  };
  static double crossing_ccw_angle(const Node& x, const Node& e, const glm::dvec3& n);
  /// clip() where no edge crosses the horizon (`inside` of poly's vertices above it, 0 or all; m_dots set).
  std::size_t clip_uncrossed(const SphericalPolygon& poly, const glm::dvec3& n, std::size_t inside,
                             SphericalPolygonList& out);
  /// The kept vertices and the horizon crossings, in polygon order, into m_nodes (entries in m_entries).
  void list_crossings(const SphericalPolygon& poly, const glm::dvec3& n);
  /// Each exit's entry along the horizon (Node::partner, Node::arc).
  void pair_crossings(const glm::dvec3& n);
  /// The pieces: the cycles of m_nodes, appended to `out`; returns how many.
  std::size_t walk_cycles(const glm::dvec3& n, SphericalPolygonList& out);

  std::vector<double> m_dots;
  std::vector<Node> m_nodes;
  std::vector<int> m_entries;
  std::vector<char> m_used;
};

/// Whether direction w (unit) lies inside the simple counter-clockwise polygon (interior on the left).
/// Exact winding count: the fan of signed Van Oosterom–Strackee triangles from -w sums to
/// area - 4 pi * winding(w), so any polygon, also larger than a hemisphere, is handled. O(#vertices).
bool contains_direction(const SphericalPolygon& poly, const glm::dvec3& w);
/// The same with the polygon's solid_angle already known.
bool contains_direction(const SphericalPolygon& poly, const glm::dvec3& w, double poly_solid_angle);

/// A cap {w : dot(w, centre) >= min_cos} that holds a polygon — its vertices, its minor-arc edges and its
/// interior —: a quick test before contains_direction. The whole sphere (min_cos = -1) where no such cap is
/// known: the vertices not within a cap narrower than a hemisphere, or a solid angle larger than the cap's
/// (the polygon then encloses the rest of the sphere).
struct BoundingCap {
  glm::dvec3 centre{0.0, 0.0, 1.0};
  double min_cos = -1.0;
};
/// The cap of `poly` (its solid_angle given) about the mean of its vertices. O(#vertices).
BoundingCap bounding_cap(const SphericalPolygon& poly, double poly_solid_angle);
/// False only where contains_direction(poly, w) is false for the polygon whose cap this is: w lies beyond the
/// cap by more than rounding (1e-9), where the boundary is far and the winding count exactly 0.
inline bool may_contain(const BoundingCap& cap, const glm::dvec3& w) {
  return cap.centre.x * w.x + cap.centre.y * w.y + cap.centre.z * w.z >= cap.min_cos - 1e-9;
}

/// The horizon of n as a spherical polygon (four quarter arcs, counter-clockwise about n): the hemisphere.
SphericalPolygon hemisphere_polygon(const glm::dvec3& n);

/// Lambert's formula, without clipping: 1/2 sum theta_i (n . Gamma_i).
double projected_solid_angle(const SphericalPolygon& poly, const glm::dvec3& n);

/// Arvo's vector irradiance 1/2 sum theta_i Gamma_i = integral of w over the polygon (for any n,
/// n . vector_irradiance = projected_solid_angle).
glm::dvec3 vector_irradiance(const SphericalPolygon& poly);

/// Cosine-weighted first moment integral over the polygon of w (n.w) dw, for a polygon inside the
/// hemisphere of n (used for the cosine-weighted bent normal).
glm::dvec3 cosine_weighted_moment(const SphericalPolygon& poly, const glm::dvec3& n);
/// The same with the polygon's solid_angle already known (it is part of the moment).
glm::dvec3 cosine_weighted_moment(const SphericalPolygon& poly, const glm::dvec3& n, double poly_solid_angle);

/// Solid angle (area on the unit sphere) of a simple polygon, by the Van Oosterom–Strackee triangle fan
/// summed with a single atan2 (the argument of the product of the triangles' complex numbers).
double solid_angle(const SphericalPolygon& poly);
/// The same with the polygon's vector_irradiance already known (the fan's apex).
double solid_angle(const SphericalPolygon& poly, const glm::dvec3& irradiance);

}  // namespace pleat
