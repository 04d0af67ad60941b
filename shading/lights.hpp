// Lights for shading from visibility cones (docs/method.md §10), and how users write them: command-line specs
// and a small JSON lighting file. Several lights of any kinds combine in one Lighting; all quantities are
// linear RGB. The kinds are one type list (Light): each kind is one file pair in shading/lights/ and one row
// below (shading/light_kind.hpp says what a kind provides). Parsing validates once, where input enters, and
// throws InputError naming the spec or the JSON path.
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

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "shading/lights/area.hpp"
#include "shading/lights/cloudy_sky.hpp"
#include "shading/lights/directional.hpp"
#include "shading/lights/environment.hpp"
#include "shading/lights/point.hpp"
#include "shading/lights/uniform_sky.hpp"

namespace pleat {

/// Every kind of light, one row each; the order is the order lights are summed in (kind by kind, each kind
/// in the order given), and the order their names are listed in.
using Light = std::variant<UniformSkyLight,     //
                           HemisphereSkyLight,  //
                           DirectionalLight,    //
                           PointLight,          //
                           AreaLight,           //
                           EnvironmentLight>;

/// A lighting setup: any number of lights of any kinds.
struct Lighting {
  std::string name;
  std::vector<Light> lights;

  std::size_t size() const { return lights.size(); }
  bool empty() const { return lights.empty(); }
  /// The lights of one kind, in the order given.
  template <class Kind>
  std::vector<const Kind*> all() const {
    std::vector<const Kind*> out;
    for (const Light& light : lights)
      if (const Kind* l = std::get_if<Kind>(&light)) out.push_back(l);
    return out;
  }
  /// f(light) for every light, kind by kind in the type list's order, each kind in the order given (the
  /// order lights are summed in everywhere, so that sums do not depend on the order they were given in).
  template <class F>
  void for_each(F&& f) const {
    for_each_kind(f, std::make_index_sequence<std::variant_size_v<Light>>());
  }
  /// One line per light, for logs and --help-like summaries.
  std::string describe() const;
  /// The files the lights read (the kinds with a `file`), each with what names it: "--light NAME:".
  std::vector<std::pair<std::string, std::filesystem::path>> files() const {
    std::vector<std::pair<std::string, std::filesystem::path>> out;
    for_each([&](const auto& light) {
      if constexpr (requires { light.file; })
        out.emplace_back("--light " + std::string(light.kNames.spec) + ":", light.file);
    });
    return out;
  }

 private:
  template <class F, std::size_t... K>
  void for_each_kind(F& f, std::index_sequence<K...>) const {
    (..., [&] {
      for (const Light& light : lights)
        if (light.index() == K) f(std::get<K>(light));
    }());
  }
};

/// The spec syntax of every kind, "a | b | ...", for --help.
std::string light_spec_syntax();

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

}  // namespace pleat
