#include "shading/lights/area.hpp"

#include <cmath>
#include <glm/geometric.hpp>
#include <stdexcept>

#include "shading/cone_lighting.hpp"
#include "shading/internal/light_parsing.hpp"

namespace pleat {

AreaLight AreaLight::parse_spec(LightSpec& spec) {
  // Positional part: vertices separated by ';', coordinates by ','. Keys follow the last vertex.
  std::string points_text(spec.args());
  spec.split_keys({});
  const std::size_t eq = points_text.find('=');
  if (eq != std::string::npos) {
    const std::size_t comma = points_text.rfind(',', eq);
    if (comma == std::string::npos) throw std::invalid_argument("expected vertices before the keys");
    spec.split_keys(std::string_view(points_text).substr(comma + 1));
    points_text = points_text.substr(0, comma);
  }
  AreaLight light;
  for (const std::string& vertex : split(points_text, ';')) {
    const auto coords = split(vertex, ',');
    double x, y, z;
    if (coords.size() != 3 || !parse_number(coords[0], x) || !parse_number(coords[1], y) ||
        !parse_number(coords[2], z))
      throw std::invalid_argument("area light vertex '" + vertex + "' is not x,y,z");
    light.polygon.push_back({x, y, z});
  }
  light.radiance = spec.scalar("L", 1.0) * spec.tint();
  const double sided = spec.scalar("sided", 2.0);
  if (sided != 1.0 && sided != 2.0) throw std::invalid_argument("sided must be 1 or 2");
  light.two_sided = sided == 2.0;
  spec.check_all_used();
  check_non_negative(light.radiance, "radiance");
  validate_area_light(light);
  return light;
}

AreaLight AreaLight::parse_json(LightJson& json) {
  AreaLight light;
  const nlohmann::json* v = json.get("vertices");
  if (!v || !v->is_array()) json.fail("vertices", "expected an array of [x, y, z]");
  for (std::size_t i = 0; i < v->size(); ++i)
    light.polygon.push_back(json.vec3((*v)[i], "vertices[" + std::to_string(i) + "]"));
  light.radiance = json.colour("radiance");
  if (const nlohmann::json* s = json.get("two_sided")) {
    if (!s->is_boolean()) json.fail("two_sided", "expected true or false");
    light.two_sided = s->get<bool>();
  }
  try {
    validate_area_light(light);
  } catch (const std::invalid_argument& e) {
    json.fail("vertices", e.what());
  }
  return light;
}

std::string AreaLight::describe() const {
  return "area light, " + std::to_string(polygon.size()) + " vertices, L=" + format_colour(radiance) +
         (two_sided ? " two-sided" : " one-sided");
}

glm::dvec3 AreaLight::cone_irradiance(ConeLighting& cones, const glm::dvec3& position) const {
  const std::size_t count = polygon.size();
  if (count < 3 || cones.pieces().empty()) return glm::dvec3(0.0);
  const double facing = glm::dot(position - polygon[0], normal);
  if (facing == 0.0 || (!two_sided && facing < 0.0)) return glm::dvec3(0.0);
  // The light as seen from x, counter-clockwise about its interior (seen from outside the unit sphere):
  // the vertex order is right-handed about the light's normal, which appears clockwise from its front.
  SphericalPolygon& seen = cones.scratch_polygon();
  seen.clear();
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t j = facing > 0.0 ? count - 1 - i : i;
    const glm::dvec3 d = polygon[j] - position;
    seen.push_back(d / glm::length(d));
  }
  // Clip every piece by the half-spaces of the light's edges in turn.
  const SphericalPolygonList* source = nullptr;  // null: the pieces themselves
  for (std::size_t i = 0; i < count; ++i) {
    const glm::dvec3 g = glm::cross(seen[i], seen[(i + 1) % count]);
    const double len = glm::length(g);
    if (!(len > 0.0)) continue;  // a vanishing edge (the light is a point from here)
    SphericalPolygonList& target = source == &cones.scratch(0) ? cones.scratch(1) : cones.scratch(0);
    target.clear();
    if (source == nullptr) {
      for (const SphericalPolygon* piece : cones.pieces()) cones.clipper().clip(*piece, g / len, target);
    } else {
      for (std::size_t k = 0; k < source->size; ++k) cones.clipper().clip((*source)[k], g / len, target);
    }
    source = &target;
    if (target.size == 0) return glm::dvec3(0.0);
  }
  if (source == nullptr) return glm::dvec3(0.0);  // every edge vanished: no solid angle
  return total_projection(*source, cones.axis()) * radiance;
}

bool AreaLight::hit(const glm::dvec3& o, const glm::dvec3& w, double& tmax, glm::dvec3& out) const {
  const double denom = glm::dot(w, normal);
  if (denom == 0.0 || (!two_sided && denom > 0.0)) return false;  // parallel, or seen from behind
  const double t = glm::dot(polygon[0] - o, normal) / denom;
  if (!(t > 0.0 && t < tmax)) return false;
  const glm::dvec3 x = o + t * w;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const glm::dvec3& p = polygon[i];
    const glm::dvec3& q = polygon[(i + 1) % polygon.size()];
    if (!(glm::dot(glm::cross(q - p, x - p), normal) >= 0.0)) return false;
  }
  tmax = t;
  out = radiance;
  return true;
}

void validate_area_light(AreaLight& light) {
  const auto& p = light.polygon;
  if (p.size() < 3) throw std::invalid_argument("an area light needs at least 3 vertices");
  for (const auto& v : p)
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
      throw std::invalid_argument("area light vertices must be finite");
  // Newell normal and size.
  glm::dvec3 normal(0.0), centre(0.0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    normal += glm::cross(p[i], p[(i + 1) % p.size()]);
    centre += p[i];
  }
  centre /= double(p.size());
  double size = 0.0;
  for (const auto& v : p) size = std::max(size, glm::length(v - centre));
  const double len = glm::length(normal);
  if (!(len > 1e-12 * size * size) || size == 0.0)
    throw std::invalid_argument("area light polygon is degenerate");
  normal /= len;
  for (const auto& v : p)
    if (std::abs(glm::dot(v - centre, normal)) > 1e-6 * size)
      throw std::invalid_argument("area light polygon is not planar");
  // Convex: every turn is to the left about the normal, and the turns add up to one full turn (a
  // self-crossing star turns left everywhere too, but twice around).
  double turning = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const glm::dvec3 e0 = p[(i + 1) % p.size()] - p[i];
    const glm::dvec3 e1 = p[(i + 2) % p.size()] - p[(i + 1) % p.size()];
    const double turn_sin = glm::dot(glm::cross(e0, e1), normal);
    if (turn_sin < 0.0 || glm::length(e0) == 0.0)
      throw std::invalid_argument("area light polygon is not convex");
    turning += std::atan2(turn_sin, glm::dot(e0, e1));
  }
  if (std::abs(turning - 2.0 * 3.14159265358979323846) > 1e-6)
    throw std::invalid_argument("area light polygon is not convex (it winds more than once)");
  light.normal = normal;
}

}  // namespace pleat
