#include "sim_io/plan_file.hpp"

#include <cmath>
#include <fstream>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>
#include <sstream>

#include "sim_io/atomic_file.hpp"
#include "static_core/input_error.hpp"

namespace pleat {
namespace {

constexpr int kVersion = 1;

nlohmann::json to_json(const glm::dvec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); }

}  // namespace

void write_plan_file(const std::filesystem::path& path, const SlicingPlan& plan) {
  nlohmann::json out = {{"pleat_plan", kVersion},
                        {"storage", cone_storage_name(plan.storage)},
                        {"reconstruction", cone_reconstruction_name(plan.reconstruction)}};
  out["orientations"] = nlohmann::json::array();
  for (const glm::dvec3& o : plan.orientations) out["orientations"].push_back(to_json(o));
  if (plan.spacing > 0) {
    out["spacing"] = plan.spacing;
  } else {
    out["planes"] = nlohmann::json::array();
    for (const SlicingPlane& p : plan.planes)
      out["planes"].push_back({{"orientation", p.orientation},
                               {"offset", p.offset},
                               {"normal", to_json(p.normal)},
                               {"u", to_json(p.u)},
                               {"w", to_json(p.w)}});
  }
  write_file_atomically(path, out.dump(1) + "\n");
}

SlicingPlan read_plan_file(const std::filesystem::path& path) {
  const std::string name = path.string();
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(name, "", "cannot open the plan file");
  std::stringstream text;
  text << in.rdbuf();
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(text.str());
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(name, "byte " + std::to_string(e.byte), "not a plan file (invalid JSON)");
  }
  auto fail = [&](const std::string& place, const std::string& what) -> InputError {
    return InputError(name, place, what);
  };
  auto number = [&](const nlohmann::json& v, const std::string& place) {
    if (!v.is_number()) throw fail(place, "expected a number");
    const double x = v.get<double>();
    if (!std::isfinite(x)) throw fail(place, "not finite");
    return x;
  };
  auto vector = [&](const nlohmann::json& v, const std::string& place) {
    if (!v.is_array() || v.size() != 3) throw fail(place, "expected [x, y, z]");
    const glm::dvec3 d(number(v[0], place), number(v[1], place), number(v[2], place));
    if (!(glm::length(d) > 0)) throw fail(place, "a zero direction");
    return d;
  };
  if (!doc.is_object() || !doc.contains("pleat_plan")) throw fail("", "not a plan file (no \"pleat_plan\")");
  if (doc["pleat_plan"] != kVersion)
    throw fail("pleat_plan", "version " + doc["pleat_plan"].dump() + " (this pleat reads version 1)");

  SlicingPlan plan;
  if (!doc.contains("storage") || !doc["storage"].is_string()) throw fail("storage", "expected a rule name");
  try {
    plan.storage = cone_storage_from_name(doc["storage"].get<std::string>());
  } catch (const std::invalid_argument& e) {
    throw fail("storage", e.what());
  }
  if (doc.contains("reconstruction")) {  // files written before it was saved hold grouped plans
    if (!doc["reconstruction"].is_string()) throw fail("reconstruction", "expected a rule name");
    try {
      plan.reconstruction = cone_reconstruction_from_name(doc["reconstruction"].get<std::string>());
    } catch (const std::invalid_argument& e) {
      throw fail("reconstruction", e.what());
    }
  }
  const nlohmann::json& orientations = doc.value("orientations", nlohmann::json());
  if (!orientations.is_array() || orientations.empty())
    throw fail("orientations", "expected a non-empty list of [x, y, z]");
  for (std::size_t i = 0; i < orientations.size(); ++i)  // as written: unit normals keep their bits
    plan.orientations.push_back(vector(orientations[i], "orientations[" + std::to_string(i) + "]"));
  const bool lattice = doc.contains("spacing"), listed = doc.contains("planes");
  if (lattice == listed) throw fail("", "expected either \"spacing\" (a lattice) or \"planes\"");
  if (lattice) {
    plan.spacing = number(doc["spacing"], "spacing");
    if (!(plan.spacing > 0)) throw fail("spacing", "must be positive");
    return plan;
  }
  const nlohmann::json& planes = doc["planes"];
  if (!planes.is_array()) throw fail("planes", "expected a list of planes");
  for (std::size_t i = 0; i < planes.size(); ++i) {
    const std::string place = "planes[" + std::to_string(i) + "]";
    const nlohmann::json& p = planes[i];
    if (!p.is_object() || !p.contains("orientation") || !p["orientation"].is_number_integer())
      throw fail(place, "expected {\"orientation\", \"offset\", \"normal\", \"u\", \"w\"}");
    const long long o = p["orientation"].get<long long>();
    if (o < 0 || o >= static_cast<long long>(plan.orientations.size()))
      throw fail(place, "orientation " + std::to_string(o) + " does not exist");
    SlicingPlane plane;
    plane.orientation = static_cast<int>(o);
    plane.offset = number(p.value("offset", nlohmann::json()), place + ".offset");
    plane.normal = vector(p.value("normal", nlohmann::json()), place + ".normal");
    plane.u = vector(p.value("u", nlohmann::json()), place + ".u");
    plane.w = vector(p.value("w", nlohmann::json()), place + ".w");
    plan.planes.push_back(plane);  // as written, bit for bit
  }
  return plan;
}

}  // namespace pleat
