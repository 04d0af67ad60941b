// The parsing helpers the kinds of light share (shading/light_kind.hpp): a --light spec's arguments and a
// JSON light object, each checking its values where they enter. Internal to shading/.
#pragma once

#include <filesystem>
#include <glm/vec3.hpp>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace pleat {

std::string trim(std::string_view s);
/// `s` split at every `sep`, each part trimmed.
std::vector<std::string> split(std::string_view s, char sep);
/// A finite number filling all of `text`.
bool parse_number(const std::string& text, double& value);
/// v / |v|; std::invalid_argument naming `what` for a zero or non-finite vector.
glm::dvec3 unit_or_throw(const glm::dvec3& v, const char* what);
/// std::invalid_argument naming `what` unless every component is finite and >= 0.
void check_non_negative(const glm::dvec3& c, const char* what);
std::string format_vec(const glm::dvec3& v);
std::string format_colour(const glm::dvec3& c);
/// `file` against `base_dir` when relative.
std::filesystem::path resolve(const std::filesystem::path& file, const std::filesystem::path& base_dir);

/// A spec's arguments: comma-separated positional tokens, then key=value items (a key's value may continue
/// over the following tokens). Every key must be read (check_all_used). Errors: std::invalid_argument.
class LightSpec {
 public:
  /// `args`: what follows "NAME:"; `base_dir`: where relative files are.
  LightSpec(std::string_view args, std::filesystem::path base_dir);
  /// The text of the arguments as given (kinds with a syntax of their own: the area light's vertices).
  std::string_view args() const { return m_args; }
  const std::filesystem::path& base_dir() const { return m_base_dir; }
  /// Splits `args` instead of args() into positional tokens and keys (kinds with a syntax of their own);
  /// otherwise args() are split when first read.
  void split_keys(std::string_view args);

  const std::vector<std::string>& positional();
  std::vector<double> positional_numbers();
  bool has(const std::string& k);
  std::vector<double> numbers(const std::string& k);
  double scalar(const std::string& k, double fallback);
  glm::dvec3 vec3(const std::string& k, const glm::dvec3& fallback);
  /// rgb=R,G,B (default white).
  glm::dvec3 tint() { return vec3("rgb", glm::dvec3(1.0)); }
  void check_all_used();

 private:
  void split_once();

  std::string_view m_args;
  bool m_split = false;
  std::filesystem::path m_base_dir;
  std::vector<std::string> m_positional;
  std::map<std::string, std::vector<std::string>> m_keys;
  std::set<std::string> m_used;
};

/// One JSON light object at `place` of `source`; errors are InputError(source, place.key, why). Every key
/// the kind does not read is refused (check_all_used).
class LightJson {
 public:
  LightJson(const nlohmann::json& object, std::string source, std::string place,
            std::filesystem::path base_dir)
      : m_json(object),
        m_source(std::move(source)),
        m_place(std::move(place)),
        m_base_dir(std::move(base_dir)) {}
  const std::filesystem::path& base_dir() const { return m_base_dir; }
  [[noreturn]] void fail(const std::string& key, const std::string& why) const;
  /// The value at `key`, or null when absent (the key is allowed either way).
  const nlohmann::json* get(const char* key);
  /// A colour (a number or [r, g, b]) at `key` (default 1), times "color" when given; finite, >= 0.
  glm::dvec3 colour(const char* key);
  /// A unit vector from [x, y, z] at `key` (default `fallback`); non-zero.
  glm::dvec3 unit(const char* key, const glm::dvec3& fallback);
  glm::dvec3 vec3(const nlohmann::json& value, const std::string& key) const;
  double number(const nlohmann::json& value, const std::string& key) const;
  /// Whether the object has `key` (without allowing it).
  bool contains(const char* key) const { return m_json.contains(key); }
  /// Refuses a key no get() asked for, naming the kind.
  void check_all_used(std::string_view kind) const;

 private:
  const nlohmann::json& m_json;
  std::string m_source, m_place;
  std::filesystem::path m_base_dir;
  std::set<std::string> m_allowed{"type", "color"};
};

}  // namespace pleat
