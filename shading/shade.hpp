// shade_frame: per-vertex, per-side radiance of the cloth from its visibility cones, with the Stewart–Langer
// local inter-reflection model, and the tone mapping to the sRGB colours that viewers show.
//
// Radiometry (Lambertian cloth of albedo rho; docs/method.md §10; Stewart & Langer, PAMI 1997). The occluded
// directions of a point are assumed to radiate the point's own radiance B, so the total irradiance is
// E + pi B (1 - A), E the direct irradiance from all lights through the cone and A the sky visibility,
// and B = (rho / pi) (E + pi B (1 - A)), i.e.
//     B = rho (E / pi) / (1 - rho (1 - A)).
// For a uniform sky of radiance L, E = pi L A and this is the paper's B = rho L A / (1 - rho (1 - A)):
// A = 1 gives rho L, A = 0 gives 0, and B grows monotonically with A. Without inter-reflection,
// B = rho E / pi. Both sides of the cloth are shaded, each from its own cone about side * n(v).
//
// Tone mapping (to_srgb): multiply by the exposure, compress the luminance Y (Rec. 709 weights) by the
// extended Reinhard curve Y' = Y (1 + Y / W^2) / (1 + Y) with white point W (default 4: radiance 4 maps to
// 1), scale the colour by Y'/Y (hue kept), clamp to [0,1] and encode with the sRGB transfer function.
// ToneMap::Clamp skips the curve (exposure, clamp, sRGB): for checking exact values.
//
// Cost: O(sum of cone edges x lights) per frame at most, O(1) per vertex and side for uniform skies (A read
// from FrameVisibility::measures); TBB-parallel over vertices, one ConeLighting (scratch) per thread: no
// allocation per vertex once warm. Measured in bench/shading_bench.cpp (bench/results/shading.md).
// Preconditions: visibility was computed for this frame (normals and cones sized to the topology's vertices).
#pragma once

#include <array>
#include <glm/vec3.hpp>
#include <vector>

#include "shading/lights.hpp"
#include "static_core/mesh.hpp"
#include "static_core/visibility_cone.hpp"

namespace pleat {

struct ShadeParams {
  double albedo = 0.6;          ///< rho, per mesh, in [0, 1)
  double exposure = 1.0;        ///< used by the tone mapping of callers (pleat shade)
  bool interreflection = true;  ///< Stewart–Langer; false: B = rho E / pi
  bool parallel = true;         ///< TBB over vertices
};

struct ShadedFrame {
  std::array<std::vector<glm::vec3>, 2> radiance;    ///< [side][vertex]: linear RGB radiance B
  std::array<std::vector<glm::vec3>, 2> irradiance;  ///< [side][vertex]: direct irradiance E
  std::array<std::vector<float>, 2> sky_visibility;  ///< [side][vertex]: A from the clipped cone

  const std::vector<glm::vec3>& front() const { return radiance[0]; }
  const std::vector<glm::vec3>& back() const { return radiance[1]; }
};

/// Stewart–Langer radiance for direct irradiance E and sky visibility A (see above); albedo in [0, 1).
glm::dvec3 stewart_langer_radiance(double albedo, const glm::dvec3& irradiance, double sky_visibility);

/// Shades every vertex on both sides. Throws InputError on an invalid frame (static_core/mesh_validation.hpp;
/// the triangles are not read, so not checked), std::invalid_argument on a visibility of another size or a
/// bad albedo. When visibility.measures are present (compute_visibility fills them), A is read from them
/// rather than recomputed (see cone_lighting.hpp's fast paths).
ShadedFrame shade_frame(const MeshTopology& topology, const Frame& frame, const FrameVisibility& visibility,
                        const Lighting& lighting, const ShadeParams& params = {});
/// The same into `out`, reusing its storage (no allocation per frame once sized).
void shade_frame(const MeshTopology& topology, const Frame& frame, const FrameVisibility& visibility,
                 const Lighting& lighting, const ShadeParams& params, ShadedFrame& out);

enum class ToneMap { Reinhard, Clamp };

struct ToneMapParams {
  double exposure = 1.0;
  ToneMap op = ToneMap::Reinhard;
  double white = 4.0;  ///< Reinhard white point: this (exposed) luminance maps to 1
};

/// One colour through the tone mapping above; components in [0, 1].
glm::vec3 tone_map(const glm::vec3& linear, const ToneMapParams& params);
std::vector<glm::vec3> to_srgb(const std::vector<glm::vec3>& linear, const ToneMapParams& params);
/// Reinhard (white 4) at the given exposure.
std::vector<glm::vec3> to_srgb(const std::vector<glm::vec3>& linear, double exposure);

}  // namespace pleat
