// Per-vertex results of the visibility computation: the 3D visibility cones and what is derived from them.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "static_core/mesh.hpp"
#include "static_core/spherical_polygon.hpp"

namespace pleat {

/// The 3D visibility cone of one (vertex, side): disjoint pieces, each a polygonal cone with apex at the
/// vertex, given by its unit edge directions in counter-clockwise radial order about side*n(v).
struct VisibilityCone {
  std::vector<SphericalPolygon> pieces;
};

/// What shading needs of a cone, per vertex and side.
struct ConeMeasures {
  double sky_visibility = 0.0;  ///< A in [0,1]: cosine-weighted visible fraction (docs/method.md §1)
  glm::dvec3 bent_normal{0.0};  ///< cosine-weighted mean visible direction (unit; side normal if empty)
  double solid_angle = 0.0;     ///< steradians of the cone
};

/// Counters of one frame's static computation (reported by --stats).
struct VisibilityStats {
  std::size_t slices = 0;
  std::size_t slice_vertices = 0;
  std::size_t regions = 0;
  std::size_t windows = 0;
  std::size_t regions_with_holes = 0;
  std::size_t crossing_slices = 0;      ///< slices whose chains cross (self-intersecting input)
  std::size_t chain_crossings = 0;      ///< crossing points found in those slices
  std::vector<double> filled_fraction;  ///< per orientation: fraction of vertices that copied a cone
  /// Cloth vertices deeper than the contact tolerance inside a closed occluder or a ground plane's solid,
  /// taken as on its surface (check_contact), and the deepest of them (0: none).
  std::size_t penetrating_vertices = 0;
  double deepest_penetration = 0.0;
  Index deepest_vertex = 0;
};

/// Everything computed for one frame, indexed by welded vertex.
struct FrameVisibility {
  /// Per vertex that receives cones (MeshTopology::num_receivers: the cloth, not its occluders).
  std::vector<glm::dvec3> normals;                    ///< n(v), area-weighted, unit
  std::array<std::vector<VisibilityCone>, 2> cones;   ///< [side][vertex]
  std::array<std::vector<ConeMeasures>, 2> measures;  ///< [side][vertex]
  VisibilityStats stats;

  const ConeMeasures& measure(Side s, Index v) const { return measures[static_cast<int>(s)][v]; }
  const VisibilityCone& cone(Side s, Index v) const { return cones[static_cast<int>(s)][v]; }
};

}  // namespace pleat
