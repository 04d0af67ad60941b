// An equirectangular environment map (shading/environment_map.hpp; docs/method.md §10):
// E = scale sum_k integral over piece_k of L(w) (m.w) dw. Cost: O(map columns spanned by the cone's edges).
#pragma once

#include <filesystem>
#include <glm/vec3.hpp>
#include <string>

#include "shading/environment_map.hpp"
#include "shading/light_kind.hpp"

namespace pleat {

struct EnvironmentLight {
  EnvironmentMap map;
  double scale = 1.0;
  std::filesystem::path file;

  static constexpr LightNames kNames{"env", "env:FILE.hdr|.png[,scale=s,up=X,Y,Z,rotate=DEG,maxres=W]", "env",
                                     "environment"};
  static EnvironmentLight parse_spec(LightSpec& spec);
  static EnvironmentLight parse_json(LightJson& json);
  std::string describe() const;
  static constexpr bool kNeedsPieces = true;
  glm::dvec3 cone_irradiance(ConeLighting& cones, const glm::dvec3& position) const;
  glm::dvec3 escaped_radiance(const glm::dvec3& w) const;
};

}  // namespace pleat
