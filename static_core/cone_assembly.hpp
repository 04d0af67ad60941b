// From 2D cones stored on a mesh vertex to its 3D visibility cones (Stewart 1999 §2.4; docs/method.md §8).
//
// Each stored 2D cone is a set of wedges in a slicing plane, taken with its apex at the mesh vertex. The
// wedges are first clipped to the side's half-space (directions d with d . side*n(v) >= 0). Two wedges are
// linked when they share more than the apex (the paper's test: the planes' common line lies in both) or
// when a point of one arc lies over the other — near its circle, or farther where the circles between saw
// the way down open — or near its ends (slices sample a visible region sparsely,
// so arcs of one narrow opening rarely cross exactly; a wedge that joins no other becomes a thin band
// about its plane, half the angle between neighbouring orientations wide); each connected group becomes one
// piece: its wedges' bounding directions are sorted radially about the group's mean direction (azimuthal
// projection about it) — a polygonal cone, not necessarily convex, counter-clockwise. (The paper sorts about
// the centroid of the points projected onto the tangent plane; that fails on the slot-shaped cones of deep
// folds — see cone_assembly.cpp.) Between two consecutive bounding directions whose horizon great circles are
// known (PlanarCone::tangents from aim_wedges; the side's horizon and the occluding planes where an end was
// clipped to them), the piece follows the horizon instead of the chord: a corner where the two great circles
// meet — exactly there between two planes' boundaries and where an occluding plane's (the ground's) meets a
// curved horizon, else 2/3 of the way from the chord's middle (a parabolic arc's bulge). Cost: O(k^2) for k
// wedges at the vertex (k is a few dozen).
// Thread safety: reentrant; each thread its own ConeAssemblyScratch.
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "static_core/planar_cone.hpp"
#include "static_core/slicing_plan.hpp"
#include "static_core/visibility_cone.hpp"

namespace pleat {

/// Reusable memory of assemble_cone (one per thread): no allocation per call once it has grown.
class ConeAssemblyScratch {
 public:
  ConeAssemblyScratch();
  ~ConeAssemblyScratch();
  struct Buffers;
  std::unique_ptr<Buffers> m_buffers;
};

/// The 3D visibility cone of a vertex on one side from its 2D cones. `side_normal` = side * n(v), unit.
/// Writes into `result`, reusing its memory.
void assemble_cone(std::span<const PlanarCone> cones, const glm::dvec3& side_normal,
                   ConeAssemblyScratch& scratch, VisibilityCone& result);
/// The same, and the cone's measures (as measure_cone gives them) from the integrals the assembly computes
/// anyway (each piece's vector irradiance and solid angle): what the engines call. Each wedge is also clipped
/// to every half-space {d : dot(d, h) >= 0} of `half_spaces` (unit normals: the sides of the occluding planes
/// the vertex is on, MeshTopology::planes). `rule`: the reconstruction rule's row
/// (static_core/cone_rules.hpp; this file's grouped rule, or the nearest-circle rule of
/// static_core/internal/nearest_circle.hpp), its reconstructor made in `scratch` when first used.
void assemble_and_measure_cone(std::span<const PlanarCone> cones, const glm::dvec3& side_normal,
                               ConeAssemblyScratch& scratch, VisibilityCone& result, ConeMeasures* measures,
                               std::span<const glm::dvec3> half_spaces = {},
                               ConeReconstruction rule = ConeReconstruction::Grouped);
/// The same, allocating (tests, one-off use).
VisibilityCone assemble_cone(std::span<const PlanarCone> cones, const glm::dvec3& side_normal);

/// The measures of `cone` from each piece's vector irradiance and solid angle (as measure_cone sums them):
/// for a reconstruction rule that computed them. O(pieces).
ConeMeasures measures_of_pieces(const VisibilityCone& cone, std::span<const glm::dvec3> irradiance,
                                std::span<const double> solid_angle, const glm::dvec3& side_normal);

/// A, bent normal and solid angle of a cone from assemble_cone (Lambert's formula on each piece).
ConeMeasures measure_cone(const VisibilityCone& cone, const glm::dvec3& side_normal);

}  // namespace pleat
