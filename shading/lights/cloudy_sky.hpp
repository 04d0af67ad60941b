// The paper's cloudy-day sky (Stewart 1999 §4; docs/method.md §10): radiance L for directions w with up.w >
// 0, none below: E = L proj(cone ∩ hemisphere(up), m). A piece wholly above (below) the up horizon adds its
// Lambert integral (nothing) without clipping; only pieces that straddle it are clipped.
#pragma once

#include <glm/vec3.hpp>
#include <string>

#include "shading/light_kind.hpp"

namespace pleat {

struct HemisphereSkyLight {
  glm::dvec3 radiance{1.0};
  glm::dvec3 up{0.0, 0.0, 1.0};  ///< unit

  static constexpr LightNames kNames{"cloudy", "cloudy:L,up=X,Y,Z", "cloudy", "hemisphere"};
  static HemisphereSkyLight parse_spec(LightSpec& spec);
  static HemisphereSkyLight parse_json(LightJson& json);
  std::string describe() const;
  static constexpr bool kNeedsPieces = true;
  glm::dvec3 cone_irradiance(ConeLighting& cones, const glm::dvec3& position) const;
  glm::dvec3 escaped_radiance(const glm::dvec3& w) const;
};

}  // namespace pleat
