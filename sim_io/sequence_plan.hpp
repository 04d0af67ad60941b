// The slicing plan of a whole sequence, from the options `pleat visibility` takes (--orientations,
// --spacing, --spacing-edges, --planes, --adaptive, --max-missing, --cone-storage, --cone-reconstruction,
// --paper, --plan), the same
// for the command line and the Python module (docs/method.md §2). The plan is made once for the whole
// sequence, never from the frames a run computes: orientations and spacing from the sequence's first frame,
// the world-anchored lattice of planes over the box of all its frames (MeshSequence::bounds), so a frame's
// result is the same from any range, chunk or rank count.
#pragma once

#include <optional>
#include <string>

#include "sim_io/mesh_sequence.hpp"
#include "static_core/slicing_plan.hpp"

namespace pleat {

struct PlanOptions {
  int orientations = DiffusePlanParams{}.orientations;  ///< 1..1000
  std::optional<double> spacing;                        ///< finite, > 0: distance between parallel planes
  std::optional<double> spacing_edges;  ///< finite, > 0: spacing in average edge lengths of the first frame
  std::optional<int> planes_per_orientation;  ///< >= 1
  bool adaptive = false;
  double max_missing = 0.05;               ///< with adaptive, in [0, 1]
  std::string storage = "aimed-on-fan";    ///< a storage rule's name (static_core/cone_rules.hpp)
  std::string reconstruction = "grouped";  ///< a reconstruction rule's name
  bool paper = false;
  std::string plan_file;  ///< read the plan from this file (--save-plan) instead; excludes the others

  /// How errors name the options: as the Python module's keywords (spacing_edges) or as the command line's
  /// options (--spacing-edges).
  enum class Naming { Keywords, CommandLine };
  /// Throws std::invalid_argument naming the option for a value out of range (a spacing that is not a
  /// finite number > 0, planes < 1, ...) or options that exclude each other. The one check of these values:
  /// the command line runs it on each option as it is parsed, the Python module on its keywords.
  void check(Naming naming = Naming::Keywords) const;
  /// The plan for `sequence` (from plan_file, or made from its first frame and bounds). Throws InputError
  /// for a bad plan file, and std::invalid_argument naming the option (or the plan file) and the input when
  /// the plan's spacing is wider than the cloth: wider than the first frame's extent along every
  /// orientation, so that no plane might cut it and every A would be 0 (with a spacing up to that extent,
  /// at least one plane cuts the first frame); InputError naming the input for a plan its cloth cannot have
  /// (planes too many for its extent).
  SlicingPlan make(const MeshSequence& sequence, Naming naming = Naming::Keywords) const;
  /// One line saying what the options ask for (for reports and a checkpoint's job key).
  std::string describe() const;

 private:
  /// Throws (make's) when the plan's lattice spacing is wider than the cloth of `frame`.
  void check_spacing_cuts(const SlicingPlan& plan, const MeshTopology& topology, const Frame& frame,
                          const std::string& input, Naming naming) const;
};

}  // namespace pleat
