#include "shading/lights/cloudy_sky.hpp"

#include <glm/geometric.hpp>
#include <stdexcept>

#include "shading/cone_lighting.hpp"
#include "shading/internal/light_parsing.hpp"

namespace pleat {

namespace {

/// A piece in the hemisphere of axis holds the whole open hemisphere of -up (or of up) only if axis = -up
/// (axis = up): below this margin of axis.up from -1 (1) the shortcuts are not taken.
constexpr double kOppositeMargin = 1e-9;

}  // namespace

HemisphereSkyLight HemisphereSkyLight::parse_spec(LightSpec& spec) {
  const auto p = spec.positional_numbers();
  if (p.size() > 1) throw std::invalid_argument("cloudy takes one radiance value");
  HemisphereSkyLight light;
  light.radiance = (p.empty() ? spec.scalar("L", 1.0) : p[0]) * spec.tint();
  light.up = unit_or_throw(spec.vec3("up", {0, 0, 1}), "up");
  check_non_negative(light.radiance, "radiance");
  spec.check_all_used();
  return light;
}

HemisphereSkyLight HemisphereSkyLight::parse_json(LightJson& json) {
  HemisphereSkyLight light;
  light.radiance = json.colour("radiance");
  light.up = json.unit("up", {0, 0, 1});
  return light;
}

std::string HemisphereSkyLight::describe() const {
  return "cloudy L=" + format_colour(radiance) + " up=" + format_vec(up);
}

glm::dvec3 HemisphereSkyLight::cone_irradiance(ConeLighting& cones, const glm::dvec3&) const {
  const auto pieces = cones.pieces();
  const double facing = glm::dot(cones.axis(), up);
  const bool may_take_above = facing > -1.0 + kOppositeMargin;
  const bool may_take_below = facing < 1.0 - kOppositeMargin;
  double sum = 0.0;
  bool whole_cone = true;  // every piece entirely above the up horizon
  SphericalPolygonList& clipped = cones.scratch(0);
  clipped.clear();
  for (const SphericalPolygon* piece : pieces) {
    bool above = true, below = true;
    for (const glm::dvec3& v : *piece) {
      const double d = glm::dot(up, v);
      above = above && d >= 0.0;
      below = below && d <= 0.0;
    }
    if (above && may_take_above) continue;  // added below, all at once when possible
    whole_cone = false;
    if (below && may_take_below) continue;
    cones.clipper().clip(*piece, up, clipped);
  }
  if (whole_cone && cones.all_in_place()) {
    sum = cones.projected();  // the cone's own Lambert integral (measures or the pieces' sum)
  } else {
    for (std::size_t k = 0; k < pieces.size(); ++k) {
      bool above = true;
      for (const glm::dvec3& v : *pieces[k]) above = above && glm::dot(up, v) >= 0.0;
      if (above && may_take_above) sum += cones.piece_projection(k);
    }
    sum += total_projection(clipped, cones.axis());
  }
  return sum * radiance;
}

glm::dvec3 HemisphereSkyLight::escaped_radiance(const glm::dvec3& w) const {
  return glm::dot(w, up) > 0.0 ? radiance : glm::dvec3(0.0);
}

}  // namespace pleat
