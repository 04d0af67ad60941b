// Slicing plans: the paper's diffuse families, the adaptive median split, point- and area-light pencils.
#include "static_core/slicing_plan.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <set>
#include <tuple>
#include <utility>

#include "oracles/test_meshes.hpp"
#include "sim_io/cloth_generators.hpp"
#include "static_core/adaptive_plan.hpp"
#include "static_core/mesh_slicer.hpp"
#include "static_core/visibility.hpp"
#include "support/input_error.hpp"

namespace pleat {
namespace {

TEST(SlicingPlan, PlaneFramesAreRightHandedAndOrthonormal) {
  for (const glm::dvec3 n : {glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 1), glm::dvec3(-0.3, 0.2, 0.9)}) {
    const SlicingPlane p = make_plane(n, 0.5, 0);
    EXPECT_NEAR(glm::length(p.u), 1.0, 1e-15);
    EXPECT_NEAR(glm::length(p.w), 1.0, 1e-15);
    EXPECT_NEAR(glm::dot(p.u, p.w), 0.0, 1e-15);
    EXPECT_NEAR(glm::distance(glm::cross(p.u, p.w), p.normal), 0.0, 1e-15);
  }
}

TEST(SlicingPlan, DefaultDiffusePlanHasEightSpreadFamilies) {
  const ClothGenerator cloth(ClothKind::Curtain, {30, 2, 24.0, 0});
  const SlicingPlan plan = make_diffuse_plan(cloth.topology(), cloth.frame(0), {});
  ASSERT_EQ(plan.orientations.size(), 8u);
  EXPECT_EQ(plan.storage, ConeStorage::AimedOnFan);
  for (std::size_t a = 0; a < 8; ++a)
    for (std::size_t b = a + 1; b < 8; ++b)  // distinct families: no two normals parallel
      EXPECT_LT(std::abs(glm::dot(plan.orientations[a], plan.orientations[b])), 0.95) << a << " " << b;
  const SlicingPlan paper = make_paper_plan(cloth.topology(), cloth.frame(0));
  EXPECT_EQ(paper.orientations.size(), 6u);
  EXPECT_EQ(paper.storage, ConeStorage::NearerEndpoint);
}

TEST(SlicingPlan, RelaxedOrientationsAreFartherApartThanTheSpiral) {
  const ClothGenerator cloth(ClothKind::Curtain, {12, 2, 24.0, 0});
  // The closest pair of families, as an angle between lines (a normal and its negation are one family).
  auto closest = [](const std::vector<glm::dvec3>& dirs) {
    double largest_cos = 0;
    for (std::size_t a = 0; a < dirs.size(); ++a)
      for (std::size_t b = a + 1; b < dirs.size(); ++b)
        largest_cos = std::max(largest_cos, std::abs(glm::dot(dirs[a], dirs[b])));
    return std::acos(std::min(1.0, largest_cos)) * 180 / 3.14159265358979323846;
  };
  for (const auto& [n, spiral_degrees, relaxed_degrees] :
       {std::tuple{8, 39.0, 44.9}, std::tuple{12, 26.3, 36.5}, std::tuple{20, 17.5, 29.9}}) {
    DiffusePlanParams params;
    params.orientations = n;
    const SlicingPlan relaxed = make_diffuse_plan(cloth.topology(), cloth.frame(0), params);
    params.relaxed = false;
    const SlicingPlan spiral = make_diffuse_plan(cloth.topology(), cloth.frame(0), params);
    ASSERT_EQ(relaxed.orientations.size(), std::size_t(n));
    for (const glm::dvec3& d : relaxed.orientations) {
      EXPECT_NEAR(glm::length(d), 1.0, 1e-12);
      EXPECT_GE(d.z, 0.0);  // one representative per family, on the upper hemisphere
    }
    EXPECT_NEAR(closest(spiral.orientations), spiral_degrees, 0.1) << n;
    EXPECT_GE(closest(relaxed.orientations), relaxed_degrees) << n;
    EXPECT_GT(closest(relaxed.orientations), closest(spiral.orientations) + 4.0) << n;
    // Deterministic: the same plan every time (the kinetic engine and the cone cache depend on it).
    params.relaxed = true;
    EXPECT_EQ(make_diffuse_plan(cloth.topology(), cloth.frame(0), params).orientations, relaxed.orientations);
  }
}

TEST(SlicingPlan, DiffusePlanHasThePapersSixFamiliesOneEdgeApart) {
  const ClothGenerator cloth(ClothKind::Curtain, {30, 2, 24.0, 0});
  const Frame frame = cloth.frame(0);
  const double edge = average_edge_length(cloth.topology(), frame);
  // The paper's spacing (one edge) on request, the default's (1/2 edge) otherwise.
  for (const auto& [params, spacing] : {std::pair{DiffusePlanParams{6, 0.0, 0, 1.0}, edge},
                                        std::pair{DiffusePlanParams{6, 0.0, 0}, 0.5 * edge}}) {
    const SlicingPlan plan = make_diffuse_plan(cloth.topology(), frame, params);
    ASSERT_EQ(plan.orientations.size(), 6u);
    EXPECT_NEAR(plan.orientations[3].x, std::sqrt(0.5), 1e-15);  // (1,1,0) normalized
    for (int o = 0; o < 6; ++o) {
      std::vector<double> offsets;
      for (const auto& p : plan.planes)
        if (p.orientation == o) offsets.push_back(p.offset);
      ASSERT_GE(offsets.size(), 1u);
      std::sort(offsets.begin(), offsets.end());
      for (std::size_t i = 1; i < offsets.size(); ++i)
        EXPECT_NEAR(offsets[i] - offsets[i - 1], spacing, 1e-12);
    }
  }
  const SlicingPlan counted = make_diffuse_plan(cloth.topology(), frame, {12, 0.0, 7});
  EXPECT_EQ(counted.orientations.size(), 12u);
  EXPECT_EQ(counted.planes.size(), 12u * 7u);
}

TEST(SlicingPlan, LatticePlanesAreAnchoredInWorldSpace) {
  // Offsets are (k + 1/2) * spacing for integer k, whatever the cloth's extent: a plan covering more space
  // (another frame range, a longer cache) has the same planes where they overlap, bit for bit.
  const ClothGenerator cloth(ClothKind::Flag, {14, 2, 24.0, 0});
  const Frame frame = cloth.frame(0);
  const SlicingPlan tight = make_diffuse_plan(cloth.topology(), frame, {});
  ASSERT_GT(tight.spacing, 0.0);
  for (const SlicingPlane& p : tight.planes) {
    const double k = p.offset / tight.spacing - 0.5;
    EXPECT_NEAR(k, std::round(k), 1e-9) << p.offset;
  }
  Bounds wide = cloth_bounds(cloth.topology(), frame);
  ASSERT_FALSE(wide.empty());
  wide.add(wide.lo - glm::dvec3(3.0, 1.0, 2.0));
  wide.add(wide.hi + glm::dvec3(1.0, 4.0, 0.5));
  const SlicingPlan loose = make_diffuse_plan(cloth.topology(), frame, {}, &wide);
  EXPECT_EQ(loose.spacing, tight.spacing);
  EXPECT_EQ(loose.orientations, tight.orientations);
  ASSERT_GT(loose.planes.size(), tight.planes.size() + 8);
  std::set<std::pair<int, double>> loose_planes;
  for (const SlicingPlane& p : loose.planes) loose_planes.insert({p.orientation, p.offset});
  for (const SlicingPlane& p : tight.planes)
    EXPECT_TRUE(loose_planes.count({p.orientation, p.offset})) << p.orientation << " " << p.offset;
  // The planes that meet no cloth add empty slices and change no cone: the same values to the bit.
  const FrameVisibility a = compute_visibility(cloth.topology(), frame, tight);
  const FrameVisibility b = compute_visibility(cloth.topology(), frame, loose);
  for (Side side : kBothSides)
    for (Index v = 0; v < cloth.topology().num_vertices; ++v)
      ASSERT_EQ(a.measure(side, v).sky_visibility, b.measure(side, v).sky_visibility) << v;
}

TEST(SlicingPlan, CoverWithPlanesRejectsWhatCannotBeALattice) {
  SlicingPlan plan;
  plan.orientations = {{0, 0, 1}};
  Bounds box;
  box.add({0, 0, 0});
  box.add({1, 1, 1});
  EXPECT_THROW(cover_with_planes(plan, box), std::invalid_argument);  // no spacing
  plan.spacing = 0.25;
  EXPECT_THROW(cover_with_planes(plan, Bounds{}), std::invalid_argument);  // nothing to cover
  cover_with_planes(plan, box);
  ASSERT_EQ(plan.planes.size(), 4u);  // 0.125, 0.375, 0.625, 0.875
  EXPECT_EQ(plan.planes.front().offset, 0.125);
  EXPECT_EQ(plan.planes.back().offset, 0.875);
  plan.spacing = 1e-12;
  EXPECT_THROW(cover_with_planes(plan, box), InputError);  // absurdly many planes, refused before allocating
}

TEST(SlicingPlan, AnIsolatedVertexDoesNotStretchAPlan) {
  // A vertex no triangle uses gets no cone; far away, it once multiplied a diffuse plan's planes (a fuzzed
  // 16-vertex cloth had 19,911) and moved the pencils' centroid.
  const ClothGenerator cloth(ClothKind::Flag, {12, 2, 24.0, 0});
  const Frame frame = cloth.frame(0);
  MeshTopology stray_topology = cloth.topology();
  Frame stray_frame = frame;
  stray_topology.num_vertices += 1;
  stray_frame.positions.push_back({400.0, -300.0, 250.0});
  auto same = [](const SlicingPlan& a, const SlicingPlan& b) {
    ASSERT_EQ(a.planes.size(), b.planes.size());
    for (std::size_t i = 0; i < a.planes.size(); ++i) {
      EXPECT_EQ(a.planes[i].normal, b.planes[i].normal) << i;
      EXPECT_EQ(a.planes[i].offset, b.planes[i].offset) << i;
    }
  };
  same(make_diffuse_plan(stray_topology, stray_frame, {}), make_diffuse_plan(cloth.topology(), frame, {}));
  const glm::dvec3 light(0.3, 2.0, -1.0);
  same(make_point_light_plan(stray_topology, stray_frame, light),
       make_point_light_plan(cloth.topology(), frame, light));
  const std::vector<glm::dvec3> quad = {{-1, 3, -1}, {1, 3, -1}, {1, 3, 1}, {-1, 3, 1}};
  same(make_area_light_plan(stray_topology, stray_frame, quad),
       make_area_light_plan(cloth.topology(), frame, quad));
}

TEST(SlicingPlan, AdaptivePlanLeavesAtMostTheAllowedFractionWithoutCone) {
  const ClothGenerator cloth(ClothKind::Flag, {25, 2, 24.0, 3});
  const Frame frame = cloth.frame(1);
  const MeshConnectivity connectivity(cloth.topology());
  for (double allowed : {0.05, 0.2}) {
    const SlicingPlan plan = make_adaptive_plan(cloth.topology(), frame, {6, allowed});
    for (int o = 0; o < 6; ++o) {
      std::set<Index> covered;
      for (const auto& p : plan.planes)
        if (p.orientation == o)
          for (Index v : cone_recipients(cloth.topology(), connectivity, frame, p)) covered.insert(v);
      const double missing = 1.0 - double(covered.size()) / cloth.topology().num_vertices;
      EXPECT_LE(missing, allowed + 1e-12) << "orientation " << o;
    }
  }
}

TEST(SlicingPlan, PointLightPlanesContainTheLight) {
  const ClothGenerator cloth(ClothKind::Roll, {20, 2, 24.0, 0});
  const Frame frame = cloth.frame(0);
  const glm::dvec3 light(0.3, 2.0, -1.0);
  const SlicingPlan plan = make_point_light_plan(cloth.topology(), frame, light);
  ASSERT_GT(plan.planes.size(), 5u);
  for (const auto& p : plan.planes) EXPECT_NEAR(glm::dot(p.normal, light), p.offset, 1e-12);
}

TEST(SlicingPlan, AreaLightPlanesRotateAboutLinesJoiningOppositeCorners) {
  const ClothGenerator cloth(ClothKind::Curtain, {20, 2, 24.0, 0});
  const Frame frame = cloth.frame(0);
  const std::vector<glm::dvec3> quad = {{-1, 3, -1}, {1, 3, -1}, {1, 3, 1}, {-1, 3, 1}};
  const SlicingPlan plan = make_area_light_plan(cloth.topology(), frame, quad);
  ASSERT_EQ(plan.orientations.size(), 2u);  // diagonals 0-2 and 1-3
  for (const auto& p : plan.planes) {
    const glm::dvec3 a = quad[p.orientation], b = quad[p.orientation + 2];
    EXPECT_NEAR(glm::dot(p.normal, a), p.offset, 1e-12);
    EXPECT_NEAR(glm::dot(p.normal, b), p.offset, 1e-12);
  }
}

}  // namespace
}  // namespace pleat
