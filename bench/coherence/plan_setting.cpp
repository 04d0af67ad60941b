// Cone-engine configurations named on the command line (see plan_setting.hpp).
#include "bench/coherence/plan_setting.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "static_core/cone_rules.hpp"

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
        " (expected orientations:spacing:storage[:spiral][:nearest-circle], e.g. 12:0.5:aimed-on-fan)");
  };
  std::vector<std::string> fields;
  for (std::size_t from = 0;;) {
    const auto to = text.find(':', from);
    fields.push_back(text.substr(from, to == std::string::npos ? std::string::npos : to - from));
    if (to == std::string::npos) break;
    from = to + 1;
  }
  if (fields.size() < 3) throw bad("has fewer than three fields");
  const std::string &count = fields[0], &spacing = fields[1], &storage = fields[2];
  bool relaxed = true;
  ConeReconstruction reconstruction = ConeReconstruction::Grouped;
  for (std::size_t i = 3; i < fields.size(); ++i) {
    if (fields[i] == "spiral") {
      relaxed = false;
      continue;
    }
    try {
      reconstruction = cone_reconstruction_from_name(fields[i]);
    } catch (const std::invalid_argument&) {
      throw bad("has a field '" + fields[i] + "' that is neither 'spiral' nor a reconstruction rule");
    }
  }
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
    throw bad("names no storage rule (" + cone_storage_names() + ")");
  }
  Setting result = setting(orientations, edges, rule, relaxed);
  result.reconstruction = reconstruction;
  return result;
}

std::string setting_name(const Setting& s) {
  char spacing[32];
  std::snprintf(spacing, sizeof spacing, "%g", s.plan.spacing_in_edges);
  std::string name = std::to_string(s.plan.orientations) + ':' + spacing + ':' + cone_storage_name(s.storage);
  if (!s.plan.relaxed) name += ":spiral";
  if (s.reconstruction != ConeReconstruction::Grouped)
    name.append(":").append(cone_reconstruction_name(s.reconstruction));
  return name;
}

}  // namespace pleat::bench
