// Funnel shortest-path trees in a triangulated simple region, stored as parent pointers over corners; and the
// same funnels grown along the sleeves of a region with holes (see_window_through_sleeves, at the end).
// Paper: Guibas, Hershberger, Leven, Sharir, Tarjan 1987; Stewart 1999 §2.3.1. Method: docs/method.md §5 (the
// funnel as one array searched by bisection, and why that is exact), §6 (sleeves).
// From a root corner (a window endpoint) the tree is grown across the region's dual tree; the parent of a new
// corner x is where x's tangent touches the funnel's chains, or the cusp. Every turn is an exact orientation
// predicate; a vertex collinear with a funnel edge counts as touched, which makes the tree unique.
// Preconditions: grow_shortest_path_tree's region has no holes.
// Cost: O(log funnel size) predicates per triangle crossed (the paper's walk along a chain, O(funnel depth),
// is the oracle in tests/oracles).
// Thread safety: reentrant; each thread its own FunnelScratch.
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
/// sees (docs/benchmarks.md compares it with the triangular expansion it replaced). Tests: slice_cones_test
/// against the brute-force angular sweep.
void see_window_through_sleeves(const SliceTriangulation& slice, const SliceWindow& window,
                                std::size_t region_faces, SleeveScratch& scratch,
                                std::vector<SleeveSight>& sights);

}  // namespace pleat
