#include "shading/internal/light_parsing.hpp"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <glm/geometric.hpp>
#include <sstream>
#include <stdexcept>

#include "support/input_error.hpp"

namespace pleat {

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

std::filesystem::path resolve(const std::filesystem::path& file, const std::filesystem::path& base_dir) {
  if (file.is_absolute() || base_dir.empty()) return file;
  return base_dir / file;
}

// ---- spec strings ---------------------------------------------------------------------------------------

LightSpec::LightSpec(std::string_view args, std::filesystem::path base_dir)
    : m_args(args), m_base_dir(std::move(base_dir)) {}

void LightSpec::split_once() {
  if (!m_split) split_keys(m_args);
}

const std::vector<std::string>& LightSpec::positional() {
  split_once();
  return m_positional;
}

bool LightSpec::has(const std::string& k) {
  split_once();
  return m_keys.count(k) != 0;
}

void LightSpec::split_keys(std::string_view args) {
  m_split = true;
  m_positional.clear();
  m_keys.clear();
  if (trim(args).empty()) return;
  std::string current_key;
  for (const std::string& token : split(args, ',')) {
    const std::size_t eq = token.find('=');
    if (eq != std::string::npos) {
      current_key = trim(std::string_view(token).substr(0, eq));
      if (current_key.empty()) throw std::invalid_argument("empty key in '" + token + "'");
      if (m_keys.count(current_key)) throw std::invalid_argument("key '" + current_key + "' given twice");
      m_keys[current_key].push_back(trim(std::string_view(token).substr(eq + 1)));
    } else if (current_key.empty()) {
      m_positional.push_back(token);
    } else {
      m_keys[current_key].push_back(token);
    }
  }
}

std::vector<double> LightSpec::positional_numbers() {
  std::vector<double> out;
  for (const std::string& t : positional()) {
    double v;
    if (!parse_number(t, v)) throw std::invalid_argument("expected a number, got '" + t + "'");
    out.push_back(v);
  }
  return out;
}

std::vector<double> LightSpec::numbers(const std::string& k) {
  split_once();
  m_used.insert(k);
  std::vector<double> out;
  for (const std::string& t : m_keys.at(k)) {
    double v;
    if (!parse_number(t, v)) throw std::invalid_argument("'" + k + "' expects numbers, got '" + t + "'");
    out.push_back(v);
  }
  return out;
}

double LightSpec::scalar(const std::string& k, double fallback) {
  if (!has(k)) return fallback;
  const auto v = numbers(k);
  if (v.size() != 1) throw std::invalid_argument("'" + k + "' expects one number");
  return v[0];
}

glm::dvec3 LightSpec::vec3(const std::string& k, const glm::dvec3& fallback) {
  if (!has(k)) return fallback;
  const auto v = numbers(k);
  if (v.size() != 3) throw std::invalid_argument("'" + k + "' expects three numbers x,y,z");
  return {v[0], v[1], v[2]};
}

void LightSpec::check_all_used() {
  split_once();
  for (const auto& [k, v] : m_keys)
    if (!m_used.count(k)) throw std::invalid_argument("unknown key '" + k + "'");
}

// ---- JSON ---------------------------------------------------------------------------------------------

void LightJson::fail(const std::string& key, const std::string& why) const {
  throw InputError(m_source, key.empty() ? m_place : m_place + "." + key, why);
}

const nlohmann::json* LightJson::get(const char* key) {
  m_allowed.insert(key);
  return m_json.contains(key) ? &m_json[key] : nullptr;
}

namespace {

bool is_triple(const nlohmann::json& j) {
  return j.is_array() && j.size() == 3 && j[0].is_number() && j[1].is_number() && j[2].is_number();
}

}  // namespace

glm::dvec3 LightJson::colour(const char* key) {
  auto of = [&](const nlohmann::json& j, const std::string& at) -> glm::dvec3 {
    if (j.is_number()) return glm::dvec3(j.get<double>());
    if (is_triple(j)) return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
    fail(at, "expected a number or [r, g, b]");
  };
  glm::dvec3 c(1.0);
  if (const nlohmann::json* v = get(key)) c = of(*v, key);
  if (m_json.contains("color")) c *= of(m_json["color"], "color");
  for (int k = 0; k < 3; ++k)
    if (!(c[k] >= 0.0) || !std::isfinite(c[k])) fail(key, "must be finite and non-negative");
  return c;
}

glm::dvec3 LightJson::vec3(const nlohmann::json& j, const std::string& key) const {
  if (is_triple(j)) return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
  fail(key, "expected [x, y, z]");
}

double LightJson::number(const nlohmann::json& j, const std::string& key) const {
  if (!j.is_number()) fail(key, "expected a number");
  return j.get<double>();
}

glm::dvec3 LightJson::unit(const char* key, const glm::dvec3& fallback) {
  glm::dvec3 v = fallback;
  if (const nlohmann::json* x = get(key)) v = vec3(*x, key);
  const double len = glm::length(v);
  if (!(len > 0.0) || !std::isfinite(len)) fail(key, "must be a non-zero vector");
  return v / len;
}

void LightJson::check_all_used(std::string_view kind) const {
  for (const auto& [key, value] : m_json.items())
    if (!m_allowed.count(key)) fail(key, "unknown field for a " + std::string(kind) + " light");
}

}  // namespace pleat
