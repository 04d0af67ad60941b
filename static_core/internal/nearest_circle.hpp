// The nearest-circle reconstruction of a 3D cone from 2D cones (ConeReconstruction::NearestCircle;
// docs/method.md §8). Internal: cone_assembly.hpp is the entry.
//
// Each 2D cone of a vertex lies on the great circle of its plane's orientation through the vertex. Every
// direction ω of the sphere takes the visibility of the nearest point of the nearest circle: circle k with
// the least |ω·n_k|, at the point where the meridian through ω (the great circle through ω and n_k) meets it.
// The set of directions whose nearest circle is k is its cell; in circle k's chart
//     ω(φ, τ) = cos τ c(φ) + sin τ n_k,   c(φ) = cos φ u_k + sin φ w_k,
// circle j is farther than circle k on the sheet s = sign(τ) up to the elevation
//     tan τ = |a| / (1 − s σ b),   a = c(φ)·n_j,  b = n_k·n_j,  σ = s sign(a)
// where ω lies on the great circle ω·(n_k − σ n_j) = 0. So the cell's boundary on each sheet (its envelope)
// is the least of those curves over j: great-circle arcs, joined where two of them cross or where a curve
// pinches to the circle (a = 0: circle j crosses circle k). The envelope depends only on the set of circles,
// so it is computed once per set (every vertex of a plan has the same few sets) by sorting every candidate
// breakpoint and reading which curve is least between consecutive ones — no marching, no event tolerance.
// A visible arc of circle k gives the cell part over it: bounded by the two meridians at its ends and the
// envelopes above and below; the parts of all arcs of all circles are disjoint and tile the sphere when every
// circle is wholly visible. Each part is clipped to the side's hemisphere and the occluding planes'
// half-spaces; the clipped parts are the cone's pieces.
#pragma once

#include <glm/vec3.hpp>
#include <span>
#include <vector>

#include "static_core/angular_set.hpp"
#include "static_core/spherical_polygon.hpp"
#include "static_core/visibility_cone.hpp"

namespace pleat {

struct PlanarCone;

/// Reusable memory and the envelope cache of the nearest-circle assembly (one per thread).
class NearestCircleAssembler {
 public:
  /// The cone of `cones` (their wedges need not be united) on the side `side_normal` (unit), clipped to the
  /// half-spaces {d : d·h >= 0} of `half_spaces`, into `result` (its memory reused); piece i's vector
  /// irradiance and solid angle are then irradiance()[i] and solid_angle()[i].
  void assemble(std::span<const PlanarCone> cones, const glm::dvec3& side_normal,
                std::span<const glm::dvec3> half_spaces, VisibilityCone& result);
  const std::vector<glm::dvec3>& irradiance() const { return m_irradiance; }
  const std::vector<double>& solid_angle() const { return m_solid_angle; }

  /// One circle: its plane's normal and in-plane frame ((u, w, n) of either handedness).
  struct Circle {
    glm::dvec3 n, u, w;
    double handed;  ///< sign of (u × w)·n
  };
  /// Where one curve is the envelope of a sheet: from angle phi (in [0, 2pi)) to the next piece's.
  struct EnvelopePiece {
    double phi;
    int circle;             ///< j; -1: no other circle (the envelope is the pole)
    int sigma;              ///< the great circle ω·(n_k − σ n_j) = 0
    glm::dvec3 start{0.0};  ///< the boundary's point at phi (a corner of every cell part that spans it)
  };
  /// The envelopes of one set of circles: per circle k, per sheet (0: towards +n_k, 1: towards -n_k), the
  /// pieces sorted by phi, covering the whole turn cyclically.
  struct CircleSet {
    std::vector<Circle> circles;
    std::vector<std::vector<EnvelopePiece>> envelope;  ///< [2 * k + sheet]
  };
  /// The envelopes of a set of distinct circles (no two with parallel normals); exposed for the tests.
  static void make_envelopes(CircleSet& set);
  /// The point of circle k's cell boundary on `sheet` at angle phi, by `piece`'s curve.
  static glm::dvec3 envelope_point(const CircleSet& set, std::size_t k, int sheet, const EnvelopePiece& piece,
                                   double phi);

 private:
  const CircleSet& circle_set();  // of m_circles (from the cache, or made and cached)
  /// Step 1: m_circles, one per plane normal (up to sign), and each circle's wedges in its frame.
  void gather_circles(std::span<const PlanarCone> cones);
  /// Step 2: m_cell, circle k's cell over [a, b] (the lower envelope from a to b, the circle's point at b,
  /// the upper envelope back to a, the circle's point at a); false when it has no area.
  bool make_cell(const CircleSet& set, std::size_t k, double a, double b);
  /// Step 3: m_parts, m_cell's part in the side's hemisphere and the half-spaces.
  void clip_cell(const glm::dvec3& side_normal, std::span<const glm::dvec3> half_spaces);

  std::vector<glm::dvec3> m_irradiance;
  std::vector<double> m_solid_angle;
  std::vector<Circle> m_circles;                    // this call's
  std::vector<std::vector<Wedge>> m_circle_wedges;  // per circle, in its frame
  std::vector<CircleSet> m_cache;
  std::vector<Wedge> m_united;
  std::vector<AngularInterval> m_intervals;
  SphericalPolygon m_cell;
  SphericalPolygonList m_parts, m_next;
  HemisphereClipper m_clipper;
};

}  // namespace pleat
