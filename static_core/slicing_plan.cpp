#include "static_core/slicing_plan.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/geometric.hpp>
#include <mutex>
#include <numeric>
#include <stdexcept>
#include <string>

#include "static_core/mesh_validation.hpp"
#include "support/input_error.hpp"

namespace pleat {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// average_edge_length without validation (the plans validate where they are entered).
double mean_edge_length(const MeshTopology& topology, const Frame& frame) {
  double sum = 0.0;
  std::size_t count = 0;
  for (const auto& t : topology.triangles)
    for (int i = 0; i < 3; ++i) {
      sum += glm::distance(frame.positions[t[i]], frame.positions[t[(i + 1) % 3]]);
      ++count;
    }
  return count ? sum / count : 0.0;
}

/// The positions of the vertices some triangle uses, each once: the cloth that planes can cut. Isolated
/// vertices get no cone and must not stretch a plan (a stray vertex far away would multiply its planes).
std::vector<glm::dvec3> cloth_positions(const MeshTopology& topology, const Frame& frame) {
  std::vector<char> used(frame.positions.size(), 0);
  for (const auto& t : topology.triangles)
    for (Index v : t) used[v] = 1;
  std::vector<glm::dvec3> positions;
  for (std::size_t v = 0; v < used.size(); ++v)
    if (used[v]) positions.push_back(frame.positions[v]);
  return positions;
}

glm::dvec3 centroid_of(const std::vector<glm::dvec3>& positions) {
  glm::dvec3 centroid(0.0);
  for (const auto& p : positions) centroid += p;
  return centroid / static_cast<double>(std::max<std::size_t>(1, positions.size()));
}

/// Spreads unit directions taken as lines (d and -d are one family of planes) evenly: a fixed number of
/// steps of electrostatic repulsion between each direction and the nearer of the other's two ends, on the
/// sphere, each direction kept on the upper hemisphere. Deterministic. From the Fibonacci spiral's 8 lines,
/// whose closest pair is 39.0 degrees apart, to 45.0 degrees (12: 26.3 -> 36.7, 20: 17.5 -> 30.1); measured
/// more accurate than the spiral on 6 of the 8 sequences of bench/results/accuracy_budget.md at the default
/// spacing.
void relax_lines(std::vector<glm::dvec3>& dirs) {
  constexpr int kSteps = 2000;
  const std::size_t n = dirs.size();
  std::vector<glm::dvec3> force(n);
  for (int step = 0; step < kSteps; ++step) {
    for (std::size_t i = 0; i < n; ++i) {
      force[i] = glm::dvec3(0.0);
      for (std::size_t j = 0; j < n; ++j) {
        if (j == i) continue;
        const glm::dvec3 other = glm::dot(dirs[i], dirs[j]) >= 0 ? dirs[j] : -dirs[j];
        const glm::dvec3 apart = dirs[i] - other;
        const double length = glm::length(apart);
        force[i] += apart / (length * length * length);
      }
    }
    const double rate = (0.02 * (1.0 - double(step) / kSteps) + 1e-4) / double(n);
    for (std::size_t i = 0; i < n; ++i) {
      const glm::dvec3 along = force[i] - glm::dot(force[i], dirs[i]) * dirs[i];
      dirs[i] = glm::normalize(dirs[i] + rate * along);
      if (dirs[i].z < 0) dirs[i] = -dirs[i];
    }
  }
}

constexpr int kMaxRelaxed = 32;  ///< diffuse_orientations relaxes up to this many

}  // namespace

/// The paper's six orientations for 6; otherwise n directions spread over the half sphere (a Fibonacci
/// spiral on the upper hemisphere: a plane normal and its negation are the same family), relaxed by
/// relax_lines when asked and n <= kMaxRelaxed (relaxing costs n^2 per step; larger counts are left on the
/// spiral, unmeasured).
std::vector<glm::dvec3> diffuse_orientations(int n, bool relaxed) {
  if (n <= 0) throw std::invalid_argument("slicing plan: the number of orientations must be positive");
  if (n == 6)
    return {glm::normalize(glm::dvec3(1, 0, 0)), glm::normalize(glm::dvec3(0, 1, 0)),
            glm::normalize(glm::dvec3(0, 0, 1)), glm::normalize(glm::dvec3(1, 1, 0)),
            glm::normalize(glm::dvec3(1, 0, 1)), glm::normalize(glm::dvec3(0, 1, 1))};
  auto spiral = [n] {
    std::vector<glm::dvec3> dirs;
    const double golden = kPi * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < n; ++i) {
      const double z = 1.0 - (i + 0.5) / n;  // upper hemisphere
      const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
      dirs.push_back(glm::normalize(glm::dvec3(r * std::cos(golden * i), r * std::sin(golden * i), z)));
    }
    return dirs;
  };
  if (!relaxed || n > kMaxRelaxed) return spiral();
  // Relaxing is deterministic and costs about as much as slicing a small cloth: once per count and process.
  static std::array<std::once_flag, kMaxRelaxed + 1> once;
  static std::array<std::vector<glm::dvec3>, kMaxRelaxed + 1> relaxed_lines;
  std::call_once(once[n], [&] {
    relaxed_lines[n] = spiral();
    relax_lines(relaxed_lines[n]);
  });
  return relaxed_lines[n];
}

