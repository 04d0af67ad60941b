#include "static_core/plan_codec.hpp"

#include <cmath>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "static_core/cone_rules.hpp"
#include "support/byte_stream.hpp"
#include "support/fingerprint.hpp"
#include "support/input_error.hpp"

namespace pleat {
namespace {

constexpr int kVersion = 1;

nlohmann::json to_json(const glm::dvec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); }

/// The checks of one plan file's values, each error naming the file and the place.
struct JsonReader {
  const std::string& file;

  InputError fail(const std::string& place, const std::string& what) const {
    return InputError(file, place, what);
  }
  double number(const nlohmann::json& v, const std::string& place) const {
    if (!v.is_number()) throw fail(place, "expected a number");
    const double x = v.get<double>();
    if (!std::isfinite(x)) throw fail(place, "not finite");
    return x;
  }
  glm::dvec3 vector(const nlohmann::json& v, const std::string& place) const {
    if (!v.is_array() || v.size() != 3) throw fail(place, "expected [x, y, z]");
    const glm::dvec3 d(number(v[0], place), number(v[1], place), number(v[2], place));
    if (!(glm::length(d) > 0)) throw fail(place, "a zero direction");
    return d;
  }
  /// The id of the rule named at `key` (absent: `fallback`).
  template <class Id>
  Id rule(const nlohmann::json& doc, const char* key, Id (*from_name)(std::string_view),
          const Id* fallback) const {
    if (!doc.contains(key) && fallback) return *fallback;
    if (!doc.contains(key) || !doc[key].is_string()) throw fail(key, "expected a rule name");
    try {
      return from_name(doc[key].get<std::string>());
    } catch (const std::invalid_argument& e) {
      throw fail(key, e.what());
    }
  }
  SlicingPlane plane(const nlohmann::json& p, std::size_t i, std::size_t orientations) const {
    const std::string place = "planes[" + std::to_string(i) + "]";
    if (!p.is_object() || !p.contains("orientation") || !p["orientation"].is_number_integer())
      throw fail(place, "expected {\"orientation\", \"offset\", \"normal\", \"u\", \"w\"}");
    const long long o = p["orientation"].get<long long>();
    if (o < 0 || o >= static_cast<long long>(orientations))
      throw fail(place, "orientation " + std::to_string(o) + " does not exist");
    SlicingPlane plane;  // as written, bit for bit
    plane.orientation = static_cast<int>(o);
    plane.offset = number(p.value("offset", nlohmann::json()), place + ".offset");
    plane.normal = vector(p.value("normal", nlohmann::json()), place + ".normal");
    plane.u = vector(p.value("u", nlohmann::json()), place + ".u");
    plane.w = vector(p.value("w", nlohmann::json()), place + ".w");
    return plane;
  }
};

}  // namespace

std::string plan_to_bytes(const SlicingPlan& plan) {
  return ByteWriter()
      .put<std::uint64_t>(std::uint64_t(plan.storage))
      .put<std::uint64_t>(std::uint64_t(plan.reconstruction))
      .put(plan.spacing)
      .put_array(plan.orientations)
      .put_array(plan.planes)
      .take();
}

SlicingPlan plan_from_bytes(std::string_view bytes) {
  ByteReader reader(bytes);
  SlicingPlan plan;
  plan.storage = ConeStorage(reader.get<std::uint64_t>());
  plan.reconstruction = ConeReconstruction(reader.get<std::uint64_t>());
  static_cast<void>(cone_storage_rule(plan.storage));  // ids of rows that exist, or std::invalid_argument
  static_cast<void>(cone_reconstruction_rule(plan.reconstruction));
  plan.spacing = reader.get<double>();
  plan.orientations = reader.get_array<glm::dvec3>();
  plan.planes = reader.get_array<SlicingPlane>();
  return plan;
}

std::string plan_to_json(const SlicingPlan& plan) {
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
  return out.dump(1) + "\n";
}

SlicingPlan plan_from_json(std::string_view text, const std::string& file) {
  const JsonReader read{file};
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(file, "byte " + std::to_string(e.byte), "not a plan file (invalid JSON)");
  }
  if (!doc.is_object() || !doc.contains("pleat_plan"))
    throw read.fail("", "not a plan file (no \"pleat_plan\")");
  if (doc["pleat_plan"] != kVersion)
    throw read.fail("pleat_plan", "version " + doc["pleat_plan"].dump() + " (this pleat reads version 1)");
  SlicingPlan plan;
  plan.storage = read.rule<ConeStorage>(doc, "storage", cone_storage_from_name, nullptr);
  const ConeReconstruction grouped = ConeReconstruction::Grouped;  // files written before it was saved
  plan.reconstruction =
      read.rule<ConeReconstruction>(doc, "reconstruction", cone_reconstruction_from_name, &grouped);
  const nlohmann::json& orientations = doc.value("orientations", nlohmann::json());
  if (!orientations.is_array() || orientations.empty())
    throw read.fail("orientations", "expected a non-empty list of [x, y, z]");
  for (std::size_t i = 0; i < orientations.size(); ++i)  // as written: unit normals keep their bits
    plan.orientations.push_back(read.vector(orientations[i], "orientations[" + std::to_string(i) + "]"));
  const bool lattice = doc.contains("spacing"), listed = doc.contains("planes");
  if (lattice == listed) throw read.fail("", "expected either \"spacing\" (a lattice) or \"planes\"");
  if (lattice) {
    plan.spacing = read.number(doc["spacing"], "spacing");
    if (!(plan.spacing > 0)) throw read.fail("spacing", "must be positive");
    return plan;
  }
  const nlohmann::json& planes = doc["planes"];
  if (!planes.is_array()) throw read.fail("planes", "expected a list of planes");
  for (std::size_t i = 0; i < planes.size(); ++i)
    plan.planes.push_back(read.plane(planes[i], i, plan.orientations.size()));
  return plan;
}

std::uint64_t plan_fingerprint(const SlicingPlan& plan) {
  Fingerprint f;
  f.add_value(int(plan.storage)).add_value(plan.spacing);
  if (plan.reconstruction != ConeReconstruction::Grouped) f.add_value(int(plan.reconstruction));
  f.add(plan.orientations.data(), plan.orientations.size() * sizeof(glm::dvec3));
  for (const SlicingPlane& p : plan.planes)
    f.add_value(p.normal).add_value(p.offset).add_value(p.u).add_value(p.w).add_value(p.orientation);
  return f.value();
}

}  // namespace pleat
