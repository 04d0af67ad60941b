// A planar convex polygon of uniform radiance L (docs/method.md §10): E = L sum proj(piece_k ∩ light, m), the
// light as seen from x a convex spherical polygon that clips each piece by the great circles of its edges in
// turn (Sutherland–Hodgman is exact for a convex clipper). Cost: O(cone edges x light edges).
#pragma once

#include <glm/vec3.hpp>
#include <string>
#include <vector>

#include "shading/light_kind.hpp"

namespace pleat {

struct AreaLight {
  std::vector<glm::dvec3> polygon;
  glm::dvec3 radiance{1.0};
  bool two_sided = true;   ///< false: emits only towards the right-hand normal of the vertex order
  glm::dvec3 normal{0.0};  ///< unit right-hand normal (set by validation)

  static constexpr LightNames kNames{"area", "area:X,Y,Z;X,Y,Z;X,Y,Z[;...],L=l[,sided=1] (planar convex)",
                                     "area"};
  static AreaLight parse_spec(LightSpec& spec);
  static AreaLight parse_json(LightJson& json);
  std::string describe() const;
  static constexpr bool kNeedsPieces = true;
  glm::dvec3 cone_irradiance(ConeLighting& cones, const glm::dvec3& position) const;
  bool hit(const glm::dvec3& o, const glm::dvec3& w, double& tmax, glm::dvec3& radiance) const;
};

/// Checks and completes an area light: >= 3 finite vertices, planar (within 1e-6 of the size), convex and
/// not degenerate; sets `normal`. Throws std::invalid_argument saying what is wrong.
void validate_area_light(AreaLight& light);

}  // namespace pleat
