// 2D visibility cones of every slice vertex, on both sides (Stewart 1999 §2.3; DESIGN.md §2.5–2.6).
//
// At a slice vertex X the front side is the angular range immediately counter-clockwise of its outgoing
// chain edge (slice edges have the front on their left) up to the next chain edge at X; the back side is the
// range counter-clockwise of its incoming edge. A range is made of corners of regions inside the hull and,
// at hull vertices, the exterior wedge between the two hull edges (visible entirely). A corner's cone is:
//   - in a region without holes: for each window (a, b), the wedge from the first segment of the shortest
//     path to a to the first segment of the path to b (funnel trees from a and b), when it turns the right
//     way; empty when the two coincide;
//   - in a region with holes: the corner's sector minus the angular spans of the region's chain edges seen
//     from X, by an exact-predicate angular sweep.
// Collinear slices (dimension 1, a flat sheet) give each side its open half-plane.
// Cost: O(w n + f) per region without holes (w windows, n corners, f funnel walks), O(n^2 log n) with holes.
#pragma once

#include "static_core/angular_set.hpp"
#include "static_core/mesh_slicer.hpp"
#include "static_core/shortest_path_tree.hpp"
#include "static_core/slice_triangulation.hpp"

#include <cstdint>
#include <vector>

namespace pleat {

/// The cones of one slice, flat: the cone of (slice vertex v, side s) is
/// wedges[offsets[2v+s] .. offsets[2v+s+1]) (disjoint, sorted by start).
struct SliceCones {
  std::vector<Wedge> wedges;
  std::vector<std::uint32_t> offsets;
  std::size_t windows = 0;
  std::size_t regions = 0;
  std::size_t regions_with_holes = 0;
  std::size_t holes_swept = 0;  ///< regions with holes whose outer boundary was not simple: swept entirely

  std::span<const Wedge> cone(Index slice_vertex, Side side) const {
    const std::size_t k = 2 * slice_vertex + static_cast<std::size_t>(side);
    return {wedges.data() + offsets[k], wedges.data() + offsets[k + 1]};
  }
};

/// Reusable per-thread memory.
struct SliceConeScratch {
  std::vector<int> parent_a, parent_b;
  std::vector<FunnelTask> stack;
  std::vector<std::vector<Wedge>> corner_wedges;
  std::vector<int> corner_stamp;
  std::vector<int> region_corners;
  std::vector<Wedge> range_wedges;
  std::vector<std::pair<double, double>> intervals;
};

void compute_slice_cones(const Slice& slice, const SliceTriangulation& triangulation, SliceConeScratch& scratch,
                         SliceCones& out);

}  // namespace pleat
