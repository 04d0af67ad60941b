// What a frame changed, for the kinetic engine's incremental frames (docs/method.md §11.6): which mesh
// vertices moved, which slicing planes their motion reaches, and which mesh vertices a recomputed plane now
// offers something different. Exact: every test is a bitwise comparison or an exact-side bound, so what is
// kept is what a recompute would give, bit for bit.
//
// - A plane's slice, its triangulation and the cones it offers depend only on the mesh edges that cross it
//   (their endpoints' positions) and on the whole-fan marks of the offered vertices; a mesh edge starts or
//   stops crossing only when an endpoint moves. So a plane none of whose crossing edges (at the previous
//   frame or the next) has a moved endpoint, and none of whose offered vertices changed its whole-fan mark,
//   keeps everything (planes_reached).
// - A mesh vertex's 3D cone depends on the offers it takes (their stored cone, apex point, fan cuts' cones
//   and chain angles, distance and side of the plane), on its fan's positions and on the fill's source of
//   each orientation (static_core/internal/frame_assembly.hpp); offers_changed compares a recomputed plane's
//   offers with what it offered before, content for content.
// Internal header: kinetic only. Cost: O(V) for the moved vertices; the rest in proportion to what moved.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "static_core/internal/frame_assembly.hpp"
#include "static_core/mesh.hpp"
#include "static_core/mesh_connectivity.hpp"
#include "static_core/slicing_plan.hpp"

namespace pleat::kinetic {

/// The vertices whose positions differ bit for bit between `previous` and `next` (same size): `moved` per
/// vertex (0/1), `list` in increasing order. O(V).
void find_moved_vertices(const Frame& previous, const Frame& next, std::vector<char>& moved,
                         std::vector<Index>& list);

/// The vertices whose whole-fan mark (FrameMarks::whole_fans) differs between two frames, appended to `list`
/// (unsorted; may repeat a moved vertex).
void append_whole_fan_changes(std::span<const std::uint8_t> before, std::span<const std::uint8_t> after,
                              std::vector<Index>& list);

/// Per plane of `planes` (1 = reached): whether a mesh edge at a vertex of `touched` crosses the plane in
/// `previous` or `next` — bounded exactly: the plane is marked when its offset lies within the heights of the
/// vertex and its neighbours in both frames, widened by far more than a dot product's rounding. A family of
/// planes that are not parallel (a pencil through a line) is marked whole when anything moved. O(touched
/// vertices × degree × orientations × log planes + planes marked).
void planes_reached(const MeshConnectivity& connectivity, std::span<const SlicingPlane> planes,
                    std::size_t orientations, const Frame& previous, const Frame& next,
                    std::span<const Index> touched, std::vector<char>& reached);

/// What offers_changed keeps of a plane's offers before the plane is recomputed: the parts of PlaneCones the
/// 3D assembly reads.
struct OfferSnapshot {
  std::vector<glm::dvec2> points;  ///< per slice vertex
  std::vector<StoredCone> stored;
  std::vector<Index> fan_cuts;
  std::vector<glm::dvec2> chain_angles;
  SliceCones cones;
  void take(const PlaneCones& plane);  ///< copies (reusing this snapshot's memory)
  void clear();                        ///< a plane that offered nothing (new to the frame)
};

/// Per-thread memory of offers_changed.
struct OfferDiffScratch {
  std::vector<std::int64_t> slot;  ///< 2 × receivers entries, all -1 between calls
};

/// Appends to `changed` every mesh vertex (below `receivers`) that `after` offers a cone different from the
/// one `before` offered it on some side (distance, side of the plane, stored cone, apex point, or under
/// AimedOnFan its fan cuts' cones and chain angles), or that one of them offers a cone and the other none.
/// Compared bit for bit. O(offers of both).
void offers_changed(Index receivers, const OfferSnapshot& before, const PlaneCones& after,
                    OfferDiffScratch& scratch, std::vector<Index>& changed);

/// Appends every vertex `plane` offers a cone to `changed` (a plane dropped from the frame).
void append_offered(const PlaneCones& plane, std::vector<Index>& changed);

}  // namespace pleat::kinetic
