// Lights: spec-string and JSON parsing by the kinds of the type list Light (see the header for the grammar).
#include "shading/lights.hpp"

#include <cctype>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <stdexcept>

#include "shading/internal/light_parsing.hpp"
#include "support/input_error.hpp"

namespace pleat {

namespace {

using Json = nlohmann::json;

struct JsonContext {
  std::string source;
  std::filesystem::path base_dir;
  [[noreturn]] void fail(const std::string& place, const std::string& why) const {
    throw InputError(source, place, why);
  }
};

/// f(std::type_identity<Kind>) for every kind of the type list, in its order.
template <class F>
void for_each_kind(F&& f) {
  [&]<std::size_t... K>(std::index_sequence<K...>) {
    (..., f(std::type_identity<std::variant_alternative_t<K, Light>>()));
  }
  (std::make_index_sequence<std::variant_size_v<Light>>());
}

/// "a, b, c" of every kind's spec name (json: JSON name).
std::string kind_names(bool json) {
  std::string names;
  for_each_kind([&](auto kind) {
    using Kind = typename decltype(kind)::type;
    names += (names.empty() ? "" : ", ") + std::string(json ? Kind::kNames.json : Kind::kNames.spec);
  });
  return names;
}

void add_spec_or_throw(Lighting& lighting, std::string_view spec, const std::filesystem::path& base_dir) {
  const std::size_t colon = spec.find(':');
  const std::string type = trim(spec.substr(0, colon));
  LightSpec args(colon == std::string_view::npos ? std::string_view() : spec.substr(colon + 1), base_dir);
  bool found = false;
  for_each_kind([&](auto kind) {
    using Kind = typename decltype(kind)::type;
    if (found || type != Kind::kNames.spec) return;
    found = true;
    lighting.lights.push_back(Kind::parse_spec(args));
  });
  if (found) return;
  args.positional();  // a malformed argument list is reported first
  throw std::invalid_argument("unknown light type '" + type + "' (" + kind_names(false) + ")");
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
  LightJson json(j, ctx.source, place, ctx.base_dir);
  bool found = false;
  for_each_kind([&](auto kind) {
    using Kind = typename decltype(kind)::type;
    if (found ||
        (type != Kind::kNames.json && (Kind::kNames.json_alias.empty() || type != Kind::kNames.json_alias)))
      return;
    found = true;
    lighting.lights.push_back(Kind::parse_json(json));
  });
  if (!found) ctx.fail(place + ".type", "unknown light type '" + type + "' (" + kind_names(true) + ")");
  json.check_all_used(type);
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

std::string light_spec_syntax() {
  std::string text;
  for_each_kind([&](auto kind) {
    using Kind = typename decltype(kind)::type;
    text += (text.empty() ? "" : " | ") + std::string(Kind::kNames.syntax);
  });
  return text;
}

std::string Lighting::describe() const {
  std::string text;
  for_each([&](const auto& light) { text += light.describe() + "\n"; });
  return text;
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
