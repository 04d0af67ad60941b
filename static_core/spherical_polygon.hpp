// Spherical polygons and Lambert's formula (DESIGN.md §4).
//
// A spherical polygon is a list of unit vectors joined by minor great-circle arcs, counter-clockwise about
// its interior (seen from outside the sphere). Lambert's formula gives its projected solid angle about a
// normal n: Omega_perp = 1/2 sum_i theta_i (n . Gamma_i), theta_i = angle(v_i, v_i+1),
// Gamma_i = normalize(v_i x v_i+1). Octant: pi/4; hemisphere: pi. Everything here is O(#vertices).
#pragma once

#include <glm/vec3.hpp>

#include <vector>

namespace pleat {

using SphericalPolygon = std::vector<glm::dvec3>;

/// The part of `poly` in the closed hemisphere {w : n.w >= 0}; arcs along the horizon are inserted
/// (subdivided so that no arc reaches pi). n must be a unit vector.
SphericalPolygon clip_to_hemisphere(const SphericalPolygon& poly, const glm::dvec3& n);

/// Lambert's formula, without clipping: 1/2 sum theta_i (n . Gamma_i).
double projected_solid_angle(const SphericalPolygon& poly, const glm::dvec3& n);

/// Arvo's vector irradiance 1/2 sum theta_i Gamma_i = integral of w over the polygon (for any n,
/// n . vector_irradiance = projected_solid_angle).
glm::dvec3 vector_irradiance(const SphericalPolygon& poly);

/// Cosine-weighted first moment integral over the polygon of w (n.w) dw, for a polygon inside the
/// hemisphere of n (used for the cosine-weighted bent normal).
glm::dvec3 cosine_weighted_moment(const SphericalPolygon& poly, const glm::dvec3& n);

/// Solid angle (area on the unit sphere) of a simple polygon, by the Van Oosterom–Strackee triangle fan.
double solid_angle(const SphericalPolygon& poly);

}  // namespace pleat
