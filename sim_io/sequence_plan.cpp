#include "sim_io/sequence_plan.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "sim_io/plan_file.hpp"

namespace pleat {

void PlanOptions::check() const {
  const auto bad = [](const std::string& what) { throw std::invalid_argument(what); };
  if (orientations < 1 || orientations > 1000)
    bad("orientations: " + std::to_string(orientations) + " is not in 1..1000");
  if (!(std::isfinite(spacing) && spacing >= 0)) bad("spacing: must be a finite number >= 0");
  if (!(std::isfinite(spacing_edges) && spacing_edges >= 0))
    bad("spacing_edges: must be a finite number > 0");
  if (spacing > 0 && spacing_edges > 0) bad("spacing and spacing_edges exclude each other");
  if (planes_per_orientation < 0) bad("planes: must be >= 0");
  if (!(max_missing >= 0 && max_missing <= 1)) bad("max_missing: must be in [0, 1]");
  if (storage != "aimed-on-fan" && storage != "interpolated-on-fan" && storage != "nearest-on-fan" &&
      storage != "nearer-endpoint")
    bad("cone_storage: '" + storage +
        "' is not aimed-on-fan, interpolated-on-fan, nearest-on-fan or nearer-endpoint");
  const PlanOptions defaults;
  if (!plan_file.empty() && (orientations != defaults.orientations || spacing != 0 || spacing_edges != 0 ||
                             planes_per_orientation != 0 || adaptive || max_missing != defaults.max_missing ||
                             storage != defaults.storage || paper))
    bad("plan: a plan file fixes the planes; it excludes orientations, spacing, spacing_edges, planes, "
        "adaptive, max_missing, cone_storage and paper");
}

SlicingPlan PlanOptions::make(const MeshSequence& sequence) const {
  const MeshTopology& topology = sequence.topology();
  SlicingPlan plan;
  if (!plan_file.empty()) {
    plan = read_plan_file(plan_file);
  } else {
    // Measured on the sequence's first frame, never on the requested ones. A lattice is its orientations and
    // spacing: the engines take each frame's planes from it (planes_for_frame); counted planes are spread
    // over the box of every frame.
    const Frame frame = sequence.frame(0);
    const Bounds& cover = sequence.bounds();
    const int count = paper ? 6 : orientations;
    const bool counted = planes_per_orientation > 0;
    if (paper && !adaptive && spacing == 0 && spacing_edges == 0 && !counted) {
      plan = make_paper_plan(topology, frame);
    } else {
      DiffusePlanParams diffuse{count, spacing, planes_per_orientation};
      if (spacing_edges > 0) diffuse.spacing_in_edges = spacing_edges;
      plan = adaptive ? make_adaptive_plan(topology, frame, {count, max_missing})
                      : make_diffuse_plan(topology, frame, diffuse, counted ? &cover : nullptr);
      plan.storage = paper ? ConeStorage::NearerEndpoint : cone_storage_from_name(storage);
    }
  }
  if (plan.spacing > 0) plan.planes.clear();  // a lattice: each frame's planes are its own
  return plan;
}

std::string PlanOptions::describe() const {
  if (!plan_file.empty()) return "plan " + plan_file;
  const int count = paper ? 6 : orientations;
  const std::string stored = std::string(", ") + (paper ? "nearer-endpoint" : storage) + " storage";
  if (adaptive)
    return std::to_string(count) + " orientations, adaptive (max missing " + std::to_string(max_missing) +
           ")" + stored;
  if (planes_per_orientation > 0)
    return std::to_string(count) + " orientations x " + std::to_string(planes_per_orientation) + " planes" +
           stored;
  auto edges = [](double k) {
    char text[64];
    std::snprintf(text, sizeof text, "= %g of the average edge length", k);
    return std::string(text);
  };
  return std::to_string(count) + " orientations, spacing " +
         (spacing > 0         ? std::to_string(spacing)
          : spacing_edges > 0 ? edges(spacing_edges)
          : paper             ? std::string("= the average edge length")
                              : edges(DiffusePlanParams{}.spacing_in_edges)) +
         stored;
}

}  // namespace pleat
