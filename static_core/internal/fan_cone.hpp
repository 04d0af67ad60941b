// A mesh vertex's 2D cone in one slicing plane, from every cut of its fan (docs/method.md §7, "The cone of
// the fan"). Used by the aimed-on-fan storage rule before its cones are aimed at the vertex.
//
// A plane near a mesh vertex v cuts several of v's edges. A cut Y (a slice vertex) knows what lies beyond the
// surface only on its own side of the chain: its cone lies within its *local range*, the directions between
// the chain's two edges at Y. Where v sits on a sharp ridge or in a crease, the nearest cut lies on one flank
// and its range misses directions v itself sees; the cuts on the other flanks see them. So v's cone in the
// plane is assembled from all its cuts, nearest first: each gives its cone over the part of its local range
// that no nearer cut's range covered; a direction no cut's range covers counts as blocked. The result is cut
// to v's own local range in the plane through v parallel to the slicing plane — where v's fan crosses that
// plane, the one-ring's own occlusion, exactly. Every end keeps its reach, which aim_wedges then measures
// from the nearest cut (its apex): the cuts lie within an edge of each other, and turning the other cuts'
// ends towards their horizon points as seen from the nearest, or dropping their reaches, measured slightly
// worse (docs/benchmarks_archive.md, "Where the error is, per vertex, and the cone of the fan"). Internal
// header: static_core and kinetic only.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <span>
#include <vector>

#include "static_core/angular_set.hpp"
#include "static_core/internal/slice_cones.hpp"
#include "static_core/mesh.hpp"
#include "static_core/mesh_connectivity.hpp"
#include "static_core/mesh_slicer.hpp"
#include "static_core/slicing_plan.hpp"

namespace pleat {

/// The local ranges of mesh vertex v on both sides within its fan, in the plane through v parallel to
/// `plane` (its (u, w) frame), as sorted linear intervals of [0, 2pi] (split_into_intervals' form): where the
/// fan's triangles cross that plane they bound them, the front side being the one their (input-winding)
/// normals face. An open fan (v on the mesh's boundary, or a bow-tie: MeshConnectivity::has_closed_fan false)
/// bounds neither side: both ranges are the whole turn, its two sides meeting round the boundary. False, and
/// the outputs cleared, where a closed fan's crossings do not alternate between the sides (it only touches
/// the plane at v, or folds there): the fan then gives no range. Floating-point decisions: the range is a
/// sample of the visible set, not a topology.
bool fan_local_ranges(const MeshTopology& topology, const MeshConnectivity& connectivity, const Frame& frame,
                      Index v, const SlicingPlane& plane, std::vector<AngularInterval>& front,
                      std::vector<AngularInterval>& back);

/// The angles of slice vertex x's outgoing and incoming chain edges (towards the next and the previous slice
/// vertex), in [0, 2pi); NaN at a chain's end. Its front local range runs counter-clockwise from the first to
/// the second, its back range from the second to the first: where its 2D cones lie. At a chain's end both
/// cones lie anywhere in the whole turn.
glm::dvec2 chain_edge_angles(const Slice& slice, Index x);

/// Whether a vertex's fan is sharp enough for fan_cone: one of its triangles turns from the vertex's
/// area-weighted normal by more than acos(kSharpFan) (a ridge or a crease, where the nearest cut's local
/// range misses much of the vertex's own). Elsewhere the nearest cut's cone is kept as the vertex's: nearly
/// as accurate as assembling every fan's cone, at a fraction of the cost (docs/benchmarks_archive.md, "Where
/// the error is, per vertex, and the cone of the fan").
inline constexpr double kSharpFan = 0.7;
/// Per vertex, 1 where its cone in a plane is to be assembled from its whole fan (fan_cone) into `whole`:
/// where the fan is sharp (see kSharpFan) about its unit normal (`normals`: the engines'
/// area_weighted_normals), and where it is open (on the mesh's boundary: the vertex sees round the edge,
/// which a cut inside the chain, its range on one side of it, does not; docs/benchmarks_archive.md, "Open
/// fans, rings of sky, and an exact reference"). O(triangles + vertices), once per frame.
void mark_whole_fans(const MeshTopology& topology, const MeshConnectivity& connectivity, const Frame& frame,
                     std::span<const glm::dvec3> normals, std::vector<std::uint8_t>& whole);

/// Reusable memory of fan_cone.
struct FanConeScratch {
  std::vector<AngularInterval> todo, next, range, cone, seen;
};

/// v's cone on `side` in one plane, into `out` (cleared first): the cones of the plane's cuts of v's edges
/// (`cuts`, nearest first; their cones in `cones`, their chain_edge_angles in `chain_angles`, per slice
/// vertex), each over the part of its local range no nearer cut covered, within `vertex_range`
/// (fan_local_ranges); a cut at a chain's end ranges over the whole turn. Ends keep their reaches. Stops once
/// the cuts cover `vertex_range`.
void fan_cone(std::span<const Index> cuts, const SliceCones& cones, std::span<const glm::dvec2> chain_angles,
              Side side, std::span<const AngularInterval> vertex_range, FanConeScratch& scratch,
              std::vector<Wedge>& out);

}  // namespace pleat
