// Funnel shortest-path trees in a triangulated simple region (Guibas, Hershberger, Leven, Sharir, Tarjan
// 1987; Stewart 1999 §2.3.1), stored as parent pointers over corners.
//
// From a root corner (a window endpoint), the tree is grown across the region's dual tree: entering a
// triangle (u, v, x) through the diagonal (u, v) with funnel cusp a, the parent of x is the tangent point of
// x on the funnel's u-chain or v-chain (found by walking parent pointers from u or v towards a), or the cusp.
// Every turn is an exact orientation predicate; a vertex collinear with a funnel edge is taken as touched
// (the parent is the last vertex on the path), which makes the tree unique. As in the paper, no finger
// trees: the walk is O(funnel depth), small in practice. Precondition: the region has no holes.
#pragma once

#include <vector>

#include "static_core/slice_triangulation.hpp"

namespace pleat {

/// One funnel still to expand: cross the edge (face, index) with cusp `apex`.
struct FunnelTask {
  cgal::FaceHandle face;
  int index = 0;
  int apex = -1;
};

/// Sets parent[c] for every corner c of the window's region (the root's parent is itself). `parent` must
/// have num_corners() entries; entries of other regions are left as they are. `stack` is scratch memory.
void grow_shortest_path_tree(const SliceTriangulation& slice, const SliceWindow& window, bool from_b,
                             std::vector<int>& parent, std::vector<FunnelTask>& stack);

}  // namespace pleat
