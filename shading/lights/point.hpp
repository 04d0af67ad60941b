// A point light (docs/method.md §10): intensity I at p: E = I (m.l) / |p - x|^2 where l = (p - x)/|p - x|
// lies in the cone (a light nearer than a fold in its direction is still taken as blocked by it).
#pragma once

#include <glm/vec3.hpp>
#include <string>

#include "shading/light_kind.hpp"

namespace pleat {

struct PointLight {
  glm::dvec3 position{0.0};
  glm::dvec3 intensity{1.0};  ///< irradiance at distance d, facing: intensity / d^2

  static constexpr LightNames kNames{"point", "point:X,Y,Z,I=i", "point"};
  static PointLight parse_spec(LightSpec& spec);
  static PointLight parse_json(LightJson& json);
  std::string describe() const;
  static constexpr bool kNeedsPieces = true;
  glm::dvec3 cone_irradiance(ConeLighting& cones, const glm::dvec3& position) const;
  bool sample(const glm::dvec3& x, LightSample& out) const;
};

}  // namespace pleat
