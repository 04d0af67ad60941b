// The slicing plan of a whole sequence, from the options `pleat visibility` takes (--orientations,
// --spacing, --spacing-edges, --planes, --adaptive, --max-missing, --cone-storage, --paper, --plan), the same
// for the command line and the Python module (docs/method.md §2). The plan is made once for the whole
// sequence, never from the frames a run computes: orientations and spacing from the sequence's first frame,
// the world-anchored lattice of planes over the box of all its frames (MeshSequence::bounds), so a frame's
// result is the same from any range, chunk or rank count.
#pragma once

#include <string>

#include "sim_io/mesh_sequence.hpp"
#include "static_core/slicing_plan.hpp"

namespace pleat {

struct PlanOptions {
  int orientations = DiffusePlanParams{}.orientations;  ///< 1..1000
  double spacing = 0.0;                                 ///< > 0: distance between parallel planes
  double spacing_edges = 0.0;  ///< > 0: spacing in average edge lengths of the first frame
  int planes_per_orientation = 0;
  bool adaptive = false;
  double max_missing = 0.05;  ///< with adaptive, in [0, 1]
  std::string storage = "aimed-on-fan";
  bool paper = false;
  std::string plan_file;  ///< read the plan from this file (--save-plan) instead; excludes the others

  /// Throws std::invalid_argument naming the option (as on the command line) for a value out of range or
  /// options that exclude each other. (The command line checks the same with its parser.)
  void check() const;
  /// The plan for `sequence` (from plan_file, or made from its first frame and bounds). Throws InputError
  /// for a bad plan file.
  SlicingPlan make(const MeshSequence& sequence) const;
  /// One line saying what the options ask for (for reports and a checkpoint's job key).
  std::string describe() const;
};

}  // namespace pleat
