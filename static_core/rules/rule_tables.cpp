// The tables of static_core/cone_rules.hpp: one row per rule, the rule in its own file. A new rule is its
// file (static_core/rules/*.cpp, taken by static_core/CMakeLists.txt) and one row here.
#include <algorithm>
#include <stdexcept>

#include "static_core/cone_rules.hpp"

namespace pleat {
namespace rules {

extern const ConeStorageRule kNearerEndpoint, kNearestOnFan, kInterpolatedOnFan, kAimedOnFan;
extern const ConeReconstructionRule kGrouped, kNearestCircle;

const ConeStorageRule* const kStorage[] = {
    &kNearerEndpoint,
    &kNearestOnFan,
    &kInterpolatedOnFan,
    &kAimedOnFan,
};

const ConeReconstructionRule* const kReconstruction[] = {
    &kGrouped,
    &kNearestCircle,
};

}  // namespace rules

namespace {

template <class Rule>
std::string names_of(std::span<const Rule* const> table) {
  std::string text;
  for (std::size_t i = 0; i < table.size(); ++i)
    text += (i == 0 ? "" : i + 1 == table.size() ? " or " : ", ") + std::string(table[i]->name);
  return text;
}

template <class Id, class Rule>
Id id_of(std::span<const Rule* const> table, std::string_view name, const char* what) {
  for (std::size_t i = 0; i < table.size(); ++i)
    if (table[i]->name == name) return Id(i);
  throw std::invalid_argument("unknown " + std::string(what) + " '" + std::string(name) + "' (" +
                              names_of(table) + ")");
}

template <class Rule>
const Rule& row(std::span<const Rule* const> table, std::size_t id, const char* what) {
  if (id >= table.size())
    throw std::invalid_argument(std::string(what) + ": no rule of id " + std::to_string(id));
  return *table[id];
}

}  // namespace

std::span<const ConeStorageRule* const> cone_storage_rules() { return rules::kStorage; }
std::span<const ConeReconstructionRule* const> cone_reconstruction_rules() { return rules::kReconstruction; }

const ConeStorageRule& cone_storage_rule(ConeStorage storage) {
  return row(cone_storage_rules(), std::size_t(storage), "cone storage rule");
}
const ConeReconstructionRule& cone_reconstruction_rule(ConeReconstruction reconstruction) {
  return row(cone_reconstruction_rules(), std::size_t(reconstruction), "cone reconstruction rule");
}

std::string cone_storage_names() { return names_of(cone_storage_rules()); }
std::string cone_reconstruction_names() { return names_of(cone_reconstruction_rules()); }

const char* cone_storage_name(ConeStorage storage) { return cone_storage_rule(storage).name.data(); }
ConeStorage cone_storage_from_name(std::string_view name) {
  return id_of<ConeStorage>(cone_storage_rules(), name, "cone storage rule");
}

const char* cone_reconstruction_name(ConeReconstruction reconstruction) {
  return cone_reconstruction_rule(reconstruction).name.data();
}
ConeReconstruction cone_reconstruction_from_name(std::string_view name) {
  return id_of<ConeReconstruction>(cone_reconstruction_rules(), name, "cone reconstruction rule");
}

}  // namespace pleat
