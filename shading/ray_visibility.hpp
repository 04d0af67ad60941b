// Ray-cast sky visibility: the Monte-Carlo ground truth of A_front / A_back (docs/method.md §1) and of the
// bent normals, by casting cosine-distributed rays from every vertex with Embree.
//
// Estimator. For vertex v and side s, with axis m = side_sign(s) * n(v), K directions ω_i are drawn from
// the cosine density cos(θ)/π on the hemisphere about m; A = (number of rays that escape) / K. Since
// A = (1/π) ∫ vis(ω) cos θ dω is the cosine-weighted mean of vis, this is unbiased. The K points are a
// Hammersley set ((i + ½)/K, radical-inverse₂(i)) shifted modulo 1 by a per-(seed, vertex, side) random
// offset (Cranley–Patterson rotation), then mapped to the disk by Shirley–Chiu's concentric map and lifted
// to the hemisphere (Malley's method). The shift keeps the estimate unbiased and makes each vertex's
// error independent of its neighbours'; the stratification makes the variance well below the iid bound
// σ² = A(1−A)/K, which is therefore a safe (conservative) error bar. Bent normal: the normalized mean of
// the escaping directions (the cosine-weighted mean visible direction); the side axis when none escapes.
// Deterministic: the same seed gives bit-identical results, serial or parallel.
//
// Self-hits. Rays start exactly at the vertex (in Embree's float coordinates the origin is the vertex of
// the incident triangles). A ray leaving a vertex can meet an incident (planar) triangle only at its
// origin, so:
//  1. Hits on the one-ring triangles are ignored (an Embree context filter); they can only be round-off.
//  2. tnear = 1e-6 × scene diameter skips hits at the origin on non-incident triangles (unwelded seams);
//     cloth layers are never that close.
//  3. Whether a direction leaves on the wanted side is decided locally, from the one-ring itself, exactly:
//     the ring triangles, seen from v, are the arcs of a closed spherical polygon (the link: the directions
//     from v to its one-ring, in winding order), simple wherever the fan does not intersect itself, with the
//     front on its left; ω leaves on the front iff the link winds about it (contains_direction). A direction
//     that crosses the surface at its origin (e.g. at the bottom of a crease, directions of the hemisphere
//     beyond the two faces) counts as blocked without casting it. At a vertex on the mesh's boundary the link
//     is open and nothing is blocked locally (the two sides meet around the boundary); at a non-manifold
//     vertex the ring triangles are projected along n(v) and the one whose plane is nearest to ω among those
//     whose sector contains its projection tells the side — exact only where the fan is a height field over
//     the plane ⊥ n. (Before 2026-11-28 that projection was the rule everywhere; on sharp ridges, where the
//     fan folds over in projection, it blocked directions the vertex sees: docs/benchmarks_archive.md, "Open
//     fans, rings of sky, and an exact reference".)
// Without step 3, the hemisphere about the vertex normal at a crease would see "through" the adjacent
// faces, and a V-fold's bottom would get A = 1 instead of sin α.
//
// Infinite planes (MeshTopology::planes: the ground). A direction into a plane from the vertex's side of it
// (a vertex on it: above, as the engines take it) is blocked without casting it. The plane's square, which
// the scene holds for rendering, ends 50 cloth diagonals away: cast at it alone, rays just below the horizon
// passed beyond its edge (an upright sheet 10 units over the ground read A = 0.74 instead of 0.5; the
// drape's front sides up to 0.005 too high, 0.001 on average).
//
// Cost: K rays per vertex and side; Embree streams of 64 rays (faster than rtcOccluded1 loops), TBB-parallel
// over vertices; some samples are decided by the one-ring test without a ray. Rays per second:
// docs/benchmarks_archive.md, "Against Embree at matched error".
#pragma once

#include <array>
#include <cstdint>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <span>
#include <vector>

#include "shading/embree_scene.hpp"
#include "static_core/mesh.hpp"

