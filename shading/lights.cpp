// Lights: spec-string and JSON parsing, validation (see header for the grammar).
#include "shading/lights.hpp"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <glm/geometric.hpp>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <stdexcept>

#include "static_core/input_error.hpp"

namespace pleat {

namespace {

using Json = nlohmann::json;

std::string trim(std::string_view s) {
  std::size_t b = 0, e = s.size();
  while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
  return std::string(s.substr(b, e - b));
}

std::vector<std::string> split(std::string_view s, char sep) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t pos = s.find(sep, start);
    out.push_back(
        trim(s.substr(start, pos == std::string_view::npos ? std::string_view::npos : pos - start)));
    if (pos == std::string_view::npos) break;
    start = pos + 1;
  }
  return out;
}

bool parse_number(const std::string& text, double& value) {
  if (text.empty()) return false;
  char* end = nullptr;
  value = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() && std::isfinite(value);
}

glm::dvec3 unit_or_throw(const glm::dvec3& v, const char* what) {
  const double len = glm::length(v);
  if (!(len > 0.0) || !std::isfinite(len))
    throw std::invalid_argument(std::string(what) + " must be a non-zero vector");
  return v / len;
}

void check_non_negative(const glm::dvec3& c, const char* what) {
  for (int k = 0; k < 3; ++k)
    if (!(c[k] >= 0.0) || !std::isfinite(c[k]))
      throw std::invalid_argument(std::string(what) + " must be finite and non-negative");
}

std::string format_vec(const glm::dvec3& v) {
  std::ostringstream s;
  s << v.x << ',' << v.y << ',' << v.z;
  return s.str();
}

std::string format_colour(const glm::dvec3& c) {
  std::ostringstream s;
  if (c.x == c.y && c.y == c.z)
    s << c.x;
  else
    s << '(' << c.x << ',' << c.y << ',' << c.z << ')';
  return s.str();
}

// ---- spec strings ---------------------------------------------------------------------------------------

struct SpecArgs {
  std::vector<std::string> positional;  // raw tokens before the first key
  std::map<std::string, std::vector<std::string>> keys;
  std::set<std::string> used;

  bool has(const std::string& k) const { return keys.count(k) != 0; }
  std::vector<double> numbers(const std::string& k) {
    used.insert(k);
    std::vector<double> out;
    for (const std::string& t : keys.at(k)) {
      double v;
      if (!parse_number(t, v)) throw std::invalid_argument("'" + k + "' expects numbers, got '" + t + "'");
      out.push_back(v);
    }
    return out;
  }
  double scalar(const std::string& k, double fallback) {
    if (!has(k)) return fallback;
    const auto v = numbers(k);
    if (v.size() != 1) throw std::invalid_argument("'" + k + "' expects one number");
    return v[0];
  }
  glm::dvec3 vec3(const std::string& k, const glm::dvec3& fallback) {
    if (!has(k)) return fallback;
    const auto v = numbers(k);
    if (v.size() != 3) throw std::invalid_argument("'" + k + "' expects three numbers x,y,z");
    return {v[0], v[1], v[2]};
  }
  std::string text(const std::string& k, const std::string& fallback) {
    if (!has(k)) return fallback;
    used.insert(k);
    std::string s;
    for (const auto& t : keys.at(k)) {
      if (!s.empty()) s += ',';
      s += t;
    }
    return s;
  }
  void check_all_used() const {
    for (const auto& [k, v] : keys)
      if (!used.count(k)) throw std::invalid_argument("unknown key '" + k + "'");
  }
};

SpecArgs split_spec(std::string_view args) {
  SpecArgs out;
  if (trim(args).empty()) return out;
  std::string current_key;
  for (const std::string& token : split(args, ',')) {
    const std::size_t eq = token.find('=');
    if (eq != std::string::npos) {
      current_key = trim(std::string_view(token).substr(0, eq));
      if (current_key.empty()) throw std::invalid_argument("empty key in '" + token + "'");
      if (out.keys.count(current_key)) throw std::invalid_argument("key '" + current_key + "' given twice");
      out.keys[current_key].push_back(trim(std::string_view(token).substr(eq + 1)));
    } else if (current_key.empty()) {
      out.positional.push_back(token);
    } else {
      out.keys[current_key].push_back(token);
    }
  }
  return out;
}

