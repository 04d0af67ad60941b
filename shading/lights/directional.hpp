// A directional light (docs/method.md §10): irradiance E0 on a surface facing it, travelling along d:
// E = E0 (m.l) where l = -d lies in the cone (m.l > 0).
#pragma once

#include <glm/vec3.hpp>
#include <string>

#include "shading/light_kind.hpp"

namespace pleat {

struct DirectionalLight {
  glm::dvec3 direction{0.0, 0.0, -1.0};  ///< unit; the direction the light travels (towards the cloth)
  glm::dvec3 irradiance{1.0};            ///< on a surface facing the light

  static constexpr LightNames kNames{"dir", "dir:DX,DY,DZ,E=e (D: direction of travel)", "directional",
                                     "dir"};
  static DirectionalLight parse_spec(LightSpec& spec);
  static DirectionalLight parse_json(LightJson& json);
  std::string describe() const;
  static constexpr bool kNeedsPieces = true;
  glm::dvec3 cone_irradiance(ConeLighting& cones, const glm::dvec3& position) const;
  bool sample(const glm::dvec3& x, LightSample& out) const;
};

}  // namespace pleat
