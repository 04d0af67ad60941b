// Lights for shading from visibility cones (docs/method.md §10), and how users write them: command-line specs
// and a small JSON lighting file. Several lights of any kinds combine in one Lighting; all quantities are
// linear RGB. Parsing validates once, where input enters, and throws InputError naming the spec or the JSON
// path.
//
// Spec strings (--light), TYPE:ARGS with comma-separated positional numbers, then key=value items (a key's
// value may continue over following numbers, e.g. up=0,0,1); `rgb=r,g,b` tints any light:
//   sky:L                          uniform sky of radiance L over the whole sphere
//   cloudy:L,up=X,Y,Z              the paper's cloudy-day sky: radiance L above the up axis, 0 below
//   dir:DX,DY,DZ,E=e               directional light travelling along D (towards the cloth), irradiance e
//   point:X,Y,Z,I=i                point light of intensity i at X,Y,Z (irradiance i cos / d^2)
//   area:X,Y,Z;X,Y,Z;X,Y,Z...,L=l  planar convex polygon of radiance l (two-sided; sided=1: only towards
//                                  the right-hand normal of the vertex order)
//   env:FILE,scale=s,up=X,Y,Z,rotate=DEG,maxres=W   equirectangular .hdr/.png (see environment_map.hpp)
// JSON lighting file: {"lights": [SPEC-STRING or OBJECT, ...]} (or a bare array), objects like
//   {"type": "point", "position": [0,2,1], "intensity": 10, "color": [1,0.9,0.8]}
//   types/fields: sky{radiance}, cloudy{radiance, up}, directional{direction, irradiance},
//   point{position, intensity}, area{vertices, radiance, two_sided}, env{file, scale, up, rotate, max_width};
//   scalars may be [r,g,b]. Relighting file: {"setups": [{"name": N, "lights": [...]}, ...]}.
// Relative env-map paths are resolved against the JSON file's directory (or the working directory).
#pragma once

#include <filesystem>
#include <glm/vec3.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "shading/environment_map.hpp"

namespace pleat {

struct UniformSkyLight {
  glm::dvec3 radiance{1.0};
};

/// Radiance for directions w with up.w > 0, none below (Stewart 1999 §4's "cloudy day").
struct HemisphereSkyLight {
  glm::dvec3 radiance{1.0};
  glm::dvec3 up{0.0, 0.0, 1.0};  ///< unit
};

struct DirectionalLight {
  glm::dvec3 direction{0.0, 0.0, -1.0};  ///< unit; the direction the light travels (towards the cloth)
  glm::dvec3 irradiance{1.0};            ///< on a surface facing the light
};

struct PointLight {
  glm::dvec3 position{0.0};
  glm::dvec3 intensity{1.0};  ///< irradiance at distance d, facing: intensity / d^2
};

/// A planar convex polygon of uniform radiance.
struct AreaLight {
  std::vector<glm::dvec3> polygon;
  glm::dvec3 radiance{1.0};
  bool two_sided = true;   ///< false: emits only towards the right-hand normal of the vertex order
  glm::dvec3 normal{0.0};  ///< unit right-hand normal (set by validation)
};

struct EnvironmentLight {
  EnvironmentMap map;
  double scale = 1.0;
  std::filesystem::path file;
};

/// A lighting setup: any number of lights of each kind.
struct Lighting {
  std::string name;
  std::vector<UniformSkyLight> skies;
  std::vector<HemisphereSkyLight> cloudy_skies;
  std::vector<DirectionalLight> directional;
  std::vector<PointLight> points;
  std::vector<AreaLight> areas;
  std::vector<EnvironmentLight> environments;

  std::size_t size() const {
    return skies.size() + cloudy_skies.size() + directional.size() + points.size() + areas.size() +
           environments.size();
  }
  bool empty() const { return size() == 0; }
  /// One line per light, for logs and --help-like summaries.
  std::string describe() const;
};

/// Parses one spec string (grammar above) into `lighting`. Throws InputError("--light", spec, why).
void add_light_spec(Lighting& lighting, std::string_view spec, const std::filesystem::path& base_dir = {});

/// Parses a lighting JSON document (text); `source` names it in errors.
Lighting parse_lighting_json(const std::string& text, const std::string& source,
                             const std::filesystem::path& base_dir = {});
/// Reads and parses a lighting JSON file.
Lighting load_lighting(const std::filesystem::path& path);

/// Parses a relighting JSON document: several named setups. Names must be unique, non-empty, and use only
/// letters, digits, '-', '_' and '.' (they become parts of file names).
std::vector<Lighting> parse_lighting_setups_json(const std::string& text, const std::string& source,
                                                 const std::filesystem::path& base_dir = {});
std::vector<Lighting> load_lighting_setups(const std::filesystem::path& path);

/// Checks and completes an area light: >= 3 finite vertices, planar (within 1e-6 of the size), convex and
/// not degenerate; sets `normal`. Throws std::invalid_argument saying what is wrong.
void validate_area_light(AreaLight& light);

}  // namespace pleat
