// A cone-engine configuration named on the command line, "orientations:spacing:storage[:spiral][:rule]": the
// diffuse plan's orientation count (6: the paper's axis-aligned set; other counts spread over the hemisphere,
// relaxed to evenly spaced lines unless ":spiral"), its plane spacing in average edge lengths and the
// storage rule (cone_storage_name), and the reconstruction rule (cone_reconstruction_name; default grouped).
// Shared by the benchmarks that compare plans (accuracy_budget_bench
// --settings, frame_coherence_bench --plans).
#pragma once

#include <string>

#include "static_core/slicing_plan.hpp"

namespace pleat::bench {

struct Setting {
  DiffusePlanParams plan;                       ///< default: make_diffuse_plan's defaults
  ConeStorage storage = SlicingPlan{}.storage;  ///< default: the engine's
  ConeReconstruction reconstruction = SlicingPlan{}.reconstruction;
};

/// A setting of `orientations` families `spacing_edges` average edge lengths apart.
Setting setting(int orientations, double spacing_edges, ConeStorage storage, bool relaxed = true);

/// Parses "8:0.5:interpolated-on-fan", "8:0.75:interpolated-on-fan:spiral" or with a last field naming the
/// reconstruction rule, "16:0.5:aimed-on-fan:nearest-circle". Throws std::invalid_argument
/// naming `flag` and the text for anything else (a count below 1, a spacing not positive and finite, an
/// unknown storage rule, trailing characters).
Setting parse_setting(const std::string& text, const std::string& flag);

/// The canonical text of a setting, which parse_setting reads back: "12:0.5:aimed-on-fan[:spiral]".
std::string setting_name(const Setting& s);

}  // namespace pleat::bench
