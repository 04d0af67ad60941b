// The occluders' part of a slice, as shadows on the cloth's 2D cones (docs/method.md §3).
//
// A cloth point p's 2D cone is the set of directions whose ray from p meets no chain of the slice. The
// cloth's chains are triangulated and their cones grown as Stewart's §2.3 has it; the occluders' chains are
// not: each blocks from p exactly the directions whose rays meet it, which are
//   - from a point strictly outside the chain's convex hull, the range between p's two tangents to the hull:
//     a connected chain holds its hull's vertices, so a line through the hull's interior separates two of
//     them and crosses the chain between them, in front of p (the argument of Stewart's §2.3.2 for holes);
//   - from any other point, the union of the ranges its segments subtend (a segment through p blocks none).
// Cloth in contact (docs/method.md §6.2): a point inside a closed chain (inside a solid occluder, exact
// parity), or behind an open chain's surface within the scene's contact tolerance, is seen from the nearest
// point of the occluders' surface instead (contact_viewpoint), so that touching or sinking into a collider
// never inverts the cone.
// So the cone is the cloth's cone minus those ranges, each end at a chain vertex as a funnel tree would put
// it (thin_wedge_between of the directions to the two vertices), with its reach. The occluders' triangles,
// regions and windows are never built: a body or a table costs its slicing and a hull per chain.
// Internal header: static_core and kinetic only.
#pragma once

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "static_core/angular_set.hpp"
#include "static_core/internal/slice_cones.hpp"
#include "static_core/mesh_slicer.hpp"

namespace pleat {

/// The occluders' chains of one slice: per chain its segments, its convex hull (counter-clockwise, exact
/// predicates; one point or two for a chain on a point or a line) and its bounding box.
struct OccluderChains {
  struct Chain {
    std::uint32_t segments_begin = 0, segments_end = 0;  ///< into `segments`
    std::uint32_t hull_begin = 0, hull_end = 0;          ///< into `hull`
    glm::dvec2 lo{0.0}, hi{0.0};                         ///< bounding box
    glm::dvec2 centre{0.0};                              ///< of the hull's vertices (three or more)
    double radius = 0.0;                                 ///< their mean distance from it
    std::uint32_t polar_first = 0;                       ///< the hull vertex at the smallest polar angle
    bool closed = false;  ///< one loop (every vertex on two segments): the section of a solid
  };
  std::vector<Chain> chains;
  std::vector<std::array<glm::dvec2, 2>> segments;
  std::vector<glm::dvec2> hull;
  std::vector<double>
      polar;  ///< per hull vertex: its direction from its chain's centre (tangent walks start)
};

/// Per-thread memory of the shadows.
struct ShadowScratch {
  std::vector<int> parent, chain_of;     // per occluder slice vertex: union-find, its chain
  std::vector<std::uint8_t> degree;      // per occluder slice vertex: its segments
  std::vector<Index> order, edge_order;  // vertices and edges by chain
  std::vector<std::size_t> first;        // (the counting sort's)
  std::vector<glm::dvec2> points;        // of one chain
  std::vector<cgal::Point2> cgal_points, cgal_hull;
  std::vector<Wedge> blocked, united, visible, out;
  std::array<std::vector<Wedge>, 2> side_cone;
  std::vector<AngularInterval> intervals;
  WedgeScratch wedges;
  std::vector<Wedge> wedges_out;
  std::vector<std::array<std::uint32_t, 2>>
      tangents;                    // per chain: the last tangents found (start of the walk)
  std::vector<char> outside_hull;  // per chain: hulls_outside of the viewpoint
  std::vector<std::uint32_t> offsets_out;
};

/// The chains of `occluders` (an occluders-only slice), with their hulls and boxes.
void gather_occluder_chains(const Slice& occluders, ShadowScratch& scratch, OccluderChains& out);

/// Where the occluders are seen from for a cloth point p: p itself, or, in contact, a point of a chain (the
/// segment it lies on, or the end of it). Seen from a point on a closed chain, the segments through it block
/// nothing (the rest of the loop blocks the solid); on an open chain, the segment blocks its back half-plane.
struct Viewpoint {
  glm::dvec2 point{0.0};
  std::int32_t chain = -1;    ///< the chain `point` lies on (-1: p itself, on none)
  std::uint32_t segment = 0;  ///< into OccluderChains::segments
  int end = -1;               ///< -1: inside the segment; 0, 1: at its first or second end
  bool open = false;          ///< the chain is open
};

/// Per chain, whether p lies strictly outside its convex hull (off its box or beyond an edge; a hull of two
/// points: off its line; of one: never), into `outside` (resized to the chains). Exact. O(hull vertices of
/// the chains whose box holds p).
void hulls_outside(const OccluderChains& chains, const glm::dvec2& p, std::vector<char>& outside);

/// The viewpoint of a cloth point p: the nearest point of the closed chains' segments when p lies inside or
/// on a closed chain (the parity of their crossings, exact); else the nearest point of an open chain's
/// segment when p lies on it or behind it (on its back, right side) no farther than `tolerance` > 0 in the
/// plane; else p. `outside`: hulls_outside of p. O(segments of the closed chains whose hull holds p and of
/// the open chains within `tolerance` of their box), O(chains) when none does.
Viewpoint contact_viewpoint(const OccluderChains& chains, const glm::dvec2& p, std::span<const char> outside,
                            double tolerance);

/// What chain `c` blocks seen from `from`: united wedges (is_united), appended to `out`. Segments through
/// the viewpoint block nothing. `outside_hull`: whether from.point lies strictly outside the chain's hull
/// (hulls_outside of from.point).
void blocked_by_chain(const OccluderChains& chains, std::size_t c, const Viewpoint& from, bool outside_hull,
                      ShadowScratch& scratch, std::vector<Wedge>& out);

/// Takes from the cone of every needed slice vertex of `slice` (empty `needed`: every one) on both sides what
/// the chains block seen from its viewpoint (contact_viewpoint with `contact_tolerance`, blocked_by_chain),
/// in place.
void cast_occluder_shadows(const Slice& slice, const OccluderChains& chains, std::span<const char> needed,
                           double contact_tolerance, ShadowScratch& scratch, SliceCones& cones);

}  // namespace pleat
