// Cone-engine configurations named on the command line (see plan_setting.hpp).
#include "bench/coherence/plan_setting.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace pleat::bench {

Setting setting(int orientations, double spacing_edges, ConeStorage storage, bool relaxed) {
  Setting s;
  s.plan.orientations = orientations;
  s.plan.spacing_in_edges = spacing_edges;
  s.plan.relaxed = relaxed;
  s.storage = storage;
  return s;
}

Setting parse_setting(const std::string& text, const std::string& flag) {
  auto bad = [&](const std::string& why) {
    return std::invalid_argument(
        flag + ": '" + text + "' " + why +
        " (expected orientations:spacing:storage[:spiral], e.g. 12:0.5:aimed-on-fan)");
  };
  const auto a = text.find(':'), b = a == std::string::npos ? a : text.find(':', a + 1);
  if (b == std::string::npos) throw bad("has fewer than three fields");
  const auto c = text.find(':', b + 1);
  const std::string count = text.substr(0, a), spacing = text.substr(a + 1, b - a - 1);
  const std::string storage = text.substr(b + 1, c == std::string::npos ? std::string::npos : c - b - 1);
  if (c != std::string::npos && text.substr(c + 1) != "spiral")
    throw bad("ends in neither the storage rule nor ':spiral'");
  int orientations = 0;
  double edges = 0;
  std::size_t used = 0;
  try {
    orientations = std::stoi(count, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != count.size() || orientations < 1) throw bad("has no positive orientation count");
  try {
    edges = std::stod(spacing, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != spacing.size() || !(edges > 0) || !std::isfinite(edges))
    throw bad("has no positive spacing");
  ConeStorage rule{};
  try {
    rule = cone_storage_from_name(storage);
  } catch (const std::invalid_argument&) {
    throw bad("names no storage rule (nearer-endpoint, nearest-on-fan, interpolated-on-fan, aimed-on-fan)");
  }
  return setting(orientations, edges, rule, c == std::string::npos);
}

std::string setting_name(const Setting& s) {
  char spacing[32];
  std::snprintf(spacing, sizeof spacing, "%g", s.plan.spacing_in_edges);
  return std::to_string(s.plan.orientations) + ':' + spacing + ':' + cone_storage_name(s.storage) +
         (s.plan.relaxed ? "" : ":spiral");
}

}  // namespace pleat::bench