std::vector<double> positional_numbers(const SpecArgs& a) {
  std::vector<double> out;
  for (const std::string& t : a.positional) {
    double v;
    if (!parse_number(t, v)) throw std::invalid_argument("expected a number, got '" + t + "'");
    out.push_back(v);
  }
  return out;
}

glm::dvec3 tint(SpecArgs& a) { return a.vec3("rgb", glm::dvec3(1.0)); }

std::filesystem::path resolve(const std::filesystem::path& file, const std::filesystem::path& base_dir) {
  if (file.is_absolute() || base_dir.empty()) return file;
  return base_dir / file;
}

void add_spec_or_throw(Lighting& lighting, std::string_view spec, const std::filesystem::path& base_dir) {
  const std::size_t colon = spec.find(':');
  const std::string type = trim(spec.substr(0, colon));
  const std::string_view rest = colon == std::string_view::npos ? std::string_view() : spec.substr(colon + 1);

  if (type == "area") {
    // Positional part: vertices separated by ';', coordinates by ','. Keys follow the last vertex.
    SpecArgs a;
    std::string points_text(rest);
    const std::size_t eq = points_text.find('=');
    if (eq != std::string::npos) {
      const std::size_t comma = points_text.rfind(',', eq);
      if (comma == std::string::npos) throw std::invalid_argument("expected vertices before the keys");
      a = split_spec(std::string_view(points_text).substr(comma + 1));
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
    light.radiance = a.scalar("L", 1.0) * tint(a);
    const double sided = a.scalar("sided", 2.0);
    if (sided != 1.0 && sided != 2.0) throw std::invalid_argument("sided must be 1 or 2");
    light.two_sided = sided == 2.0;
    a.check_all_used();
    check_non_negative(light.radiance, "radiance");
    validate_area_light(light);
    lighting.areas.push_back(std::move(light));
    return;
  }

  SpecArgs a = split_spec(rest);
  if (type == "sky") {
    const auto p = positional_numbers(a);
    if (p.size() > 1) throw std::invalid_argument("sky takes one radiance value");
    UniformSkyLight light;
    light.radiance = (p.empty() ? a.scalar("L", 1.0) : p[0]) * tint(a);
    check_non_negative(light.radiance, "radiance");
    a.check_all_used();
    lighting.skies.push_back(light);
  } else if (type == "cloudy") {
    const auto p = positional_numbers(a);
    if (p.size() > 1) throw std::invalid_argument("cloudy takes one radiance value");
    HemisphereSkyLight light;
    light.radiance = (p.empty() ? a.scalar("L", 1.0) : p[0]) * tint(a);
    light.up = unit_or_throw(a.vec3("up", {0, 0, 1}), "up");
    check_non_negative(light.radiance, "radiance");
    a.check_all_used();
    lighting.cloudy_skies.push_back(light);
  } else if (type == "dir") {
    const auto p = positional_numbers(a);
    if (p.size() != 3) throw std::invalid_argument("dir expects a direction dx,dy,dz");
    DirectionalLight light;
    light.direction = unit_or_throw({p[0], p[1], p[2]}, "direction");
    light.irradiance = a.scalar("E", 1.0) * tint(a);
    check_non_negative(light.irradiance, "irradiance");
    a.check_all_used();
    lighting.directional.push_back(light);
  } else if (type == "point") {
    const auto p = positional_numbers(a);
    if (p.size() != 3) throw std::invalid_argument("point expects a position x,y,z");
    PointLight light;
    light.position = {p[0], p[1], p[2]};
    light.intensity = a.scalar("I", 1.0) * tint(a);
    check_non_negative(light.intensity, "intensity");
    a.check_all_used();
    lighting.points.push_back(light);
  } else if (type == "env") {
    std::string file;
    for (const auto& t : a.positional) {
      if (!file.empty()) file += ',';
      file += t;
    }
    if (file.empty()) throw std::invalid_argument("env expects a file name");
    EnvironmentOrientation orientation;
    orientation.up = a.vec3("up", orientation.up);
    orientation.rotation_degrees = a.scalar("rotate", 0.0);
    const double max_width = a.scalar("maxres", kDefaultEnvironmentWidth);
    EnvironmentLight light;
    light.scale = a.scalar("scale", 1.0);
    if (!(light.scale >= 0.0)) throw std::invalid_argument("scale must be non-negative");
    if (a.has("rgb")) throw std::invalid_argument("rgb is not supported for env lights (use scale)");
    a.check_all_used();
    unit_or_throw(orientation.up, "up");
    light.file = resolve(file, base_dir);
    light.map = EnvironmentMap::load(light.file, orientation, static_cast<int>(max_width));
    lighting.environments.push_back(std::move(light));
  } else {
    throw std::invalid_argument("unknown light type '" + type + "' (sky, cloudy, dir, point, area, env)");
  }
}

// ---- JSON ---------------------------------------------------------------------------------------------

struct JsonContext {
  std::string source;
  std::filesystem::path base_dir;
  [[noreturn]] void fail(const std::string& place, const std::string& why) const {
    throw InputError(source, place, why);
  }
};

glm::dvec3 json_colour(const JsonContext& ctx, const Json& j, const std::string& place) {
  if (j.is_number()) return glm::dvec3(j.get<double>());
  if (j.is_array() && j.size() == 3 && j[0].is_number() && j[1].is_number() && j[2].is_number())
    return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
  ctx.fail(place, "expected a number or [r, g, b]");
}

glm::dvec3 json_vec3(const JsonContext& ctx, const Json& j, const std::string& place) {
  if (j.is_array() && j.size() == 3 && j[0].is_number() && j[1].is_number() && j[2].is_number())
    return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
  ctx.fail(place, "expected [x, y, z]");
}

double json_number(const JsonContext& ctx, const Json& j, const std::string& place) {
  if (!j.is_number()) ctx.fail(place, "expected a number");
  return j.get<double>();
}

void add_json_light(Lighting& lighting, const JsonContext& ctx, const Json& j, const std::string& place) {
  if (j.is_string()) {
    try {
      add_spec_or_throw(lighting, j.get<std::string>(), ctx.base_dir);
    } catch (const std::invalid_argument& e) {
      ctx.fail(place, e.what());
    }
    return;
  }
  if (!j.is_object()) ctx.fail(place, "a light is a spec string or an object");
  if (!j.contains("type") || !j["type"].is_string()) ctx.fail(place + ".type", "missing light type");
  const std::string type = j["type"].get<std::string>();
  std::set<std::string> allowed = {"type", "color"};
  auto get = [&](const char* key) -> const Json* {
    allowed.insert(key);
    return j.contains(key) ? &j[key] : nullptr;
  };
  auto colour = [&](const char* key) {
    glm::dvec3 c(1.0);
    if (const Json* v = get(key)) c = json_colour(ctx, *v, place + "." + key);
    if (j.contains("color")) c *= json_colour(ctx, j["color"], place + ".color");
    for (int k = 0; k < 3; ++k)
      if (!(c[k] >= 0.0) || !std::isfinite(c[k]))
        ctx.fail(place + "." + key, "must be finite and non-negative");
    return c;
  };
  auto unit = [&](const char* key, glm::dvec3 fallback) {
    glm::dvec3 v = fallback;
    if (const Json* x = get(key)) v = json_vec3(ctx, *x, place + "." + key);
    const double len = glm::length(v);
    if (!(len > 0.0) || !std::isfinite(len)) ctx.fail(place + "." + key, "must be a non-zero vector");
    return v / len;
  };

  if (type == "sky") {
    lighting.skies.push_back({colour("radiance")});
  } else if (type == "cloudy" || type == "hemisphere") {
    HemisphereSkyLight light;
    light.radiance = colour("radiance");
    light.up = unit("up", {0, 0, 1});
    lighting.cloudy_skies.push_back(light);
  } else if (type == "directional" || type == "dir") {
    DirectionalLight light;
    if (!j.contains("direction")) ctx.fail(place + ".direction", "missing");
    light.direction = unit("direction", {0, 0, -1});
    light.irradiance = colour("irradiance");
    lighting.directional.push_back(light);
  } else if (type == "point") {
    PointLight light;
    const Json* p = get("position");
    if (!p) ctx.fail(place + ".position", "missing");
    light.position = json_vec3(ctx, *p, place + ".position");
    light.intensity = colour("intensity");
    lighting.points.push_back(light);
  } else if (type == "area") {
    AreaLight light;
    const Json* v = get("vertices");
    if (!v || !v->is_array()) ctx.fail(place + ".vertices", "expected an array of [x, y, z]");
    for (std::size_t i = 0; i < v->size(); ++i)
      light.polygon.push_back(json_vec3(ctx, (*v)[i], place + ".vertices[" + std::to_string(i) + "]"));
    light.radiance = colour("radiance");
    if (const Json* s = get("two_sided")) {
      if (!s->is_boolean()) ctx.fail(place + ".two_sided", "expected true or false");
      light.two_sided = s->get<bool>();
    }
    try {
      validate_area_light(light);
    } catch (const std::invalid_argument& e) {
      ctx.fail(place + ".vertices", e.what());
    }
    lighting.areas.push_back(std::move(light));
  } else if (type == "env" || type == "environment") {
    EnvironmentLight light;
    const Json* f = get("file");
    if (!f || !f->is_string()) ctx.fail(place + ".file", "expected a file name");
    EnvironmentOrientation orientation;
    orientation.up = unit("up", orientation.up);
    if (const Json* r = get("rotate")) orientation.rotation_degrees = json_number(ctx, *r, place + ".rotate");
    int max_width = kDefaultEnvironmentWidth;
    if (const Json* m = get("max_width"))
      max_width = static_cast<int>(json_number(ctx, *m, place + ".max_width"));
    if (const Json* s = get("scale")) light.scale = json_number(ctx, *s, place + ".scale");
    if (!(light.scale >= 0.0)) ctx.fail(place + ".scale", "must be non-negative");
    if (j.contains("color")) ctx.fail(place + ".color", "not supported for env lights (use scale)");
    light.file = resolve(f->get<std::string>(), ctx.base_dir);
    light.map = EnvironmentMap::load(light.file, orientation, max_width);
    lighting.environments.push_back(std::move(light));
  } else {
    ctx.fail(place + ".type",
             "unknown light type '" + type + "' (sky, cloudy, directional, point, area, env)");
  }
  for (const auto& [key, value] : j.items())
    if (!allowed.count(key)) ctx.fail(place + "." + key, "unknown field for a " + type + " light");
}

Lighting lighting_from_json(const JsonContext& ctx, const Json& j, const std::string& place) {
  Lighting lighting;
  const Json* lights = &j;
  std::string lights_place = place;
  if (j.is_object()) {
    if (!j.contains("lights")) ctx.fail(place.empty() ? "lights" : place + ".lights", "missing");
    lights = &j["lights"];
    lights_place = place.empty() ? "lights" : place + ".lights";
    if (j.contains("name")) {
      if (!j["name"].is_string()) ctx.fail(place + ".name", "expected a string");
      lighting.name = j["name"].get<std::string>();
    }
  }
  if (!lights->is_array()) ctx.fail(lights_place, "expected an array of lights");
  for (std::size_t i = 0; i < lights->size(); ++i)
    add_json_light(lighting, ctx, (*lights)[i], lights_place + "[" + std::to_string(i) + "]");
  return lighting;
}

Json parse_json_or_throw(const std::string& text, const std::string& source) {
  try {
    return Json::parse(text);
  } catch (const Json::parse_error& e) {
    throw InputError(source, "byte " + std::to_string(e.byte), "invalid JSON");
  }
}

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "", "cannot open");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

