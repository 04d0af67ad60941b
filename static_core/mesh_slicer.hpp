// Slicing a mesh with a plane (Stewart 1999 §2; docs/method.md §3).
//
// The slice of a mesh by a plane has one slice vertex per mesh edge that crosses the plane and one slice
// edge per face that crosses it; they form open or closed chains. Which side of the plane a mesh vertex is
// on is decided exactly (filtered exact predicate); a vertex exactly on the plane is treated as lying just
// above it (symbolic perturbation), so every face is either uncut or cut along exactly two of its edges and
// the chains are always well formed. Slice edges are oriented so that the front side of the surface (the
// side its face normals point to, in the input winding) is on their left.
// Cost: O(#candidate faces) per plane.
// Thread safety: reentrant; each thread its own SlicerScratch.
#pragma once

#include <cstdint>
#include <glm/vec2.hpp>
#include <span>
#include <vector>

#include "static_core/mesh.hpp"
#include "static_core/mesh_connectivity.hpp"
#include "static_core/slicing_plan.hpp"

namespace pleat {

struct SliceVertex {
  Index edge = 0;         ///< the mesh edge it lies on
  Index above = 0;        ///< the edge's endpoint on or above the plane
  Index below = 0;        ///< the edge's endpoint below the plane
  double t = 0.0;         ///< position along the edge, from `above` (0) to `below` (1)
  glm::dvec2 point{0.0};  ///< 2D coordinates in the plane's (u, w) frame
  Index nearer = 0;       ///< the nearer endpoint, on which the 2D cone is stored
  double distance = 0.0;  ///< 3D distance from `nearer`
};

/// A slice edge from `from` to `to` (slice vertex indices), with the front side on its left.
struct SliceEdge {
  Index from = 0;
  Index to = 0;
  Index face = 0;
};

struct Slice {
  std::vector<SliceVertex> vertices;
  std::vector<SliceEdge> edges;
  std::vector<std::int32_t> out_edge;  ///< per slice vertex: a slice edge leaving it, or -1
  std::vector<std::int32_t> in_edge;   ///< per slice vertex: a slice edge entering it, or -1
  void clear();
};

/// Reusable per-thread memory of slice_mesh (no allocation per slice once warmed up).
struct SlicerScratch {
  std::vector<std::int32_t> slice_vertex_of_edge;  ///< -1 where the edge was not crossed
  std::vector<std::uint8_t> flat;                  ///< per slice vertex: on a flat edge (run through)
  std::vector<std::int32_t> new_index;             ///< per slice vertex: its index once flat ones are out
  std::vector<SliceEdge> edges;                    ///< the chain edges once flat crossings are run through
};

/// Slices the faces listed in `candidate_faces` (all faces that may cross the plane; others are ignored)
/// into `out`. Deterministic: slice vertices are numbered in order of first appearance.
///
/// `flat_edges` (per mesh edge, from flat_occluder_edges for this frame; empty: none): a chain runs straight
/// through a crossing of a flat edge, so that crossing gets no slice vertex and the two slice edges on either
/// side of it are one. The chain is the same point set (the crossing lies on the segment between its chain
/// neighbours, exactly); only occluders' edges are flat, so no vertex loses a cone.
void slice_mesh(const MeshTopology& topology, const MeshConnectivity& connectivity, const Frame& frame,
                const SlicingPlane& plane, std::span<const Index> candidate_faces, SlicerScratch& scratch,
                Slice& out, std::span<const std::uint8_t> flat_edges = {});

/// Per mesh edge of `connectivity`, 1 where the edge is *flat* in `frame`: an interior edge (two faces, in
/// opposite directions) between occluder vertices whose two faces lie in one plane on either side of it —
/// coplanar and not folded onto each other, decided exactly (CGAL's orientation and coplanar_orientation on
/// the input coordinates), a face with collinear corners never flat. A modelled table's caps and the
/// diagonals of a cylinder's side quads are flat; cloth edges never are. O(edges), once per frame.
void flat_occluder_edges(const MeshTopology& topology, const MeshConnectivity& connectivity,
                         const Frame& frame, std::vector<std::uint8_t>& flat);

/// For each plane of the plan, the faces that may cross it (the candidate_faces of slice_mesh), among the
/// topology's sliced triangles (MeshTopology::num_sliced_triangles). Parallel
/// families are bucketed by offset: a face is listed for the planes within its height interval widened by a
/// margin far above the rounding of a dot product; other planes get every face. O(F log P + output).
std::vector<std::vector<Index>> candidate_faces_per_plane(const MeshTopology& topology, const Frame& frame,
                                                          const SlicingPlan& plan);
/// The same into `result`, reusing its lists' memory (a sequence: once per frame). With `only` (per plane;
/// empty: every plane), the planes marked 0 get an empty list (the kinetic engine's planes that keep their
/// slice).
void candidate_faces_per_plane(const MeshTopology& topology, const Frame& frame, const SlicingPlan& plan,
                               std::vector<std::vector<Index>>& result, std::span<const char> only = {});

/// A plane's candidate faces (sorted, as candidate_faces_per_plane lists them) split into the cloth's and the
/// occluders' (whose triangles follow the cloth's: MeshTopology). The cloth's are sliced and triangulated;
/// the occluders' are sliced for their shadows (docs/method.md §3).
struct PlaneFaces {
  std::span<const Index> cloth, occluders;
};
PlaneFaces split_faces(const MeshTopology& topology, std::span<const Index> faces);

/// Exact side of a point against a plane: true when on or above (dot(normal, p) >= offset). A floating-point
/// filter decides whenever its error bound allows (almost always); CGAL's exact predicate the rest.
bool on_or_above(const SlicingPlane& plane, const glm::dvec3& p);
/// The same by CGAL's exact predicate alone (the filter's oracle in the tests).
bool on_or_above_exact(const SlicingPlane& plane, const glm::dvec3& p);

/// The mesh vertices that receive a 2D cone from this plane (the nearer endpoints of its slice vertices).
std::vector<Index> cone_recipients(const MeshTopology& topology, const MeshConnectivity& connectivity,
                                   const Frame& frame, const SlicingPlane& plane);

}  // namespace pleat
