// 2D visibility cones of every slice vertex, on both sides (Stewart 1999 §2.3; DESIGN.md §2.5–2.6).
//
// At a slice vertex X the front side is the angular range immediately counter-clockwise of its outgoing
// chain edge (slice edges have the front on their left) up to the next chain edge at X; the back side is the
// range counter-clockwise of its incoming edge. A range is made of corners of regions inside the hull and,
// at hull vertices, the exterior wedge between the two hull edges (visible entirely). A corner's cone is:
//   - in a region without holes: for each window (a, b), the wedge from the first segment of the shortest
//     path to a to the first segment of the path to b (funnel trees from a and b), when it turns the right
//     way; empty when the two coincide;
//   - in a region with holes: the directions whose ray from X leaves the hull through a window before it
//     meets a chain edge, by triangular expansion from the corner's triangles (exact orientation tests).
//     In a large region (SliceConeScratch::outer_polygon_min_faces) the corners on its outer boundary take
//     the paper's §2.3.2 instead: funnel trees in the polygon bounded by the outer boundary alone, minus
//     each hole's shadow (the range between the tangents to its convex hull); the corners on the holes, and
//     those inside a hole's hull, stay with the expansion (the paper left them to a quadratic sweep).
// Collinear slices (dimension 1, a flat sheet) give each side its open half-plane.
// Cost: O(w n + f) per region without holes (w windows, n corners, f funnel walks); with holes, per corner
// the triangles seen from it (output-sensitive; O(n) each at worst, so O(n^2) for a region), or for the
// outer corners of a large region O(n log n) for the polygon's triangulation plus, per corner, the size of
// the holes' hulls.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "static_core/angular_set.hpp"
#include "static_core/mesh_slicer.hpp"
#include "static_core/shortest_path_tree.hpp"
#include "static_core/slice_triangulation.hpp"

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

/// A range of directions from a corner's vertex x, from ray x->right counter-clockwise to ray x->left, that
/// crosses the edge of `face` opposite `index` (triangular expansion in regions with holes).
struct ExpansionTask {
  cgal::FaceHandle face;
  int index = 0;
  cgal::VertexHandle right, left;
};

/// Reusable memory of the outer-polygon method for large regions with holes (slice_cones.cpp).
struct OuterPolygonScratch {
  std::vector<int> root;       ///< union-find over CDT vertices, by representative slice vertex
  std::vector<int> touched;    ///< the entries of `root` and `sub_index` in use
  std::vector<int> sub_index;  ///< per vertex: its index in the outer polygon's slice, or -1
  std::vector<cgal::VertexHandle> vertex_of_sub;
  Slice outer;  ///< the chains of the region's outer boundary
  std::unique_ptr<SliceTriangulation> triangulation;
  std::vector<int> parent_a, parent_b;
  std::vector<std::vector<cgal::Point2>> hulls;  ///< the holes' convex hulls, counter-clockwise
  std::vector<std::vector<std::pair<cgal::Point2, cgal::Point2>>> ranges;  ///< per corner: visible ranges
  std::vector<std::pair<cgal::Point2, cgal::Point2>> next;
  std::vector<char> by_expansion;  ///< per corner: left to the triangular expansion
  /// (vertex, the far end of the separator that bounds a corner clockwise, the corner), in R and in P
  std::vector<std::array<int, 3>> keys, p_keys;
  std::vector<int> r_corners, p_corners;     ///< corners of R, and the corners of P standing for them
  std::vector<std::pair<int, int>> members;  ///< (component root, vertex) of the holes
  std::vector<cgal::Point2> points;
};

/// Reusable per-thread memory.
struct SliceConeScratch {
  /// Regions with holes of at least this many triangles take the outer-polygon method (funnel trees in the
  /// polygon without its holes, minus the holes' shadows) for the corners on their outer boundary; the
  /// triangular expansion's cost grows with the square of a region's size, this method's almost linearly.
  std::size_t outer_polygon_min_faces = 1024;
  std::size_t outer_polygon_corners = 0;  ///< corners given their cones by that method (a running count)
  OuterPolygonScratch outer;
  std::vector<int> parent_a, parent_b;
  FunnelScratch funnel;
  std::vector<std::vector<Wedge>> corner_wedges;
  std::vector<int> corner_stamp;
  std::vector<int> region_corners;
  std::vector<Wedge> range_wedges;
  std::vector<std::pair<double, double>> intervals;
  std::vector<ExpansionTask> expansion;
  std::vector<char>
      vertex_needed;  ///< per slice vertex that represents a CDT vertex (VertexInfo::slice_vertex)
};

/// The cones of every slice vertex, or, given `needed` (one flag per slice vertex), of the flagged ones only:
/// the others get empty cones and their corners no wedges (funnel trees still grow where a needed corner is).
void compute_slice_cones(const Slice& slice, const SliceTriangulation& triangulation,
                         SliceConeScratch& scratch, SliceCones& out, std::span<const char> needed = {});

}  // namespace pleat
