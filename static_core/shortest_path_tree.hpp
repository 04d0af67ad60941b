// Funnel shortest-path trees in a triangulated simple region (Guibas, Hershberger, Leven, Sharir, Tarjan
// 1987; Stewart 1999 §2.3.1), stored as parent pointers over corners.
//
// From a root corner (a window endpoint), the tree is grown across the region's dual tree. Entering a
// triangle (L, R, x) through the diagonal (L, R) with funnel cusp a, the parent of x is the point of the
// funnel's L-chain or R-chain where x's tangent touches it, or the cusp. Every turn is an exact orientation
// predicate; a vertex collinear with a funnel edge is taken as touched (the parent is the last vertex on the
// path), which makes the tree unique.
//
// The funnel is kept as one array, funnel[lo..hi] = (L = l_k, ..., l_1, a, r_1, ..., r_m = R), and searched
// by bisection. Why that is exact. The funnel (the two chains and LR) is a simple polygon whose only convex
// corners are a, L and R, its chain vertices being reflex or flat (a flat one: a collinear vertex taken as
// touched). Walked once round, it turns by 360°, so with θ_i the direction of l_{i-1} -> l_i (increasing with
// i), θ_k - θ_1 plus the turn at L stays under 180°: the direction of L -> R is less than θ_1 + 180°. Let t
// be the largest i with x left of or on the line l_{i-1} l_i (the walk's answer). From l_t, x lies in
// directions [θ_t, θ_{t+1}), the test failing at t + 1 (t = k: in [θ_k, direction of L -> R + 180°), x being
// beyond LR); both ends lie within [θ_i, θ_i + 180°) for every i ≤ t, and so do the chain edges from l_{i-1}
// to l_t. Hence x - l_{i-1} is left of or on the line at i too: the test holds exactly for i = 1..t, whether
// t > 0 is decided at i = 1, and t by bisection. Mirrored on the R-chain. When the cusp is L or R (one chain
// empty) that chain is skipped. The split funnels, (l_k..l_t, x) and (x, l_t..r_m) for a tangent on the
// L-chain, are the array's two sub-ranges with x written at one end; the writes are undone when the
// depth-first walk backtracks. A range moves outwards by at most one place per triangle it crosses, at most
// the region's corners - 2. Cost: O(log funnel size) predicates per triangle, against the walk along a chain
// from its outer end (O(funnel depth), the paper's, kept as the oracle in tests/oracles), whose depth grew
// with the slices' length (3.4 tests per triangle on the 3k curtain, 15.5 at 300k). Precondition: the region
// has no holes.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "static_core/slice_triangulation.hpp"

namespace pleat {

/// One funnel still to expand: cross the edge (face, index); the funnel is funnel[lo..hi] with its cusp at
/// funnel[apex], once the undo log is back to `undo` entries and the corners `left` and `right` (unless -1)
/// are written at lo and hi.
struct FunnelTask {
  cgal::FaceHandle face;
  int index = 0;
  int lo = 0, apex = 0, hi = 0;
  std::uint32_t undo = 0;
  int left = -1, right = -1;
};

/// Reusable memory of grow_shortest_path_tree.
struct FunnelScratch {
  std::vector<FunnelTask> stack;
  std::vector<int> funnel;                ///< corners; the funnels of the walk, overlapping
  std::vector<std::pair<int, int>> undo;  ///< (position, corner it held) of every funnel write
};

/// Sets parent[c] for every corner c of the window's region (the root's parent is itself). `parent` must
/// have num_corners() entries; entries of other regions are left as they are.
void grow_shortest_path_tree(const SliceTriangulation& slice, const SliceWindow& window, bool from_b,
                             std::vector<int>& parent, FunnelScratch& scratch);

}  // namespace pleat
