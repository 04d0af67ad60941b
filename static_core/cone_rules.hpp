// The rules a slicing plan names (docs/method.md §7, §8): how a plane's 2D cones reach mesh vertices (the
// storage rule) and how a vertex's 2D cones become its 3D cone (the reconstruction rule). Each rule is a unit
// of its own in one file (static_core/rules/*.cpp, the nearest-circle rule in nearest_circle.cpp) and one row
// of its table (static_core/rules/rule_tables.cpp); the command line, the plan file, the checks and the
// Python module read the names from the tables. A rule's id (ConeStorage, ConeReconstruction) is its row.
// Thread safety: the tables are immutable; a ConeReconstructor is one thread's.
#pragma once

#include <glm/vec3.hpp>
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "static_core/slicing_plan.hpp"
#include "static_core/visibility_cone.hpp"

namespace pleat {

struct PlanarCone;

/// A storage rule: the choices the engines' steps make for it (offer_plane_cones, FrameAssembler). Cost: the
/// rule is read once per plane and once per frame, never per cut.
struct ConeStorageRule {
  std::string_view name;     ///< as the command line, the plan file and the Python module spell it
  std::string_view summary;  ///< what it does, for --help
  /// Which endpoints of a cut edge are offered the slice vertex's cone.
  enum class Offer { NearerEndpoint, BothEndpoints } offer;
  /// Which offers a vertex keeps per side and orientation: every plane's nearest, the nearest over the
  /// orientation, or the nearest from a plane below the vertex and the nearest from one above it.
  enum class Keep { EveryPlane, Nearest, NearestBelowAndAbove } keep;
  /// With NearestBelowAndAbove, how the two cones become one at the vertex's height: not at all (both kept),
  /// blended wedge angles (blend_wedges), or blended horizon points aimed at from the vertex (aim_wedges).
  enum class Combine { None, Blend, Aim } combine;
  /// Whether a vertex's own cones are those of its fan from every cut of its edges (fan_cone.hpp).
  bool fan_cones;
};

/// The per-thread state of one reconstruction rule (its memory reused from call to call).
class ConeReconstructor {
 public:
  virtual ~ConeReconstructor() = default;
  /// The 3D cone of a vertex on the side `side_normal` (unit) from its 2D `cones`, clipped to the
  /// half-spaces {d : d·h >= 0} of `half_spaces`, into `result` (memory reused); its measures into
  /// `measures` when not null (as measure_cone gives them).
  virtual void assemble(std::span<const PlanarCone> cones, const glm::dvec3& side_normal,
                        std::span<const glm::dvec3> half_spaces, VisibilityCone& result,
                        ConeMeasures* measures) = 0;
};

/// A reconstruction rule: its name and how to make one thread's reconstructor.
struct ConeReconstructionRule {
  std::string_view name;     ///< as the command line, the plan file and the Python module spell it
  std::string_view summary;  ///< what it does, for --help
  std::unique_ptr<ConeReconstructor> (*make)();
};

/// The tables, one row per rule; row i is the rule of id i.
std::span<const ConeStorageRule* const> cone_storage_rules();
std::span<const ConeReconstructionRule* const> cone_reconstruction_rules();

/// The row of an id (precondition: an id of a row; std::invalid_argument otherwise).
const ConeStorageRule& cone_storage_rule(ConeStorage storage);
const ConeReconstructionRule& cone_reconstruction_rule(ConeReconstruction reconstruction);

/// The names of a table in its order, "a, b or c" (for messages).
std::string cone_storage_names();
std::string cone_reconstruction_names();

}  // namespace pleat
