// Self-intersection check of one frame (CGAL Polygon_mesh_processing): pleat's algorithm requires none.
#pragma once

#include <utility>
#include <vector>

#include "static_core/mesh.hpp"

namespace pleat {

/// Pairs of faces (indices into topology.triangles, first < second) that intersect other than along a
/// shared edge or vertex. Degenerate (zero-area) faces are skipped.
std::vector<std::pair<Index, Index>> self_intersecting_faces(const MeshTopology& topology,
                                                             const Frame& frame);

}  // namespace pleat
