#include "shading/lights/environment.hpp"

#include <glm/common.hpp>
#include <sstream>
#include <stdexcept>

#include "shading/cone_lighting.hpp"
#include "shading/internal/light_parsing.hpp"

namespace pleat {

EnvironmentLight EnvironmentLight::parse_spec(LightSpec& spec) {
  std::string file;
  for (const auto& t : spec.positional()) {
    if (!file.empty()) file += ',';
    file += t;
  }
  if (file.empty()) throw std::invalid_argument("env expects a file name");
  EnvironmentOrientation orientation;
  orientation.up = spec.vec3("up", orientation.up);
  orientation.rotation_degrees = spec.scalar("rotate", 0.0);
  const double max_width = spec.scalar("maxres", kDefaultEnvironmentWidth);
  EnvironmentLight light;
  light.scale = spec.scalar("scale", 1.0);
  if (!(light.scale >= 0.0)) throw std::invalid_argument("scale must be non-negative");
  if (spec.has("rgb")) throw std::invalid_argument("rgb is not supported for env lights (use scale)");
  spec.check_all_used();
  unit_or_throw(orientation.up, "up");
  light.file = resolve(file, spec.base_dir());
  light.map = EnvironmentMap::load(light.file, orientation, static_cast<int>(max_width));
  return light;
}

EnvironmentLight EnvironmentLight::parse_json(LightJson& json) {
  EnvironmentLight light;
  const nlohmann::json* f = json.get("file");
  if (!f || !f->is_string()) json.fail("file", "expected a file name");
  EnvironmentOrientation orientation;
  orientation.up = json.unit("up", orientation.up);
  if (const nlohmann::json* r = json.get("rotate")) orientation.rotation_degrees = json.number(*r, "rotate");
  int max_width = kDefaultEnvironmentWidth;
  if (const nlohmann::json* m = json.get("max_width"))
    max_width = static_cast<int>(json.number(*m, "max_width"));
  if (const nlohmann::json* s = json.get("scale")) light.scale = json.number(*s, "scale");
  if (!(light.scale >= 0.0)) json.fail("scale", "must be non-negative");
  if (json.contains("color")) json.fail("color", "not supported for env lights (use scale)");
  light.file = resolve(f->get<std::string>(), json.base_dir());
  light.map = EnvironmentMap::load(light.file, orientation, max_width);
  return light;
}

std::string EnvironmentLight::describe() const {
  std::ostringstream s;
  s << "environment " << file.string() << " (" << map.width() << 'x' << map.height() << ") scale=" << scale;
  return s.str();
}

glm::dvec3 EnvironmentLight::cone_irradiance(ConeLighting& cones, const glm::dvec3&) const {
  glm::dvec3 sum(0.0);
  for (const SphericalPolygon* piece : cones.pieces()) sum += map.integrate_cosine(*piece, cones.axis());
  return scale * glm::max(sum, glm::dvec3(0.0));
}

glm::dvec3 EnvironmentLight::escaped_radiance(const glm::dvec3& w) const { return scale * map.radiance(w); }

}  // namespace pleat
