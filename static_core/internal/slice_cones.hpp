// 2D visibility cones of every slice vertex, on both sides (Stewart 1999 §2.3; docs/method.md §5–§6).
//
// At a slice vertex X the front side is the angular range immediately counter-clockwise of its outgoing
// chain edge (slice edges have the front on their left) up to the next chain edge at X; the back side is the
// range counter-clockwise of its incoming edge. A range is made of corners of regions inside the hull and,
// at hull vertices, the exterior wedge between the two hull edges (visible entirely). A corner's cone is:
//   - in a region without holes: for each window (a, b), the wedge from the first segment of the shortest
//     path to a to the first segment of the path to b (funnel trees from a and b), when it turns the right
//     way; empty when the two coincide;
//   - in a region with holes: the directions whose ray from X leaves the hull through a window before it
//     meets a chain edge. For each window, the same funnels grown along the sleeves through which the window
//     can be seen (see_window_through_sleeves, shortest_path_tree.hpp): a corner gets one wedge per sleeve
//     through which it sees the window (the paper's §2.3.2 takes the outer boundary's corners by funnel trees
//     without the holes minus the holes' shadows, and leaves the corners on holes to a quadratic sweep).
// Collinear slices (dimension 1, a flat sheet) give each side its open half-plane.
// Cost: O(w n + f) per region without holes (w windows, n corners, f funnel walks); with holes, per window
// the sleeve triangles through which it can be seen, O(log n) tests each (output-sensitive: a sleeve ends
// where no point of its last edge sees the window).
// Thread safety: reentrant; each thread its own scratch.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "static_core/angular_set.hpp"
#include "static_core/internal/shortest_path_tree.hpp"
#include "static_core/internal/slice_triangulation.hpp"
#include "static_core/mesh_slicer.hpp"

namespace pleat {

/// The cones of one slice, flat: the cone of (slice vertex v, side s) is
/// wedges[offsets[2v+s] .. offsets[2v+s+1]) (disjoint, sorted by start).
struct SliceCones {
  std::vector<Wedge> wedges;
  std::vector<std::uint32_t> offsets;
  std::size_t windows = 0;
  std::size_t regions = 0;
  std::size_t regions_with_holes = 0;

  std::span<const Wedge> cone(Index slice_vertex, Side side) const {
    const std::size_t k = 2 * slice_vertex + static_cast<std::size_t>(side);
    return {wedges.data() + offsets[k], wedges.data() + offsets[k + 1]};
  }
};

/// Reusable per-thread memory.
struct SliceConeScratch {
  std::vector<int> parent_a, parent_b;
  FunnelScratch funnel;
  std::vector<std::vector<Wedge>> corner_wedges;
  std::vector<int> corner_stamp;
  std::vector<int> region_corners;
  std::vector<Wedge> range_wedges;
  std::vector<AngularInterval> intervals;
  SleeveScratch sleeves;  ///< regions with holes
  std::vector<SleeveSight> sights;
  std::size_t sleeve_sights = 0;  ///< sights of a window through a sleeve found so far (a running count)
  std::vector<char>
      vertex_needed;  ///< per slice vertex that represents a CDT vertex (VertexInfo::slice_vertex)
};

/// The cones of every slice vertex, or, given `needed` (one flag per slice vertex), of the flagged ones only:
/// the others get empty cones and their corners no wedges (funnel trees still grow where a needed corner is).
void compute_slice_cones(const Slice& slice, const SliceTriangulation& triangulation,
                         SliceConeScratch& scratch, SliceCones& out, std::span<const char> needed = {});

}  // namespace pleat
