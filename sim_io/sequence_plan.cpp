#include "sim_io/sequence_plan.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <limits>
#include <stdexcept>

#include "sim_io/plan_file.hpp"
#include "static_core/adaptive_plan.hpp"
#include "static_core/cone_rules.hpp"
#include "support/input_error.hpp"

namespace pleat {

namespace {

// The shortest decimal that reads back to `x` ("0.1", "1e-07").
std::string shortest(double x) {
  char text[32];
  const auto [end, error] = std::to_chars(text, text + sizeof text, x);
  return error == std::errc() ? std::string(text, end) : std::to_string(x);
}

std::string number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", x);
  return text;
}

/// The largest extent of the cloth of `frame` (the vertices its triangles use) along the orientations.
double widest_extent(const MeshTopology& topology, const Frame& frame,
                     const std::vector<glm::dvec3>& orientations) {
  double widest = 0.0;
  for (const glm::dvec3& n : orientations) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const Triangle& t : topology.triangles)
      for (Index v : t) {
        const double h = glm::dot(n, frame.positions[v]);
        lo = std::min(lo, h), hi = std::max(hi, h);
      }
    if (lo <= hi) widest = std::max(widest, hi - lo);
  }
  return widest;
}

}  // namespace

void PlanOptions::check(Naming naming) const {
  const bool cli = naming == Naming::CommandLine;
  const auto name = [&](const char* keyword, const char* option) {
    return std::string(cli ? option : keyword);
  };
  const auto bad = [](const std::string& what) { throw std::invalid_argument(what); };
  if (orientations < 1 || orientations > 1000)
    bad(name("orientations", "--orientations") + ": " + std::to_string(orientations) + " is not in 1..1000");
  if (spacing && !(std::isfinite(*spacing) && *spacing > 0))
    bad(name("spacing", "--spacing") + ": must be a finite number > 0, got " + number(*spacing));
  if (spacing_edges && !(std::isfinite(*spacing_edges) && *spacing_edges > 0))
    bad(name("spacing_edges", "--spacing-edges") + ": must be a finite number > 0, got " +
        number(*spacing_edges));
  if (spacing && spacing_edges)
    bad(name("spacing", "--spacing") + " and " + name("spacing_edges", "--spacing-edges") +
        " exclude each other");
  if (planes_per_orientation && *planes_per_orientation < 1)
    bad(name("planes", "--planes") + ": must be >= 1, got " + std::to_string(*planes_per_orientation));
  if (!(max_missing >= 0 && max_missing <= 1))
    bad(name("max_missing", "--max-missing") + ": must be in [0, 1], got " + number(max_missing));
  const auto rule = [&](const std::string& value, const char* keyword, const char* option, auto from_name,
                        const std::string& names) {
    try {
      from_name(value);
    } catch (const std::invalid_argument&) {
      bad(name(keyword, option) + ": '" + value + "' is not " + names);
    }
  };
  rule(storage, "cone_storage", "--cone-storage", cone_storage_from_name, cone_storage_names());
  rule(reconstruction, "cone_reconstruction", "--cone-reconstruction", cone_reconstruction_from_name,
       cone_reconstruction_names());
  const PlanOptions defaults;
  if (!plan_file.empty() &&
      (orientations != defaults.orientations || spacing || spacing_edges || planes_per_orientation ||
       adaptive || max_missing != defaults.max_missing || storage != defaults.storage ||
       reconstruction != defaults.reconstruction || paper))
    bad(cli ? "--plan: a plan file fixes the planes; it excludes --orientations, --spacing, --spacing-edges, "
              "--planes, --adaptive, --max-missing, --cone-storage, --cone-reconstruction and --paper"
            : "plan: a plan file fixes the planes; it excludes orientations, spacing, spacing_edges, planes, "
              "adaptive, max_missing, cone_storage, cone_reconstruction and paper");
}

