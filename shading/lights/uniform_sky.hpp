// A uniform sky: radiance L from every direction (docs/method.md §10): E = L proj(cone, m), the cone's
// Lambert integral, read from its measures without looking at its pieces.
#pragma once

#include <glm/vec3.hpp>
#include <string>

#include "shading/light_kind.hpp"

namespace pleat {

struct UniformSkyLight {
  glm::dvec3 radiance{1.0};

  static constexpr LightNames kNames{"sky", "sky:L", "sky"};
  static UniformSkyLight parse_spec(LightSpec& spec);
  static UniformSkyLight parse_json(LightJson& json);
  std::string describe() const;
  static constexpr bool kNeedsPieces = false;
  glm::dvec3 cone_irradiance(ConeLighting& cones, const glm::dvec3& position) const;
  glm::dvec3 escaped_radiance(const glm::dvec3& w) const;
};

}  // namespace pleat
