// EmbreeScene: one cloth mesh in an Embree 3 BVH, kept in step with the animation, and the ray queries that
// pleat's ray-cast ground truth (ray_visibility), renderer (render) and path tracer need.
//
// Why: the visibility cones are checked against brute-force ray casting, and images are made by casting
// primary rays; both want one BVH per mesh that follows the frames cheaply. Connectivity is fixed for a
// sequence, so the index buffer is built once and only positions change: update() refits the BVH
// (RTC_BUILD_QUALITY_REFIT, cheaper than a build) or rebuilds it (docs/benchmarks.md has both costs).
// A refit keeps the tree's topology, so its quality degrades when the cloth moves far from the frame it
// was built on; call rebuild() now and then (or use BuildMode::Rebuild) for long sequences.
//
// Precision: Embree works in float. Positions are stored relative to the first frame's bounding-box centre
// so that coordinates far from the origin keep their relative precision; queries take and return world
// coordinates (double) and translate.
//
// Self-hits: a query may name a set of triangles to ignore (the one-ring of the vertex a ray starts from).
// It is applied by an Embree context filter function, so queries that ignore nothing pay nothing.
//
// Thread safety: queries are const and may run concurrently; update/rebuild must not overlap queries.
// Embree handles never appear in this header.
#pragma once

#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <limits>
#include <memory>
#include <span>
#include <vector>

#include "static_core/mesh.hpp"

namespace pleat {

struct EmbreeSceneParams {
  enum class BuildMode {
    Refit,    ///< update() refits the existing BVH (fast; quality drifts with large motion)
    Rebuild,  ///< update() builds a new BVH (slower; best trace speed)
  };
  BuildMode mode = BuildMode::Refit;
  /// RTC_SCENE_FLAG_ROBUST: watertight traversal without accuracy-reducing shortcuts. On for ground truth.
  bool robust = true;
  /// How escaping_rays hands its rays to Embree. Every call gives the same answers; which is fastest depends
  /// on the CPU and the scene (bench/frame_coherence_bench measures them and uses the fastest).
  enum class RayCall {
    Stream,    ///< rtcOccluded1M over chunks of 64 rays (Embree forms packets itself)
    Packet4,   ///< rtcOccluded4 (SSE-width packets)
    Packet8,   ///< rtcOccluded8 (AVX-width packets)
    Packet16,  ///< rtcOccluded16 (AVX-512-width packets; emulated on narrower CPUs)
    Single,    ///< rtcOccluded1, one ray at a time
  };
  RayCall ray_call = RayCall::Stream;
  /// RTC_INTERSECT_CONTEXT_FLAG_COHERENT for escaping_rays (its rays share an origin): a hint, same answers.
  bool coherent = false;
};

/// "stream", "packet4", "packet8", "packet16", "single".
const char* ray_call_name(EmbreeSceneParams::RayCall call);

/// One ray, in world coordinates. `direction` need not be unit; t is measured in units of |direction|.
struct RayQuery {
  glm::dvec3 origin{0.0};
  glm::dvec3 direction{0.0, 0.0, 1.0};
  double tnear = 0.0;
  double tfar = std::numeric_limits<double>::infinity();
};

/// The closest hit of a ray, if any.
struct RayHit {
  bool hit = false;
  double t = 0.0;
  Index triangle = 0;       ///< index into MeshTopology::triangles
  double u = 0.0, v = 0.0;  ///< barycentrics: point = (1-u-v) p0 + u p1 + v p2 (triangle corners in order)
};

/// Triangles a query ignores (typically the one-ring of the ray's origin vertex). Unordered, small.
using IgnoredTriangles = std::span<const Index>;

class EmbreeScene {
 public:
  /// Builds the BVH of `frame` over `topology`. Throws std::invalid_argument on a size mismatch, an index
  /// out of range or a non-finite position, std::runtime_error if Embree fails.
  EmbreeScene(const MeshTopology& topology, const Frame& frame, const EmbreeSceneParams& params = {});
  ~EmbreeScene();
  EmbreeScene(EmbreeScene&&) noexcept;
  EmbreeScene& operator=(EmbreeScene&&) noexcept;
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  /// Brings the BVH to `frame` (same topology): a refit or a rebuild according to params.mode. A frame
  /// whose float positions equal the current ones costs one O(n) comparison and no BVH work.
  void update(const Frame& frame);
  /// Full BVH build on `frame`, whatever the mode.
  void rebuild(const Frame& frame);

  /// Closest hit along the ray, or hit == false.
  RayHit intersect(const RayQuery& ray, IgnoredTriangles ignore = {}) const;
  /// True if anything (other than `ignore`) is hit in [tnear, tfar].
  bool occluded(const RayQuery& ray, IgnoredTriangles ignore = {}) const;
  /// Many rays from one origin: escaped[i] = 1 if the ray along directions[i] (t in [tnear, inf)) meets
  /// nothing outside `ignore`, else 0. Uses Embree's ray streams. escaped.size() == directions.size().
  void escaping_rays(const glm::dvec3& origin, std::span<const glm::vec3> directions, double tnear,
                     IgnoredTriangles ignore, std::span<std::uint8_t> escaped) const;

  /// Triangles incident to vertex v, ascending (the one-ring a ray leaving v must ignore).
  std::span<const Index> incident_triangles(Index v) const;

  const MeshTopology& topology() const;
  /// Diagonal of the current frame's bounding box (the scene scale for relative epsilons).
  double scene_diameter() const;

  std::size_t refits() const;    ///< BVH refits done by update()
  std::size_t rebuilds() const;  ///< full builds, including the first

 private:
  struct Impl;
  std::unique_ptr<Impl> m_impl;
};

}  // namespace pleat