namespace pleat {

struct RayVisibilityParams {
  int rays_per_vertex = 256;  ///< K, per vertex and side (the ground truth uses 4096)
  std::uint64_t seed = 1;
  bool parallel = true;  ///< TBB-parallel over vertices
  /// Estimate only vertices 0, s, 2s, ... (a ground truth on a sample of a large mesh); the others get NaN.
  Index vertex_stride = 1;
};

/// Per-vertex results, indexed [side][vertex] (side 0 = Front, 1 = Back).
struct RayVisibility {
  std::array<std::vector<double>, 2> sky_visibility;    ///< A estimate in [0,1]
  std::array<std::vector<glm::dvec3>, 2> bent_normals;  ///< unit; side axis if nothing escapes
  std::uint64_t rays_cast = 0;  ///< rays handed to Embree (locally blocked ones excluded)
};

/// The preconditions shared by the per-vertex Embree estimators (ray casting, path tracing): `count` >= 1,
/// one position per vertex and one normal per vertex that is not an occluder (MeshTopology::num_receivers:
/// the estimators cast from those only; occluders block), a scene built for this topology. Throws
/// std::invalid_argument naming `who`.
void check_vertex_estimator_inputs(const char* who, const char* count_name, int count,
                                   const EmbreeScene& scene, const MeshTopology& topology, const Frame& frame,
                                   const std::vector<glm::dvec3>& normals);

/// Estimates A and bent normals for every vertex and both sides of `frame`. Brings `scene` to `frame`
/// first (a refit, free if it already holds it). `normals` are the unit vertex normals n(v) of `frame`
/// (static_core's vertex_normals). Throws std::invalid_argument on size mismatches or K < 1.
RayVisibility ray_cast_visibility(EmbreeScene& scene, const MeshTopology& topology, const Frame& frame,
                                  const std::vector<glm::dvec3>& normals,
                                  const RayVisibilityParams& params = {});

/// A only: {A_front, A_back} per vertex. Same estimator as ray_cast_visibility.
std::array<std::vector<double>, 2> ray_cast_sky_visibility(EmbreeScene& scene, const MeshTopology& topology,
                                                           const Frame& frame,
                                                           const std::vector<glm::dvec3>& normals,
                                                           const RayVisibilityParams& params = {});

/// The one-ring of a vertex, prepared to tell on which side of the cloth a direction leaves the vertex
/// ("Self-hits", step 3 above). build() once per vertex (reuses its buffers), then O(ring size) per query.
class VertexFan {
 public:
  /// `ring`: the triangles incident to v (EmbreeScene::incident_triangles); `n`: the unit normal n(v).
  void build(const MeshTopology& topology, const Frame& frame, std::span<const Index> ring, Index v,
             const glm::dvec3& n);
  /// +1 if w leaves v on the front, -1 on the back, 0 if it leaves on neither alone (v on the boundary, or,
  /// at a non-manifold vertex, w passing over no ring triangle).
  int side_of(const glm::dvec3& w) const;
  /// True if a ray from v along w, wanted on `side`, crosses the cloth at its origin.
  bool enters_cloth(const glm::dvec3& w, Side side) const;

 private:
  struct Wedge {
    glm::dvec3 sector_a;  // n × ea: w·(n × ea) = (ea × w)·n  (ea, eb: other corners − v, in winding order)
    glm::dvec3 sector_b;     // eb × n: w·(eb × n) = (w × eb)·n
    glm::dvec3 unit_normal;  // (ea × eb) normalized: the input winding's front
    bool flipped;            // (ea × eb)·n < 0: w's projection is in the sector iff both dots are <= 0
    bool edge_on;            // (ea × eb)·n == 0: seen edge-on along n, its sector is empty
  };
  enum class Ring { Closed, Open, NonManifold };
  /// The link of a closed ring (unit directions from v, in winding order) and its solid angle; the
  /// projection rule's wedges are used at a non-manifold vertex only (and their normals by the fast path).
  Ring m_ring = Ring::Open;
  std::vector<glm::dvec3> m_link;
  double m_link_solid_angle = 0.0;
  std::vector<std::array<Index, 2>> m_edges;  // build()'s scratch: the far edge of each ring triangle
  std::vector<Wedge> m_wedges;
};

// ---- Sampling helpers shared by the Monte-Carlo integrators (ray visibility, path tracer). ----

/// SplitMix64's finaliser: a strong 64-bit mix, the basis of every seeded stream in pleat's samplers.
constexpr std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}
/// The top 53 bits as a double in [0, 1).
constexpr double unit_double(std::uint64_t bits) { return static_cast<double>(bits >> 11) * 0x1.0p-53; }

/// (u1, u2) in [0,1)² to a cosine-distributed direction about +z (Shirley–Chiu concentric disk map,
/// lifted; libm-free, so the same bits on every platform). Unit to 1e-8.
glm::dvec3 cosine_hemisphere_direction(double u1, double u2);

/// Orthonormal t1, t2 with t1 × t2 = axis, for a unit axis (Frisvad; Duff et al.'s branch-free variant).
void tangent_basis(const glm::dvec3& axis, glm::dvec3& t1, glm::dvec3& t2);

/// The K stratified, cosine-distributed directions in the local frame (z = axis) that vertex `vertex`,
/// side `side` uses for `seed`; exposed for tests and for other Monte-Carlo integrators of the same cone.
void cosine_hemisphere_directions(int count, std::uint64_t seed, Index vertex, Side side,
                                  std::vector<glm::dvec3>& out);

}  // namespace pleat