namespace {

std::pair<double, double> extent_along(const std::vector<glm::dvec3>& positions, const glm::dvec3& n) {
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& p : positions) {
    const double d = glm::dot(n, p);
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
  return {lo, hi};
}

/// The extent of a box along a unit direction: its corners' lowest and highest heights.
std::pair<double, double> extent_along(const Bounds& box, const glm::dvec3& n) {
  std::vector<glm::dvec3> corners;
  for (int c = 0; c < 8; ++c)
    corners.emplace_back(c & 1 ? box.hi.x : box.lo.x, c & 2 ? box.hi.y : box.lo.y,
                         c & 4 ? box.hi.z : box.lo.z);
  return extent_along(corners, n);
}

/// `count` planes spread evenly over the extent [lo, hi].
void add_counted_planes(SlicingPlan& plan, int orientation, double lo, double hi, int count) {
  const glm::dvec3 n = plan.orientations[orientation];
  const double step = (hi - lo) / count;
  for (int k = 0; k < count; ++k) plan.planes.push_back(make_plane(n, lo + step * (k + 0.5), orientation));
}

}  // namespace

Bounds cloth_bounds(const MeshTopology& topology, const Frame& frame) {
  Bounds box;
  for (const glm::dvec3& p : cloth_positions(topology, frame)) box.add(p);
  return box;
}

std::vector<Index> cloth_vertices(const MeshTopology& topology) {
  const Index receivers = topology.num_receivers();
  std::vector<char> used(receivers, 0);
  for (const Triangle& t : topology.triangles)
    if (t[0] < receivers)
      for (const Index v : t) used[v] = 1;
  std::vector<Index> vertices;
  for (Index v = 0; v < receivers; ++v)
    if (used[v]) vertices.push_back(v);
  return vertices;
}

namespace {

/// 2^52: lattice indices beyond it are not all distinct doubles (k + 1 == k).
constexpr double kExactLattice = 4503599627370496.0;

std::string far_lattice(const SlicingPlan& plan, double lo, double hi) {
  char text[300];
  std::snprintf(text, sizeof text,
                "the cloth lies %.6g to %.6g from the origin: planes %.6g apart cannot be told apart there "
                "(more than 2^52 spacings out); move the scene nearer the origin or use a larger --spacing",
                lo, hi, plan.spacing);
  return text;
}

/// The message of a frame whose planes would be too many: the orientation, its extent and the vertex
/// farthest from the median of the cloth's heights along it.
std::string too_many_planes(const SlicingPlan& plan, std::span<const Index> cloth, const Frame& frame, int o,
                            double planes) {
  const glm::dvec3& n = plan.orientations[static_cast<std::size_t>(o)];
  std::vector<double> height;
  for (const Index v : cloth) height.push_back(glm::dot(n, frame.positions[v]));
  std::vector<double> sorted = height;
  std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(sorted.size() / 2), sorted.end());
  const double median = sorted[sorted.size() / 2];
  std::size_t far = 0;
  for (std::size_t i = 0; i < height.size(); ++i)
    if (std::abs(height[i] - median) > std::abs(height[far] - median)) far = i;
  const auto [lo, hi] = std::minmax_element(height.begin(), height.end());
  char text[400];
  std::snprintf(
      text, sizeof text,
      "the cloth spans %.6g along orientation %d (%.3f, %.3f, %.3f) and would take %.3g planes %.6g "
      "apart (at most %zu a frame): vertex %u lies %.6g from the median of the cloth there; is the "
      "simulation exploded? (`pleat info` lists far-flung vertices per frame)",
      *hi - *lo, o, n.x, n.y, n.z, planes, plan.spacing, kMaxPlanesPerFrame, cloth[far],
      std::abs(height[far] - median));
  return text;
}

}  // namespace

