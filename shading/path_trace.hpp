// path_trace: a Monte-Carlo path-traced reference of the cloth's radiance, per vertex and side, under the
// same lights that pleat's cone shading uses (shading/lights.hpp), to show how close the Stewart–Langer
// local model is (`pleat compare`: side by side with an Embree path-traced reference).
//
// Model. Lambertian cloth of albedo ρ (grey, both sides), lights as in shade.hpp: B = (ρ/π) E_direct +
// ρ · E_cos[L_in], the second term estimated by paths. The first bounce from vertex v (side s) uses the
// same stratified cosine directions and the same self-hit rules as ray_visibility (a direction that
// crosses the cloth at v meets the cloth right there: the path continues from v, same side — the exact
// limit of a crease, and the Stewart–Langer assumption made literal). Later bounces start on the hit
// triangle (its geometric normal, on the side facing the ray; the hit triangle is ignored, tnear relative
// to the scene). Escaping rays collect the sky lights (uniform, cloudy, environment) and any area light
// polygon they cross before the cloth; point and directional lights are sampled at every path vertex with
// a shadow ray (next-event estimation). Paths stop by Russian roulette (survival ρ) after 3 bounces, so
// the estimate is unbiased; a hard cap of 64 bounces only guards against ρ ≈ 1.
// Cost: paths × (mean depth ≈ 1/(1−ρ)) rays (+ one shadow ray per delta light per path vertex) per vertex
// and side; TBB over vertices. Deterministic for a seed.
#pragma once

#include <array>
#include <cstdint>
#include <glm/vec3.hpp>
#include <vector>

#include "shading/embree_scene.hpp"
#include "shading/lights.hpp"
#include "static_core/mesh.hpp"

namespace pleat {

struct PathTraceParams {
  int paths_per_vertex = 1024;  ///< per vertex and side
  double albedo = 0.6;          ///< ρ in [0, 1)
  std::uint64_t seed = 1;
  bool parallel = true;
};

struct PathTracedFrame {
  std::array<std::vector<glm::vec3>, 2> radiance;  ///< [side][vertex]: linear RGB B, as ShadedFrame::radiance
  std::uint64_t rays = 0;                          ///< rays traced, shadow rays included
};

/// Path-traces every vertex's outgoing radiance on both sides of `frame` (brings `scene` to it first).
/// `normals`: the unit vertex normals (static_core's vertex_normals). Throws InputError on an invalid
/// topology or frame (static_core/mesh_validation.hpp), std::invalid_argument on other size mismatches, paths
/// < 1 or albedo outside [0, 1).
PathTracedFrame path_trace_vertices(EmbreeScene& scene, const MeshTopology& topology, const Frame& frame,
                                    const std::vector<glm::dvec3>& normals, const Lighting& lighting,
                                    const PathTraceParams& params = {});

}  // namespace pleat
