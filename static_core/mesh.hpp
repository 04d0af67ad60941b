// The cloth model every module shares: fixed connectivity over welded vertices, and per-frame positions.
//
// Connectivity and geometry are kept apart (geometry-central style): a MeshTopology is fixed for a whole
// sequence, a Frame holds one instant's positions. Algorithms take (const MeshTopology&, const Frame&).
// What follows from the triangles — edges, vertex fans, boundary, manifoldness — is MeshConnectivity
// (static_core/mesh_connectivity.hpp: OpenMesh's half-edge structure), built once per sequence by the
// engines.
#pragma once

#include <array>
#include <cstdint>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <limits>
#include <vector>

namespace pleat {

using Index = std::uint32_t;
using Triangle = std::array<Index, 3>;

/// An infinite occluding plane {x : dot(normal, x) == offset} (a ground), `normal` unit and pointing to the
/// plane's outer side: the plane bounds a solid {x : dot(normal, x) < offset}. Every point is taken as lying
/// on the outer side (a point inside the solid as on its surface: docs/method.md §6.2), so the directions
/// from any point that the plane does not block are those d with dot(d, normal) >= 0. The engines and the
/// ray-cast reference both take it so.
struct OccludingPlane {
  glm::dvec3 normal{0.0, 1.0, 0.0};
  double offset = 0.0;
  /// How far p lies inside the solid (negative: above the plane).
  double depth(const glm::dvec3& p) const { return offset - glm::dot(normal, p); }
};

/// Triangles over welded vertices 0..num_vertices-1, in the input's winding.
///
/// A scene with occluders (the bodies, tables and ground a cloth was simulated against) appends their
/// vertices after the cloth's, and their triangles after the cloth's: the last num_occluder_vertices vertices
/// are occluders. They block sight lines but receive no cones: every engine computes and stores cones for the
/// first num_receivers() vertices only (docs/method.md §1). The cone engines slice every triangle but the
/// last num_plane_triangles: those stand in for the infinite `planes` (a large square each, for ray casting
/// and rendering), which the engines apply exactly instead, by keeping in every cone only the directions on
/// the vertex's side of each plane.
///
/// `contact_tolerance` (world units, >= 0) is how far behind an open occluder's surface a cloth point is
/// still taken as resting on its front (a point inside a closed occluder or a plane's solid is always taken
/// as on its surface); cloth vertices deeper than it are reported (check_contact, static_core/contact.hpp).
struct MeshTopology {
  Index num_vertices = 0;
  std::vector<Triangle> triangles;
  Index num_occluder_vertices = 0;
  std::vector<OccludingPlane> planes{};
  Index num_plane_triangles = 0;
  double contact_tolerance = 0.0;
  Index num_receivers() const { return num_vertices - num_occluder_vertices; }
  /// The triangles the cone engines slice: the first num_sliced_triangles().
  Index num_sliced_triangles() const { return Index(triangles.size()) - num_plane_triangles; }
};

/// One instant of the sequence: a position per welded vertex.
struct Frame {
  double time = 0.0;
  std::vector<glm::dvec3> positions;
};

/// An axis-aligned box; empty (lo > hi) until a point is added.
struct Bounds {
  glm::dvec3 lo{std::numeric_limits<double>::infinity()};
  glm::dvec3 hi{-std::numeric_limits<double>::infinity()};
  void add(const glm::dvec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  void add(const Bounds& other) {
    lo = glm::min(lo, other.lo);
    hi = glm::max(hi, other.hi);
  }
  bool empty() const { return !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z); }
};

/// Which side of the surface: Front is the side of +n(v) (area-weighted vertex normal), Back of -n(v).
enum class Side : int { Front = 0, Back = 1 };
inline constexpr std::array<Side, 2> kBothSides = {Side::Front, Side::Back};
inline constexpr double side_sign(Side s) { return s == Side::Front ? 1.0 : -1.0; }

}  // namespace pleat