void planes_for_frame(const SlicingPlan& plan, std::span<const Index> cloth, const Frame& frame,
                      std::vector<SlicingPlane>& out) {
  if (!(plan.spacing > 0)) {
    out = plan.planes;
    return;
  }
  out.clear();
  if (cloth.empty()) return;
  const std::size_t orientations = plan.orientations.size();
  // The range of k per orientation, counted before any plane is made.
  std::vector<std::array<double, 2>> range(orientations);
  double total = 0.0;
  for (std::size_t o = 0; o < orientations; ++o) {
    const glm::dvec3& n = plan.orientations[o];
    double lo = INFINITY, hi = -INFINITY;
    for (const Index v : cloth) {
      const double d = glm::dot(n, frame.positions[v]);
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
    // cover_with_planes' k for [lo, hi], and one more each side: a plane within rounding of the extreme
    // vertex's height may still cut it (the slicer decides the side exactly).
    range[o] = {std::ceil(lo / plan.spacing - 0.5) - 1.0, std::floor(hi / plan.spacing - 0.5) + 1.0};
    if (!(std::max(std::abs(range[o][0]), std::abs(range[o][1])) < kExactLattice))
      throw InputError("slicing plan", frame_place(frame), far_lattice(plan, lo, hi));
    const double planes = range[o][1] - range[o][0] + 1.0;
    if (!(planes <= double(kMaxPlanesPerFrame)) || !(total + planes <= double(kMaxPlanesPerFrame)))
      throw InputError("slicing plan", frame_place(frame),
                       too_many_planes(plan, cloth, frame, int(o), total + planes));
    total += planes;
  }
  out.reserve(static_cast<std::size_t>(total));
  for (std::size_t o = 0; o < orientations; ++o)
    for (double k = range[o][0]; k <= range[o][1]; ++k)
      out.push_back(make_plane(plan.orientations[o], (k + 0.5) * plan.spacing, static_cast<int>(o)));
}

void cover_with_planes(SlicingPlan& plan, const Bounds& cover) {
  if (!(plan.spacing > 0) || !std::isfinite(plan.spacing))
    throw std::invalid_argument("cover_with_planes: the plan's spacing must be positive and finite");
  if (cover.empty()) throw std::invalid_argument("cover_with_planes: nothing to cover");
  // Every k with lo <= (k + 1/2) * spacing <= hi: a plane at a vertex's height counts it above (the slicer's
  // perturbation), so the closed range keeps every plane that can cut. Counted before any plane is made.
  std::vector<std::array<double, 2>> range;
  double total = 0.0;
  for (const glm::dvec3& n : plan.orientations) {
    const auto [lo, hi] = extent_along(cover, n);
    const double first = std::ceil(lo / plan.spacing - 0.5), last = std::floor(hi / plan.spacing - 0.5);
    if (!(std::max(std::abs(first), std::abs(last)) < kExactLattice))
      throw InputError("slicing plan", "", far_lattice(plan, lo, hi));
    total += std::max(0.0, last - first + 1.0);
    if (!(total <= double(kMaxPlanesPerFrame))) {
      char text[300];
      std::snprintf(
          text, sizeof text,
          "planes %.6g apart over an extent of %.6g would be %.3g planes or more (at most %zu): a larger "
          "--spacing or --spacing-edges",
          plan.spacing, hi - lo, total, kMaxPlanesPerFrame);
      throw InputError("slicing plan", "", text);
    }
    range.push_back({first, last});
  }
  plan.planes.clear();
  plan.planes.reserve(static_cast<std::size_t>(total));
  for (int o = 0; o < static_cast<int>(plan.orientations.size()); ++o)
    for (double k = range[std::size_t(o)][0]; k <= range[std::size_t(o)][1]; ++k)
      plan.planes.push_back(make_plane(plan.orientations[std::size_t(o)], (k + 0.5) * plan.spacing, o));
}

SlicingPlane make_plane(const glm::dvec3& normal, double offset, int orientation) {
  SlicingPlane plane;
  plane.normal = glm::normalize(normal);
  plane.offset = offset;
  plane.orientation = orientation;
  // Deterministic in-plane frame: u is the world axis least aligned with the normal, made orthogonal.
  const glm::dvec3 a = std::abs(plane.normal.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  plane.u = glm::normalize(a - glm::dot(a, plane.normal) * plane.normal);
  plane.w = glm::cross(plane.normal, plane.u);  // (u, w, normal) right-handed
  return plane;
}

double average_edge_length(const MeshTopology& topology, const Frame& frame) {
  validate_mesh(topology, frame, "average_edge_length");
  return mean_edge_length(topology, frame);
}

SlicingPlan make_diffuse_plan(const MeshTopology& topology, const Frame& frame,
                              const DiffusePlanParams& params, const Bounds* cover) {
  validate_mesh(topology, frame, "make_diffuse_plan");
  SlicingPlan plan;
  plan.orientations = diffuse_orientations(params.orientations, params.relaxed);
  const Bounds box = cover ? *cover : cloth_bounds(topology, frame);
  if (box.empty()) return plan;  // no triangle: nothing to cut
  if (params.planes_per_orientation > 0) {
    const std::vector<glm::dvec3> cloth = cloth_positions(topology, frame);
    for (int o = 0; o < static_cast<int>(plan.orientations.size()); ++o) {
      const auto [lo, hi] =
          cover ? extent_along(*cover, plan.orientations[o]) : extent_along(cloth, plan.orientations[o]);
      add_counted_planes(plan, o, lo, hi, params.planes_per_orientation);
    }
    return plan;
  }
  plan.spacing =
      params.spacing > 0 ? params.spacing : params.spacing_in_edges * mean_edge_length(topology, frame);
  if (!(plan.spacing > 0)) plan.spacing = 1.0;
  cover_with_planes(plan, box);
  return plan;
}

SlicingPlan make_paper_plan(const MeshTopology& topology, const Frame& frame, const Bounds* cover) {
  SlicingPlan plan = make_diffuse_plan(topology, frame, {6, 0.0, 0, 1.0}, cover);
  plan.storage = ConeStorage::NearerEndpoint;
  return plan;
}

/// A pencil of planes about the line {point + s * axis}, covering the angular extent of the cloth (its
/// triangles' vertices, cloth_positions) about it with an angular step that gives `spacing` (> 0) at the
/// cloth's mean distance from the line.
static void add_pencil(SlicingPlan& plan, const glm::dvec3& point, const glm::dvec3& axis,
                       const std::vector<glm::dvec3>& cloth, double spacing) {
  glm::dvec3 e1 = centroid_of(cloth) - point;
  e1 -= glm::dot(e1, axis) * axis;
  if (glm::length(e1) == 0) e1 = make_plane(axis, 0, 0).u;
  e1 = glm::normalize(e1);
  const glm::dvec3 e2 = glm::cross(axis, e1);
  double lo = INFINITY, hi = -INFINITY, mean_distance = 0.0;
  for (const auto& p : cloth) {
    const glm::dvec3 d = p - point;
    const double angle = std::atan2(glm::dot(d, e2), glm::dot(d, e1));
    lo = std::min(lo, angle);
    hi = std::max(hi, angle);
    mean_distance += glm::length(d - glm::dot(d, axis) * axis);
  }
  mean_distance /= static_cast<double>(std::max<std::size_t>(1, cloth.size()));
  const double step = mean_distance > 0 && spacing > 0 ? spacing / mean_distance : 0.01;
  const int count = std::max(1, static_cast<int>(std::ceil((hi - lo) / step)));
  const int orientation = static_cast<int>(plan.orientations.size());
  plan.orientations.push_back(axis);
  for (int k = 0; k < count; ++k) {
    const double angle = lo + (hi - lo) * (k + 0.5) / count;
    const glm::dvec3 in_plane = std::cos(angle) * e1 + std::sin(angle) * e2;
    const glm::dvec3 normal = glm::normalize(glm::cross(axis, in_plane));  // plane contains the line
    plan.planes.push_back(make_plane(normal, glm::dot(normal, point), orientation));
  }
}

SlicingPlan make_point_light_plan(const MeshTopology& topology, const Frame& frame, const glm::dvec3& light,
                                  double spacing) {
  validate_mesh(topology, frame, "make_point_light_plan");
  // Any line through the light will do (paper §2.1): take one perpendicular to the light->cloth direction.
  const std::vector<glm::dvec3> cloth = cloth_positions(topology, frame);
  glm::dvec3 to_cloth = centroid_of(cloth) - light;
  to_cloth = glm::length(to_cloth) > 0 ? glm::normalize(to_cloth) : glm::dvec3(0, 0, -1);
  if (!(spacing > 0)) spacing = mean_edge_length(topology, frame);
  SlicingPlan plan;
  add_pencil(plan, light, make_plane(to_cloth, 0, 0).u, cloth, spacing);
  return plan;
}

SlicingPlan make_area_light_plan(const MeshTopology& topology, const Frame& frame,
                                 const std::vector<glm::dvec3>& light_polygon, double spacing) {
  validate_mesh(topology, frame, "make_area_light_plan");
  if (light_polygon.size() < 3) throw std::invalid_argument("area light: a polygon needs 3 or more vertices");
  // Planes rotate about lines joining opposite points of the light's hull (paper §2.1): vertex i and
  // vertex i + n/2, one pencil (one orientation family) per line.
  const std::vector<glm::dvec3> cloth = cloth_positions(topology, frame);
  if (!(spacing > 0)) spacing = mean_edge_length(topology, frame);
  SlicingPlan plan;
  const std::size_t n = light_polygon.size();
  for (std::size_t i = 0; i < std::max<std::size_t>(1, n / 2); ++i) {
    const glm::dvec3 a = light_polygon[i], b = light_polygon[(i + n / 2) % n];
    add_pencil(plan, 0.5 * (a + b), glm::normalize(b - a), cloth, spacing);
  }
  return plan;
}

}  // namespace pleat
