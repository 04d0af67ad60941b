// Slicing plans (Stewart 1999 §2.1, §2.3.3; docs/method.md §2): which planes cut the cloth.
//
// A plan is a plain value made once for a whole sequence and reused for every frame: the kinetic layer keeps
// the planes fixed in space while the cloth moves through them. So that a frame's result never depends on
// which frames were asked for, a diffuse plan is a *lattice anchored in world space*: per orientation the
// planes at offsets (k + 1/2) * spacing for every integer k, with the orientations and the spacing taken
// from one planned frame (the sequence's first) and the planes instantiated over a box that covers every
// frame (cover_with_planes). A plane that cuts no frame adds an empty slice and changes no cone. Every
// function below that takes (topology, frame) validates them (static_core/mesh_validation.hpp: InputError).
// Thread safety: plans are plain values; the functions are pure.
#pragma once

#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <span>
#include <string_view>
#include <vector>

#include "static_core/mesh.hpp"

namespace pleat {

/// The plane {x : dot(normal, x) == offset}; (u, w, normal) is a right-handed orthonormal frame, and a
/// slice point x has 2D coordinates (dot(u, x), dot(w, x)).
struct SlicingPlane {
  glm::dvec3 normal{0, 0, 1};
  double offset = 0.0;
  glm::dvec3 u{1, 0, 0};
  glm::dvec3 w{0, 1, 0};
  int orientation =
      0;  ///< index into SlicingPlan::orientations (cones are grouped and filled per orientation)
};

/// How a plane's 2D cones reach mesh vertices (docs/method.md §7): the id of a storage rule, its row in
/// cone_storage_rules() (static_core/cone_rules.hpp; each rule's file says what it does). The enumerators
/// name the built-in rows for code that asks for one; a new rule needs none.
enum class ConeStorage : std::uint8_t {
  NearerEndpoint,     ///< the paper's (static_core/rules/nearer_endpoint.cpp)
  NearestOnFan,       ///< static_core/rules/nearest_on_fan.cpp
  InterpolatedOnFan,  ///< static_core/rules/interpolated_on_fan.cpp
  AimedOnFan,         ///< static_core/rules/aimed_on_fan.cpp
};

/// How a vertex's 2D cones become its 3D cone (docs/method.md §8): the id of a reconstruction rule, its row
/// in cone_reconstruction_rules() (static_core/cone_rules.hpp), named as ConeStorage's.
enum class ConeReconstruction : std::uint8_t {
  Grouped,        ///< the paper's (static_core/cone_assembly.cpp)
  NearestCircle,  ///< static_core/nearest_circle.cpp
};

struct SlicingPlan {
  std::vector<glm::dvec3> orientations;  ///< unit normals, one per family of planes
  std::vector<SlicingPlane> planes;
  ConeStorage storage = ConeStorage::AimedOnFan;
  ConeReconstruction reconstruction = ConeReconstruction::Grouped;
  /// > 0: the planes are the world-anchored lattice of this spacing (cover_with_planes), so a plan is
  /// (orientations, spacing, storage) plus the box it covers; 0: the planes were placed one by one (adaptive,
  /// counted, light plans) and are the plan.
  double spacing = 0.0;
};

/// The most planes one frame may take (planes_for_frame): a thousand times a 300k-vertex cloth's. More means
/// a frame whose cloth spans far more than its edges can account for (an exploded simulation, a stray
/// vertex), and a clear error instead of the memory it would take.
inline constexpr std::size_t kMaxPlanesPerFrame = 1'000'000;

/// The vertices the cloth's triangles use (below MeshTopology::num_receivers): what a frame's planes cover.
std::vector<Index> cloth_vertices(const MeshTopology& topology);

/// The planes that cut `frame`: for a lattice plan (spacing > 0) the lattice planes within the extent of the
/// `cloth` vertices (cloth_vertices) along each orientation, and one more on each side (beyond the rounding
/// of a dot product), ordered by orientation, then offset — a plane beyond the cloth offers no cone, so a
/// frame costs what its own cloth spans, and its result does not depend on other frames; for any other plan,
/// plan.planes. The offsets are those of cover_with_planes, bit for bit. Throws InputError before allocating
/// when they would be more than kMaxPlanesPerFrame, naming the orientation, the extent and the vertex
/// farthest from the cloth's median. O(cloth x orientations + planes).
void planes_for_frame(const SlicingPlan& plan, std::span<const Index> cloth, const Frame& frame,
                      std::vector<SlicingPlane>& out);

/// Replaces plan.planes by the lattice planes of every orientation that meet `cover`: offsets
/// (k + 1/2) * plan.spacing, k integer, within the box's extent along the orientation, ordered by
/// orientation, then offset. Precondition: plan.spacing > 0 and finite, cover not empty (else
/// std::invalid_argument). Throws InputError before allocating when they would be more than
/// kMaxPlanesPerFrame or too far out to tell apart. O(planes).
void cover_with_planes(SlicingPlan& plan, const Bounds& cover);

/// The box of the vertices the triangles use (isolated vertices do not stretch a plan).
Bounds cloth_bounds(const MeshTopology& topology, const Frame& frame);

/// The rule's name in its table (static_core/cone_rules.hpp).
const char* cone_storage_name(ConeStorage storage);
/// The rule of a name in the table; throws std::invalid_argument naming the table's names for any other.
ConeStorage cone_storage_from_name(std::string_view name);

/// The rule's name in its table (static_core/cone_rules.hpp).
const char* cone_reconstruction_name(ConeReconstruction reconstruction);
/// The rule of a name in the table; throws std::invalid_argument naming the table's names for any other.
ConeReconstruction cone_reconstruction_from_name(std::string_view name);

/// The plane {x : dot(normal, x) = offset} of unit normal `normal`, in the plan's orientation `orientation`,
/// with a deterministic in-plane frame (u, w).
SlicingPlane make_plane(const glm::dvec3& normal, double offset, int orientation);

struct DiffusePlanParams {
  /// 6: the paper's (1,0,0),(0,1,0),(0,0,1),(1,1,0),(1,0,1),(0,1,1); other counts spread over the hemisphere.
  /// Default 8 spread: measured more accurate per unit cost than the paper's six, whose axis-aligned planes
  /// cut cloth lying parallel to an axis plane (a pile on the ground) badly
  /// (bench/results/accuracy_budget.md).
  int orientations = 8;
  double spacing = 0.0;  ///< distance between parallel planes; 0: spacing_in_edges average edge lengths
  int planes_per_orientation = 0;  ///< if > 0, overrides spacing
  /// The default spacing in average edge lengths: 1/2, the widest that keeps every measured sequence's mean
  /// error within 0.02 of ray-traced truth (bench/results/accuracy_budget.md: at 3/4 edge the rucked sleeve
  /// and the generated sleeve are above it; denser spacing buys more per unit cost than more orientations).
  double spacing_in_edges = 0.5;
  /// Spread orientations (not 6) relaxed from the Fibonacci spiral to evenly spaced lines (up to 32).
  bool relaxed = true;
};
/// The orientations of a diffuse plan (DiffusePlanParams::orientations and relaxed): the paper's six for 6,
/// else n lines spread over the half sphere. Throws std::invalid_argument for n <= 0. Deterministic.
std::vector<glm::dvec3> diffuse_orientations(int n, bool relaxed);
/// Uniform diffuse light: parallel families of planes, the spacing measured on `frame`. With a spacing, the
/// world-anchored lattice (cover_with_planes) over `cover`, or over the cloth of `frame` (cloth_bounds) when
/// `cover` is null; with planes_per_orientation, that many planes spread evenly over the extent of `cover`
/// (or of the cloth) along each orientation (plan.spacing 0).
SlicingPlan make_diffuse_plan(const MeshTopology& topology, const Frame& frame,
                              const DiffusePlanParams& params, const Bounds* cover = nullptr);
/// The paper's plan: its 6 axis-aligned orientations, planes one average edge length apart, nearer-endpoint
/// storage (the baseline pleat's defaults are measured against).
SlicingPlan make_paper_plan(const MeshTopology& topology, const Frame& frame, const Bounds* cover = nullptr);

/// Point light: a pencil of planes through one line through the light (spacing ~ average edge length at
/// the cloth's distance).
SlicingPlan make_point_light_plan(const MeshTopology& topology, const Frame& frame, const glm::dvec3& light,
                                  double spacing = 0.0);

/// Polygonal area light: planes rotating about lines joining opposite points of the light's convex hull.
SlicingPlan make_area_light_plan(const MeshTopology& topology, const Frame& frame,
                                 const std::vector<glm::dvec3>& light_polygon, double spacing = 0.0);

/// Average length of the mesh's edges in this frame.
double average_edge_length(const MeshTopology& topology, const Frame& frame);

}  // namespace pleat
