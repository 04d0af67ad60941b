#include "shading/lights/point.hpp"

#include <cmath>
#include <glm/geometric.hpp>
#include <stdexcept>

#include "shading/cone_lighting.hpp"
#include "shading/internal/light_parsing.hpp"

namespace pleat {

PointLight PointLight::parse_spec(LightSpec& spec) {
  const auto p = spec.positional_numbers();
  if (p.size() != 3) throw std::invalid_argument("point expects a position x,y,z");
  PointLight light;
  light.position = {p[0], p[1], p[2]};
  light.intensity = spec.scalar("I", 1.0) * spec.tint();
  check_non_negative(light.intensity, "intensity");
  spec.check_all_used();
  return light;
}

PointLight PointLight::parse_json(LightJson& json) {
  PointLight light;
  const nlohmann::json* p = json.get("position");
  if (!p) json.fail("position", "missing");
  light.position = json.vec3(*p, "position");
  light.intensity = json.colour("intensity");
  return light;
}

std::string PointLight::describe() const {
  return "point at " + format_vec(position) + " I=" + format_colour(intensity);
}

glm::dvec3 PointLight::cone_irradiance(ConeLighting& cones, const glm::dvec3& x) const {
  const glm::dvec3 d = position - x;
  const double d2 = glm::dot(d, d);
  if (!(d2 > 0.0)) return glm::dvec3(0.0);
  const glm::dvec3 l = d / std::sqrt(d2);
  const double cosine = glm::dot(cones.axis(), l);
  if (!(cosine > 0.0) || !cones.sees(l)) return glm::dvec3(0.0);
  return (cosine / d2) * intensity;
}

bool PointLight::sample(const glm::dvec3& x, LightSample& out) const {
  const glm::dvec3 to = position - x;
  const double d2 = glm::dot(to, to);
  if (!(d2 > 0.0)) return false;
  out = {to / std::sqrt(d2), std::sqrt(d2), intensity, d2};
  return true;
}

}  // namespace pleat
