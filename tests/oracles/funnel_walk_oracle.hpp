// The funnel shortest-path tree grown by walking each funnel chain from its outer end towards the cusp
// (Stewart 1999 §2.3.1 without finger trees: O(funnel depth) per triangle): the way static_core grew its
// trees until the funnel became an array searched by bisection. Same trees by construction; the oracle of
// grow_shortest_path_tree.
#pragma once

#include <vector>

#include "static_core/internal/slice_triangulation.hpp"

namespace pleat::test {

/// grow_shortest_path_tree by walking the chains: parent[c] for every corner c of the window's region.
void walk_shortest_path_tree(const SliceTriangulation& slice, const SliceWindow& window, bool from_b,
                             std::vector<int>& parent);

}  // namespace pleat::test
