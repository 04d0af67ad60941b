#include "shading/lights/directional.hpp"

#include <glm/geometric.hpp>
#include <limits>
#include <stdexcept>

#include "shading/cone_lighting.hpp"
#include "shading/internal/light_parsing.hpp"

namespace pleat {

DirectionalLight DirectionalLight::parse_spec(LightSpec& spec) {
  const auto p = spec.positional_numbers();
  if (p.size() != 3) throw std::invalid_argument("dir expects a direction dx,dy,dz");
  DirectionalLight light;
  light.direction = unit_or_throw({p[0], p[1], p[2]}, "direction");
  light.irradiance = spec.scalar("E", 1.0) * spec.tint();
  check_non_negative(light.irradiance, "irradiance");
  spec.check_all_used();
  return light;
}

DirectionalLight DirectionalLight::parse_json(LightJson& json) {
  DirectionalLight light;
  if (!json.contains("direction")) json.fail("direction", "missing");
  light.direction = json.unit("direction", {0, 0, -1});
  light.irradiance = json.colour("irradiance");
  return light;
}

std::string DirectionalLight::describe() const {
  return "directional towards " + format_vec(direction) + " E=" + format_colour(irradiance);
}

glm::dvec3 DirectionalLight::cone_irradiance(ConeLighting& cones, const glm::dvec3&) const {
  const glm::dvec3 l = -direction;
  const double cosine = glm::dot(cones.axis(), l);
  if (!(cosine > 0.0) || !cones.sees(l)) return glm::dvec3(0.0);
  return cosine * irradiance;
}

bool DirectionalLight::sample(const glm::dvec3&, LightSample& out) const {
  out = {-direction, std::numeric_limits<double>::infinity(), irradiance, 1.0};
  return true;
}

}  // namespace pleat
