// Cloth in contact with its scene (docs/method.md §6.2): which cloth vertices lie deeper than the scene's
// contact tolerance (MeshTopology::contact_tolerance) inside a ground plane's solid or a closed occluder.
//
// The engines take every cloth point inside an occluder as lying on its surface (occluder_shadows.hpp,
// OccludingPlane), so that cloth resting on or sunk into a collider is never inverted; this check only counts
// the vertices sunk deeper than the tolerance, for --stats and a warning. An occluder is closed where every
// edge of its connected part joins exactly two of its triangles (a body, a box, a sphere); open parts (a
// plane mesh) have no inside.
// Cost per frame: O(cloth vertices x planes); for closed occluders an AABB tree of their triangles (rebuilt
// when they moved), a distance query per cloth vertex in their box shrunk by the tolerance, and an inside
// test (exact predicates) for those farther than it from the surface. Thread safety: check() mutates the kept
// tree; one ContactCheck per thread.
#pragma once

#include <memory>

#include "static_core/mesh.hpp"
#include "static_core/visibility_cone.hpp"

namespace pleat {

class ContactCheck {
 public:
  /// Finds the closed occluder parts of `topology`, which must outlive the check.
  explicit ContactCheck(const MeshTopology& topology);
  ~ContactCheck();
  ContactCheck(ContactCheck&&) noexcept;
  ContactCheck& operator=(ContactCheck&&) noexcept;

  /// Writes stats.penetrating_vertices, deepest_penetration and deepest_vertex for `frame` (all the
  /// topology's vertices, valid).
  void check(const Frame& frame, VisibilityStats& stats);

 private:
  struct Impl;
  std::unique_ptr<Impl> m_impl;
};

}  // namespace pleat