bool is_valid_setup_name(const std::string& name) {
  if (name.empty()) return false;
  for (char c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_' && c != '.') return false;
  return name != "." && name != "..";
}

}  // namespace

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

std::string Lighting::describe() const {
  std::ostringstream s;
  for (const auto& l : skies) s << "sky L=" << format_colour(l.radiance) << '\n';
  for (const auto& l : cloudy_skies)
    s << "cloudy L=" << format_colour(l.radiance) << " up=" << format_vec(l.up) << '\n';
  for (const auto& l : directional)
    s << "directional towards " << format_vec(l.direction) << " E=" << format_colour(l.irradiance) << '\n';
  for (const auto& l : points)
    s << "point at " << format_vec(l.position) << " I=" << format_colour(l.intensity) << '\n';
  for (const auto& l : areas)
    s << "area light, " << l.polygon.size() << " vertices, L=" << format_colour(l.radiance)
      << (l.two_sided ? " two-sided" : " one-sided") << '\n';
  for (const auto& l : environments)
    s << "environment " << l.file.string() << " (" << l.map.width() << 'x' << l.map.height()
      << ") scale=" << l.scale << '\n';
  return s.str();
}

void add_light_spec(Lighting& lighting, std::string_view spec, const std::filesystem::path& base_dir) {
  try {
    add_spec_or_throw(lighting, spec, base_dir);
  } catch (const std::invalid_argument& e) {
    throw InputError("--light", "'" + std::string(spec) + "'", e.what());
  }
}

