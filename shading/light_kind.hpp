// What every kind of light provides (docs/method.md §10), pbrt-v4's light interface in pleat's terms. A kind
// is one file pair in shading/lights/ and one row of the type list Light (shading/lights.hpp); the spec and
// JSON parsers, the lighting's description, the cone shading (ConeLighting) and the path tracer
// (path_trace.hpp) all go through these members, so nothing else names a kind. A kind `K` has:
//   static constexpr LightNames kNames;                      its names in specs and JSON, and its spec syntax
//   static K parse_spec(LightSpec& spec);                   from a --light spec's arguments (after "NAME:")
//   static K parse_json(LightJson& json);                   from a JSON object {"type": NAME, ...}
//   std::string describe() const;                           one line (no newline), for logs
//   static constexpr bool kNeedsPieces;                     whether cone_irradiance reads the cone's pieces
//   glm::dvec3 cone_irradiance(ConeLighting&, const glm::dvec3& position) const;   through the set cone
// and, for the path tracer, any of
//   glm::dvec3 escaped_radiance(const glm::dvec3& w) const;  radiance along w from infinity (skies, maps)
//   bool hit(const glm::dvec3& o, const glm::dvec3& w, double& tmax, glm::dvec3& radiance) const;
//                                                            crossed by the ray before tmax (area lights)
//   bool sample(const glm::dvec3& x, LightSample& out) const;  a delta light seen from x (shadow ray)
// Parsers throw std::invalid_argument (specs; the caller names the spec) or InputError through LightJson.
#pragma once

#include <glm/vec3.hpp>
#include <string_view>

namespace pleat {

class ConeLighting;
class LightSpec;
class LightJson;

/// A kind's names: in --light specs, its spec syntax (for --help), and in JSON (and another JSON name, or
/// "").
struct LightNames {
  std::string_view spec;
  std::string_view syntax;
  std::string_view json;
  std::string_view json_alias = {};
};

/// A delta light seen from a point: the unit direction towards it, how far (a shadow ray's length), and
/// the irradiance it gives a surface facing it: value / divisor.
struct LightSample {
  glm::dvec3 direction{0.0};
  double distance = 0.0;
  glm::dvec3 value{0.0};
  double divisor = 1.0;
};

}  // namespace pleat
