// The specification of a visibility job as the command line (`pleat visibility`, `pleat shade`) and the
// Python module both take it: the slicing plan's options (sequence_plan.hpp), the engine's parameters and
// the scene's contact tolerance, each checked by one check() with one message per bad value, naming the
// option as the caller spells it (--spacing-edges on the command line, spacing_edges in Python). The
// command line adds where the cloth and the scene come from, the frames and the chunking (cli/job.hpp); the
// Python module gives the cloth and the scene as arrays.
#pragma once

#include <optional>
#include <string>

#include "sim_io/sequence_plan.hpp"

namespace pleat {

struct JobSpec {
  using Naming = PlanOptions::Naming;

  PlanOptions plan;
  std::string engine = "kinetic";           ///< kinetic or static (kinetic/engine.hpp: engine_kind_from_name)
  double max_edit_fraction = 0.5;           ///< >= 0: the kinetic engine's rebuild threshold (KineticPolicy)
  int threads = 0;                          ///< >= 0; 0: every core
  std::string ground;                       ///< AXIS=VALUE, or "" (sim_io/scene.hpp: parse_ground_plane)
  std::optional<double> contact_tolerance;  ///< finite, >= 0 (default: the Scene's)

  /// Throws std::invalid_argument naming the option for the first value out of range (plan options first,
  /// as PlanOptions::check says them). The one check of these values.
  void check(Naming naming = Naming::Keywords) const;
};

}  // namespace pleat