Lighting parse_lighting_json(const std::string& text, const std::string& source,
                             const std::filesystem::path& base_dir) {
  const JsonContext ctx{source, base_dir};
  return lighting_from_json(ctx, parse_json_or_throw(text, source), "");
}

Lighting load_lighting(const std::filesystem::path& path) {
  return parse_lighting_json(read_text(path), path.string(), path.parent_path());
}

std::vector<Lighting> parse_lighting_setups_json(const std::string& text, const std::string& source,
                                                 const std::filesystem::path& base_dir) {
  const JsonContext ctx{source, base_dir};
  const Json j = parse_json_or_throw(text, source);
  if (!j.is_object() || !j.contains("setups")) ctx.fail("setups", "expected {\"setups\": [...]}");
  const Json& setups = j["setups"];
  std::vector<Lighting> out;
  if (setups.is_array()) {
    for (std::size_t i = 0; i < setups.size(); ++i) {
      const std::string place = "setups[" + std::to_string(i) + "]";
      if (!setups[i].is_object()) ctx.fail(place, "expected {\"name\": ..., \"lights\": [...]}");
      out.push_back(lighting_from_json(ctx, setups[i], place));
      if (out.back().name.empty()) ctx.fail(place + ".name", "missing");
    }
  } else if (setups.is_object()) {
    for (const auto& [name, value] : setups.items()) {
      out.push_back(lighting_from_json(ctx, value, "setups." + name));
      out.back().name = name;
    }
  } else {
    ctx.fail("setups", "expected an array of setups");
  }
  if (out.empty()) ctx.fail("setups", "no setups");
  std::set<std::string> names;
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (!is_valid_setup_name(out[i].name))
      ctx.fail("setups[" + std::to_string(i) + "].name", "use letters, digits, '-', '_' and '.' only");
    if (!names.insert(out[i].name).second)
      ctx.fail("setups[" + std::to_string(i) + "].name", "duplicate name");
  }
  return out;
}

std::vector<Lighting> load_lighting_setups(const std::filesystem::path& path) {
  return parse_lighting_setups_json(read_text(path), path.string(), path.parent_path());
}

}  // namespace pleat