SlicingPlan PlanOptions::make(const MeshSequence& sequence, Naming naming) const {
  check(naming);
  const MeshTopology& topology = sequence.topology();
  SlicingPlan plan;
  const Frame frame = sequence.frame(0);
  if (!plan_file.empty()) {
    plan = read_plan_file(plan_file);
  } else {
    // Measured on the sequence's first frame, never on the requested ones. A lattice is its orientations and
    // spacing: the engines take each frame's planes from it (planes_for_frame); counted planes are spread
    // over the box of every frame.
    const Bounds& cover = sequence.bounds();
    const int count = paper ? 6 : orientations;
    const bool counted = planes_per_orientation.has_value();
    if (paper && !adaptive && !spacing && !spacing_edges && !counted) {
      plan = make_paper_plan(topology, frame);
    } else {
      DiffusePlanParams diffuse{count, spacing.value_or(0.0), planes_per_orientation.value_or(0)};
      if (spacing_edges) diffuse.spacing_in_edges = *spacing_edges;
      try {
        plan = adaptive ? make_adaptive_plan(topology, frame, {count, max_missing})
                        : make_diffuse_plan(topology, frame, diffuse, counted ? &cover : nullptr);
      } catch (const std::invalid_argument& e) {  // a plan this cloth cannot have: named with the input
        throw InputError(sequence.name(), "", e.what());
      } catch (const InputError& e) {
        if (e.file() != "slicing plan") throw;
        throw InputError(sequence.name(), "", e.what());
      }
      plan.storage = paper ? ConeStorage::NearerEndpoint : cone_storage_from_name(storage);
    }
    plan.reconstruction = cone_reconstruction_from_name(reconstruction);
  }
  check_spacing_cuts(plan, topology, frame, sequence.name(), naming);
  if (plan.spacing > 0) plan.planes.clear();  // a lattice: each frame's planes are its own
  return plan;
}

void PlanOptions::check_spacing_cuts(const SlicingPlan& plan, const MeshTopology& topology,
                                     const Frame& frame, const std::string& input, Naming naming) const {
  if (!(plan.spacing > 0)) return;  // planes placed one by one: they cut the cloth
  const double widest = widest_extent(topology, frame, plan.orientations);
  if (plan.spacing <= widest) return;
  const bool cli = naming == Naming::CommandLine;
  std::string given;
  if (!plan_file.empty())
    given = "the spacing " + number(plan.spacing) + " of the plan file " + plan_file;
  else if (spacing)
    given = std::string(cli ? "--spacing " : "spacing=") + number(*spacing);
  else if (spacing_edges)
    given = std::string(cli ? "--spacing-edges " : "spacing_edges=") + number(*spacing_edges) +
            " (a spacing of " + number(plan.spacing) + ")";
  else
    given = "the spacing " + number(plan.spacing);
  throw std::invalid_argument(
      given + " is wider than the cloth " + input + " (its first frame spans " + number(widest) +
      " along the plan's widest orientation): no plane would cut it and every A would "
      "be 0; the default spacing is " +
      number(DiffusePlanParams{}.spacing_in_edges) + " average edge lengths");
}

std::string PlanOptions::describe() const {
  if (!plan_file.empty()) return "plan " + plan_file;
  const int count = paper ? 6 : orientations;
  std::string stored =
      std::string(", ") + (paper ? cone_storage_name(ConeStorage::NearerEndpoint) : storage) + " storage";
  if (reconstruction != PlanOptions{}.reconstruction) stored += ", " + reconstruction + " reconstruction";
  if (adaptive)
    return std::to_string(count) + " orientations, adaptive (max missing " + std::to_string(max_missing) +
           ")" + stored;
  if (planes_per_orientation)
    return std::to_string(count) + " orientations x " + std::to_string(*planes_per_orientation) + " planes" +
           stored;
  auto edges = [](double k) {
    char text[64];
    std::snprintf(text, sizeof text, "= %g of the average edge length", k);
    return std::string(text);
  };
  return std::to_string(count) + " orientations, spacing " +
         (spacing         ? shortest(*spacing)
          : spacing_edges ? edges(*spacing_edges)
          : paper         ? std::string("= the average edge length")
                          : edges(DiffusePlanParams{}.spacing_in_edges)) +
         stored;
}

}  // namespace pleat
