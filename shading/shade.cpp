// shade_frame and tone mapping (see header).
#include "shading/shade.hpp"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <glm/common.hpp>
#include <stdexcept>
#include <string>

#include "shading/cone_lighting.hpp"
#include "static_core/mesh_validation.hpp"
#include "support/srgb.hpp"

namespace pleat {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

glm::dvec3 stewart_langer_radiance(double albedo, const glm::dvec3& irradiance, double sky_visibility) {
  const double a = std::clamp(sky_visibility, 0.0, 1.0);
  return (albedo / (1.0 - albedo * (1.0 - a))) * (irradiance / kPi);
}

void shade_frame(const MeshTopology& topology, const Frame& frame, const FrameVisibility& visibility,
                 const Lighting& lighting, const ShadeParams& params, ShadedFrame& out) {
  // The frame only: shading reads positions, never triangles, and a topology check would cost several
  // percent of a sky-only pass (static_core/mesh_validation.hpp).
  validate_frame(topology, frame, "shade_frame");
  const std::size_t n = topology.num_vertices;
  if (visibility.normals.size() != n || visibility.cones[0].size() != n || visibility.cones[1].size() != n)
    throw std::invalid_argument("shade_frame: visibility does not match the mesh's " + std::to_string(n) +
                                " vertices");
  if (!(params.albedo >= 0.0 && params.albedo < 1.0))
    throw std::invalid_argument("shade_frame: albedo must be in [0, 1)");
  const bool have_measures = visibility.measures[0].size() == n && visibility.measures[1].size() == n;

  for (int s = 0; s < 2; ++s) {
    out.radiance[s].resize(n);
    out.irradiance[s].resize(n);
    out.sky_visibility[s].resize(n);
  }
  tbb::enumerable_thread_specific<ConeLighting> scratch([&] { return ConeLighting(lighting); });
  auto shade_range = [&](const tbb::blocked_range<std::size_t>& range, ConeLighting& cone_lighting) {
    for (std::size_t v = range.begin(); v != range.end(); ++v) {
      for (Side side : kBothSides) {
        const int s = static_cast<int>(side);
        const glm::dvec3 axis = side_sign(side) * visibility.normals[v];
        const ConeIrradiance e = cone_lighting.evaluate(visibility.cones[s][v], frame.positions[v], axis,
                                                        have_measures ? &visibility.measures[s][v] : nullptr);
        const glm::dvec3 b = params.interreflection
                                 ? stewart_langer_radiance(params.albedo, e.irradiance, e.sky_visibility)
                                 : (params.albedo / kPi) * e.irradiance;
        out.radiance[s][v] = glm::vec3(b);
        out.irradiance[s][v] = glm::vec3(e.irradiance);
        out.sky_visibility[s][v] = static_cast<float>(e.sky_visibility);
      }
    }
  };
  const tbb::blocked_range<std::size_t> all(0, n, 256);
  if (params.parallel) {
    tbb::parallel_for(
        all, [&](const tbb::blocked_range<std::size_t>& range) { shade_range(range, scratch.local()); });
  } else {
    ConeLighting cone_lighting(lighting);
    shade_range(all, cone_lighting);
  }
}

ShadedFrame shade_frame(const MeshTopology& topology, const Frame& frame, const FrameVisibility& visibility,
                        const Lighting& lighting, const ShadeParams& params) {
  ShadedFrame out;
  shade_frame(topology, frame, visibility, lighting, params, out);
  return out;
}

glm::vec3 tone_map(const glm::vec3& linear, const ToneMapParams& params) {
  glm::dvec3 c = glm::max(glm::dvec3(linear), glm::dvec3(0.0)) * params.exposure;
  if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z)) c = glm::dvec3(0.0);
  if (params.op == ToneMap::Reinhard) {
    const double y = 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
    if (y > 0.0) {
      const double w2 = params.white * params.white;
      const double mapped = y * (1.0 + y / w2) / (1.0 + y);
      c *= mapped / y;
    }
  }
  return {linear_to_srgb(static_cast<float>(c.x)), linear_to_srgb(static_cast<float>(c.y)),
          linear_to_srgb(static_cast<float>(c.z))};
}

std::vector<glm::vec3> to_srgb(const std::vector<glm::vec3>& linear, const ToneMapParams& params) {
  std::vector<glm::vec3> out(linear.size());
  for (std::size_t i = 0; i < linear.size(); ++i) out[i] = tone_map(linear[i], params);
  return out;
}

std::vector<glm::vec3> to_srgb(const std::vector<glm::vec3>& linear, double exposure) {
  ToneMapParams params;
  params.exposure = exposure;
  return to_srgb(linear, params);
}

}  // namespace pleat
