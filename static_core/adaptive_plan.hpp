// The adaptive slicing plan (Stewart 1999 §2.3.3; docs/method.md §2): planes placed one by one where vertices
// still lack a cone, by a recursive median split per orientation, on one frame.
// Preconditions: the frame is the topology's (validated: InputError). Cost: per orientation, O(V log V) for
// the splits plus one cone_recipients pass (O(F)) per plane placed. Thread safety: a pure function.
#pragma once

#include "static_core/mesh.hpp"
#include "static_core/slicing_plan.hpp"

namespace pleat {

struct AdaptivePlanParams {
  int orientations = 6;
  double max_missing_fraction = 0.05;  ///< stop when at most this fraction of vertices lacks a cone
  bool relaxed = true;                 ///< as DiffusePlanParams::relaxed
};
/// The paper's §2.3.3 placement: per orientation, a plane through the median vertex, then recursively
/// through the medians of the vertices above and below that still lack a cone.
SlicingPlan make_adaptive_plan(const MeshTopology& topology, const Frame& frame,
                               const AdaptivePlanParams& params);

}  // namespace pleat
