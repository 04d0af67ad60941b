// How 2D cones reach mesh vertices (SlicingPlan::storage, static_core/frame_assembly): store_cones against a
// brute-force choice per plane, and the engine's 3D cones under NearestOnFan against 3D cones assembled from
// a brute-force choice over all planes of each orientation, on generated cloth of every kind and random
// frames; the fill (nearest_sources) against all-pairs shortest paths.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>
#include <map>
#include <vector>

#include "oracles/test_meshes.hpp"
#include "sim_io/cloth_generators.hpp"
#include "static_core/cone_assembly.hpp"
#include "static_core/internal/frame_assembly.hpp"
#include "static_core/internal/slice_cones.hpp"
#include "static_core/internal/slice_triangulation.hpp"
#include "static_core/mesh_connectivity.hpp"
#include "static_core/mesh_slicer.hpp"
#include "static_core/visibility.hpp"

namespace pleat {
namespace {

/// Distance from mesh vertex v to slice vertex x, computed from the 3D slice point (independently of
/// SliceVertex::distance).
double distance_to(const Frame& frame, const SliceVertex& x, Index v) {
  const glm::dvec3 a = frame.positions[x.above], b = frame.positions[x.below];
  return glm::distance(frame.positions[v], a + x.t * (b - a));
}

struct Planes {
  std::vector<Slice> slices;
  std::vector<SliceCones> cones;
};

Planes slice_all(const MeshTopology& topology, const Frame& frame, const SlicingPlan& plan) {
  const MeshConnectivity connectivity(topology);
  const auto faces = candidate_faces_per_plane(topology, frame, plan);
  Planes out;
  out.slices.resize(plan.planes.size());
  out.cones.resize(plan.planes.size());
  SlicerScratch slicer;
  SliceTriangulation triangulation;
  SliceConeScratch scratch;
  for (std::size_t p = 0; p < plan.planes.size(); ++p) {
    slice_mesh(topology, connectivity, frame, plan.planes[p], faces[p], slicer, out.slices[p]);
    triangulation.build(out.slices[p]);
    compute_slice_cones(out.slices[p], triangulation, scratch, out.cones[p]);
  }
  return out;
}

/// A random generated cloth (6-13 quads a side) at a random frame, its diffuse plan under `storage`, the
/// engine's result and every plane's slice and 2D cones: the setting of the storage rules' properties.
struct StorageCase {
  explicit StorageCase(ConeStorage storage)
      : cloth(*rc::gen::element(ClothKind::Curtain, ClothKind::Roll, ClothKind::Flag, ClothKind::Sleeve),
              {*rc::gen::inRange(6, 14), 12, 24.0, 0}),
        frame(cloth.frame(*rc::gen::inRange<std::size_t>(0, 12))),
        plan(make_diffuse_plan(cloth.topology(), frame, {*rc::gen::element(6, 8), 0.0, 0})) {
    plan.storage = storage;
    vis = compute_visibility(cloth.topology(), frame, plan, {false});
    planes = slice_all(cloth.topology(), frame, plan);
  }
  const ClothGenerator cloth;
  const Frame frame;
  SlicingPlan plan;
  FrameVisibility vis;
  Planes planes;
};

/// A brute force's pick: the cut (plane, slice vertex x) at `distance` from the mesh vertex.
struct Choice {
  double distance = std::numeric_limits<double>::infinity();
  std::size_t plane = 0;
  Index x = 0;
};

/// The engine's measures of a cone equal those of the brute force's assembly.
void assert_same_measures(const ConeMeasures& m, const ConeMeasures& e) {
  RC_ASSERT(std::abs(m.sky_visibility - e.sky_visibility) <= 1e-12);
  RC_ASSERT(std::abs(m.solid_angle - e.solid_angle) <= 1e-9);
  RC_ASSERT(glm::length(m.bent_normal - e.bent_normal) <= 1e-9);
}

RC_GTEST_PROP(ConeStorage, StoreConesPicksTheNearestOffer, ()) {
  const ClothKind kind =
      *rc::gen::element(ClothKind::Curtain, ClothKind::Roll, ClothKind::Flag, ClothKind::Sleeve);
  const ClothGenerator cloth(kind, {*rc::gen::inRange(6, 16), 12, 24.0, 0});
  const Frame frame = cloth.frame(*rc::gen::inRange<std::size_t>(0, 12));
  const MeshTopology& topology = cloth.topology();
  const SlicingPlan plan = make_diffuse_plan(topology, frame, {*rc::gen::element(6, 8), 0.0, 0});
  const Planes planes = slice_all(topology, frame, plan);
  std::vector<std::int64_t> best;
  std::vector<StoredCone> stored;
  for (ConeStorage storage : {ConeStorage::NearerEndpoint, ConeStorage::NearestOnFan})
    for (const Slice& slice : planes.slices) {
      store_cones(topology.num_vertices, storage, frame, slice, stored, best);
      // Brute force: per vertex, the offers it may receive, and the nearest one.
      std::map<Index, double> nearest;
      for (const SliceVertex& x : slice.vertices)
        for (Index v : {x.above, x.below}) {
          if (storage == ConeStorage::NearerEndpoint && v != x.nearer) continue;
          const double d = distance_to(frame, x, v);
          auto [it, fresh] = nearest.emplace(v, d);
          if (!fresh) it->second = std::min(it->second, d);
        }
      RC_ASSERT(stored.size() == 2 * nearest.size());  // one per vertex and side
      for (const StoredCone& s : stored) {
        RC_ASSERT(nearest.count(s.vertex) == 1u);
        const SliceVertex& x = slice.vertices[s.slice_vertex];
        RC_ASSERT(x.above == s.vertex || x.below == s.vertex);
        const double scale = 1e-12 * (1.0 + nearest[s.vertex]);
        RC_ASSERT(std::abs(distance_to(frame, x, s.vertex) - s.distance) <= scale);
        RC_ASSERT(std::abs(s.distance - nearest[s.vertex]) <= scale);
      }
      for (std::int64_t b : best) RC_ASSERT(b == -1);  // scratch left clean
    }
}

RC_GTEST_PROP(ConeStorage, NearestOnFanAssemblesTheNearestCutPerOrientation, ()) {
  const StorageCase sc(ConeStorage::NearestOnFan);
  const auto& [cloth, frame, plan, vis, planes] = sc;
  const MeshTopology& topology = cloth.topology();
  // Brute force over all planes of an orientation: the slice vertex on the vertex's own edges nearest to it
  // (ties: the lower plane, then the lower slice vertex). Distances by the engine's formula (t times the edge
  // length), so that near-ties are decided on the same numbers: this checks the choice, the test above the
  // distances.
  const std::size_t n = topology.num_vertices, orientations = plan.orientations.size();
  std::vector<Choice> choice(n * orientations);
  for (std::size_t p = 0; p < plan.planes.size(); ++p)
    for (Index x = 0; x < planes.slices[p].vertices.size(); ++x) {
      const SliceVertex& sv = planes.slices[p].vertices[x];
      for (Index v : {sv.above, sv.below}) {
        Choice& c = choice[v * orientations + std::size_t(plan.planes[p].orientation)];
        const double length = glm::distance(frame.positions[sv.above], frame.positions[sv.below]);
        const double d = (v == sv.above ? sv.t : 1.0 - sv.t) * length;
        if (d < c.distance) c = {d, p, x};
      }
    }
  std::size_t checked = 0;
  for (Index v = 0; v < n; ++v) {
    bool complete = true;  // vertices that borrow in some orientation are the fill's business
    for (std::size_t o = 0; o < orientations; ++o)
      complete &= std::isfinite(choice[v * orientations + o].distance);
    if (!complete) continue;
    for (Side side : kBothSides) {
      std::vector<PlanarCone> cones;
      for (std::size_t o = 0; o < orientations; ++o) {
        const Choice& c = choice[v * orientations + o];
        cones.push_back({&plan.planes[c.plane], planes.cones[c.plane].cone(c.x, side)});
      }
      const glm::dvec3 side_normal = side_sign(side) * vis.normals[v];
      const ConeMeasures m = measure_cone(assemble_cone(cones, side_normal), side_normal);
      // (The engine measures pieces from the assembly's own integrals: assemble_and_measure_cone.)
      assert_same_measures(m, vis.measure(side, v));
    }
    ++checked;
  }
  RC_TAG(checked * 4 > n ? "most vertices have a cut in every orientation" : "many vertices borrow");
  RC_ASSERT(checked > 0u);
}

RC_GTEST_PROP(ConeStorage, InterpolatedOnFanAssemblesTheBlendOfTheCutsBelowAndAbove, ()) {
  const StorageCase sc(ConeStorage::InterpolatedOnFan);
  const auto& [cloth, frame, plan, vis, planes] = sc;
  const MeshTopology& topology = cloth.topology();
  // Brute force over all planes of an orientation: the cut of the vertex's own edges nearest to it among
  // planes below it ([0], the vertex is its edge's `above` end) and among planes above it ([1]).
  const std::size_t n = topology.num_vertices, orientations = plan.orientations.size();
  std::vector<std::array<Choice, 2>> choice(n * orientations);
  for (std::size_t p = 0; p < plan.planes.size(); ++p)
    for (Index x = 0; x < planes.slices[p].vertices.size(); ++x) {
      const SliceVertex& sv = planes.slices[p].vertices[x];
      for (Index v : {sv.above, sv.below}) {
        Choice& c = choice[v * orientations + std::size_t(plan.planes[p].orientation)][v == sv.above ? 0 : 1];
        const double length = glm::distance(frame.positions[sv.above], frame.positions[sv.below]);
        const double d = (v == sv.above ? sv.t : 1.0 - sv.t) * length;
        if (d < c.distance) c = {d, p, x};
      }
    }
  std::size_t checked = 0, blended = 0;
  WedgeScratch scratch;
  for (Index v = 0; v < n; ++v) {
    bool complete = true;  // vertices that borrow in some orientation are the fill's business
    for (std::size_t o = 0; o < orientations; ++o)
      complete &= std::isfinite(choice[v * orientations + o][0].distance) ||
                  std::isfinite(choice[v * orientations + o][1].distance);
    if (!complete) continue;
    for (Side side : kBothSides) {
      std::vector<std::vector<Wedge>> blends(orientations);
      std::vector<PlanarCone> cones;
      for (std::size_t o = 0; o < orientations; ++o) {
        const auto& [below, above] = choice[v * orientations + o];
        auto cone = [&](const Choice& c) { return planes.cones[c.plane].cone(c.x, side); };
        if (!std::isfinite(below.distance) || !std::isfinite(above.distance)) {
          const Choice& c = std::isfinite(below.distance) ? below : above;
          cones.push_back({&plan.planes[c.plane], cone(c)});
          continue;
        }
        const SlicingPlane &lo = plan.planes[below.plane], &hi = plan.planes[above.plane];
        RC_ASSERT(hi.offset > lo.offset);
        // The slicer decides exactly which side of a plane the vertex is on; its height, in doubles, may
        // round onto the plane, so the weight is clamped.
        const double height = glm::dot(lo.normal, frame.positions[v]);
        RC_ASSERT(height >= lo.offset - 1e-12 * (1 + std::abs(lo.offset)));
        RC_ASSERT(height <= hi.offset + 1e-12 * (1 + std::abs(hi.offset)));
        const double t = std::clamp((height - lo.offset) / (hi.offset - lo.offset), 0.0, 1.0);
        if (blend_wedges(cone(below), cone(above), t, scratch, blends[o])) {
          cones.push_back({&lo, blends[o]});
          ++blended;
        } else {
          const Choice& c = t <= 0.5 ? below : above;
          cones.push_back({&plan.planes[c.plane], cone(c)});
        }
      }
      const glm::dvec3 side_normal = side_sign(side) * vis.normals[v];
      const ConeMeasures m = measure_cone(assemble_cone(cones, side_normal), side_normal);
      assert_same_measures(m, vis.measure(side, v));
    }
    ++checked;
  }
  RC_TAG(blended * 2 > checked * orientations ? "most cones blended" : "few cones blended");
  RC_ASSERT(checked > 0u);
  RC_ASSERT(blended > 0u);
}

RC_GTEST_PROP(ConeStorage, InterpolatedOnFanTakesTheNearerCutWherePlanesAreNotParallel, ()) {
  // A point light's planes form a pencil: no two cuts of an orientation are parallel, so none is blended and
  // each key keeps the nearer of its cuts below and above the vertex, which is the nearest cut.
  const ClothGenerator cloth(*rc::gen::element(ClothKind::Curtain, ClothKind::Roll, ClothKind::Flag),
                             {*rc::gen::inRange(6, 12), 12, 24.0, 0});
  const Frame frame = cloth.frame(*rc::gen::inRange<std::size_t>(0, 12));
  const glm::dvec3 light(*rc::gen::inRange(-3, 4), *rc::gen::inRange(-3, 4), *rc::gen::inRange(3, 6));
  SlicingPlan plan = make_point_light_plan(cloth.topology(), frame, light);
  plan.storage = ConeStorage::InterpolatedOnFan;
  const FrameVisibility interpolated = compute_visibility(cloth.topology(), frame, plan, {false});
  plan.storage = ConeStorage::NearestOnFan;
  const FrameVisibility nearest = compute_visibility(cloth.topology(), frame, plan, {false});
  std::size_t wedges = 0;
  for (int side = 0; side < 2; ++side)
    for (std::size_t v = 0; v < interpolated.cones[side].size(); ++v) {
      const VisibilityCone &a = interpolated.cones[side][v], &b = nearest.cones[side][v];
      RC_ASSERT(a.pieces.size() == b.pieces.size());
      for (std::size_t i = 0; i < a.pieces.size(); ++i) RC_ASSERT(a.pieces[i] == b.pieces[i]);
      wedges += a.pieces.size();
      assert_same_measures(interpolated.measures[side][v], nearest.measures[side][v]);
    }
  RC_ASSERT(wedges > 0u);
}

/// The fill's oracle: all-pairs shortest paths (Floyd-Warshall), then per vertex the lowest-indexed source
/// among the nearest.
std::vector<std::int32_t> nearest_sources_by_all_pairs(const MeshConnectivity& connectivity,
                                                       const std::vector<double>& length,
                                                       const std::vector<char>& own) {
  const std::size_t n = connectivity.num_vertices();
  std::vector<double> d(n * n, INFINITY);
  for (std::size_t v = 0; v < n; ++v) d[v * n + v] = 0;
  for (std::size_t e = 0; e < length.size(); ++e) {
    const auto [a, b] = connectivity.endpoints()[e];
    d[a * n + b] = d[b * n + a] = std::min(d[a * n + b], length[e]);
  }
  for (std::size_t k = 0; k < n; ++k)
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = 0; j < n; ++j) d[i * n + j] = std::min(d[i * n + j], d[i * n + k] + d[k * n + j]);
  std::vector<std::int32_t> src(n, -1);
  for (std::size_t v = 0; v < n; ++v)
    for (std::size_t s = 0; s < n; ++s)
      if (own[s] && d[v * n + s] < INFINITY && (src[v] < 0 || d[v * n + s] < d[v * n + std::size_t(src[v])]))
        src[v] = std::int32_t(s);
  return src;
}

RC_GTEST_PROP(ConeStorage, FillTakesTheNearestSourceAlongEdgesLowestIndexOnTies, ()) {
  // Small whole-number lengths (0 included) make every path length exact, so ties are real ties.
  const int nx = *rc::gen::inRange(1, 8), ny = *rc::gen::inRange(1, 8);
  MeshTopology topology = test::flat_sheet(nx + 1, ny + 1).topology;
  const int removed = *rc::gen::inRange(0, int(topology.triangles.size()));  // leaves parts and lone vertices
  for (int i = 0; i < removed; ++i)
    topology.triangles.erase(topology.triangles.begin() +
                             *rc::gen::inRange(0, int(topology.triangles.size())));
  const MeshConnectivity connectivity(topology);
  std::vector<double> length(connectivity.num_edges());
  for (double& l : length) l = *rc::gen::inRange(0, 4);
  const int one_in = *rc::gen::element(1, 2, 5, 20);
  std::vector<char> own(topology.num_vertices);
  for (char& o : own) o = *rc::gen::inRange(0, one_in) == 0;
  NearestSourceScratch scratch;
  std::vector<std::int32_t> src(topology.num_vertices, 7);
  nearest_sources(connectivity, length, own, scratch, src);
  RC_ASSERT(src == nearest_sources_by_all_pairs(connectivity, length, own));
}

TEST(ConeStorage, NearestOnFanLeavesFewerVerticesToBorrow) {
  // The point of the rule: a vertex gets a cone in an orientation whenever a plane cuts one of its own edges.
  const ClothGenerator cloth(ClothKind::Curtain, {30, 12, 24.0, 0});
  const Frame frame = cloth.frame(5);
  SlicingPlan plan = make_diffuse_plan(cloth.topology(), frame, {});
  plan.storage = ConeStorage::NearerEndpoint;
  const FrameVisibility paper = compute_visibility(cloth.topology(), frame, plan, {false});
  plan.storage = ConeStorage::NearestOnFan;
  const FrameVisibility fan = compute_visibility(cloth.topology(), frame, plan, {false});
  double paper_filled = 0, fan_filled = 0;
  for (double f : paper.stats.filled_fraction) paper_filled += f;
  for (double f : fan.stats.filled_fraction) fan_filled += f;
  EXPECT_LT(fan_filled, 0.5 * paper_filled) << "paper " << paper_filled << ", fan " << fan_filled;
}

}  // namespace
}  // namespace pleat
