// Funnel shortest-path trees in a triangulated simple region (Guibas, Hershberger, Leven, Sharir, Tarjan
// 1987; Stewart 1999 §2.3.1), stored as parent pointers over corners; and the same funnels grown along the
// sleeves of a region with holes (see_window_through_sleeves, at the end).
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

#include "static_core/internal/slice_triangulation.hpp"

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

/// One funnel of a sleeve (see see_window_through_sleeves): funnel[lo..hi] with its cusp at funnel[apex],
/// once the undo log is back to `undo` entries and the corners `left` and `right` (unless -1) are written at
/// lo and hi; `before_cusp` is the corner before the cusp on the path from the root (-1 while the cusp is the
/// root).
struct SleeveFunnel {
  int lo = 0, apex = 0, hi = 0;
  std::uint32_t undo = 0;
  int left = -1, right = -1;
  int before_cusp = -1;
};

/// One sleeve still to extend: cross the edge (face, index), the sleeve having crossed `depth` triangles; the
/// funnels from the window's two ends.
struct SleeveTask {
  cgal::FaceHandle face;
  int index = 0;
  int depth = 0;
  SleeveFunnel funnel[2];
};

/// Reusable memory of see_window_through_sleeves.
struct SleeveScratch {
  std::vector<SleeveTask> stack;
  std::vector<int> funnel[2];
  std::vector<std::pair<int, int>> undo[2];
};

/// A corner that sees a window through one sleeve: it sees the window between the rays towards `from_a` and
/// `from_b` (counter-clockwise), the first vertices of its shortest paths to the window's ends in the sleeve.
struct SleeveSight {
  int corner = -1;
  int from_a = -1, from_b = -1;
};

/// Weak visibility from a window in a region with or without holes (Stewart's §2.3.1 funnel trees, grown
/// along sleeves). A sleeve is a sequence of the region's triangles, from the window's, each entered across
/// an edge that is not a separator; a sight line from the window crosses exactly the triangles of one sleeve,
/// in order, and a sleeve is a simple polygon with the window as an edge, where the funnels from the window's
/// ends a and b decide exactly which points see the window (Guibas, Hershberger, Leven, Sharir and Tarjan
/// 1987), as they do in a region without holes. So the sleeves are grown depth-first from the window's
/// triangle with both funnels, and every triangle's third vertex x, reached across edge e, is appended to
/// `sights` when the last segments of its paths to a and b turn the right way (x sees the window through this
/// sleeve, between them). A sleeve is not extended beyond e when no point of e can see the window: a point
/// sees the window only if its paths to a and to b are outward convex (turning only counter-clockwise from a,
/// only clockwise from b: same lemma), and every path from a root to a point of e passes through the funnel's
/// cusp, so a path from a root to its cusp that turns the wrong way closes the sleeve, and so does a cusp
/// where even the turn towards the first vertex of the chain on the path's own side is the wrong way (every
/// other point of e is reached turning further that way). That ends every sleeve that winds round a
/// hole: the paths from both ends wind round it the same way, so one of them turns the wrong way. A sleeve
/// never crosses more triangles than the region has (a straight line crosses each at most once), which bounds
/// the walk in any case. Every decision is an exact orientation test. Cost: about the sleeve triangles
/// through which the window can be seen, O(log funnel) tests each, not the corners times what each corner
/// sees: on the 30k roll's frame 12, 184 thousand sleeve triangles against the 16.8 million triangles the
/// triangular expansion this replaced (one per corner) crossed; on the layered plies 70 thousand against 1.75
/// million. Tests: slice_cones_test against the brute-force angular sweep.
void see_window_through_sleeves(const SliceTriangulation& slice, const SliceWindow& window,
                                std::size_t region_faces, SleeveScratch& scratch,
                                std::vector<SleeveSight>& sights);

}  // namespace pleat
