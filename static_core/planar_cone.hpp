// One stored 2D cone as the 3D assembly reads it (cone_assembly.hpp, internal/nearest_circle.hpp): a slice
// vertex's wedges in its plane's (u, w) frame, with the horizon's great circles where known (docs/method.md
// §7-§8). A view: the wedges and tangents belong to the caller.
#pragma once

#include <span>

#include "static_core/angular_set.hpp"
#include "static_core/slicing_plan.hpp"

namespace pleat {

/// One stored 2D cone: the wedges of a slice vertex's cone, in its plane's (u, w) frame.
struct PlanarCone {
  const SlicingPlane* plane = nullptr;
  std::span<const Wedge> wedges;
  /// Where known, the horizon's great circle at wedge ends (aim_wedges): the pieces follow it between ends.
  std::span<const HorizonTangent> tangents = {};
};

}  // namespace pleat
