#include "shading/lights/uniform_sky.hpp"

#include <stdexcept>

#include "shading/cone_lighting.hpp"
#include "shading/internal/light_parsing.hpp"

namespace pleat {

UniformSkyLight UniformSkyLight::parse_spec(LightSpec& spec) {
  const auto p = spec.positional_numbers();
  if (p.size() > 1) throw std::invalid_argument("sky takes one radiance value");
  UniformSkyLight light;
  light.radiance = (p.empty() ? spec.scalar("L", 1.0) : p[0]) * spec.tint();
  check_non_negative(light.radiance, "radiance");
  spec.check_all_used();
  return light;
}

UniformSkyLight UniformSkyLight::parse_json(LightJson& json) { return {json.colour("radiance")}; }

std::string UniformSkyLight::describe() const { return "sky L=" + format_colour(radiance); }

glm::dvec3 UniformSkyLight::cone_irradiance(ConeLighting& cones, const glm::dvec3&) const {
  return cones.projected() * radiance;
}

glm::dvec3 UniformSkyLight::escaped_radiance(const glm::dvec3&) const { return radiance; }

}  // namespace pleat
