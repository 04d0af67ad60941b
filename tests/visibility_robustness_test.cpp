// compute_visibility on input the algorithm does not expect: self-intersecting surfaces (chains cross),
// degenerate and non-manifold faces, a sheet lying exactly in slicing planes, tiny meshes. It must not crash
// or hang, must count crossings, and must keep every A in [0, 1].
#include <gtest/gtest.h>

#include "oracles/test_meshes.hpp"
#include "static_core/visibility.hpp"

namespace pleat {
namespace {

void expect_sane(const test::TestMesh& mesh, const FrameVisibility& vis) {
  for (Index v = 0; v < mesh.topology.num_vertices; ++v)
    for (Side s : kBothSides) {
      const double a = vis.measure(s, v).sky_visibility;
      EXPECT_GE(a, 0.0);
      EXPECT_LE(a, 1.0);
    }
}

/// Two sheets crossing along a line through no vertex of either: a self-intersecting surface. (Chains that
/// cross exactly at a point that is a slice vertex of both share that CDT vertex and are not counted.)
test::TestMesh crossing_sheets() {
  auto a = test::flat_sheet(9, 9);
  auto b = test::flat_sheet(9, 9);
  test::rigid_transform(a, {1, 0, 0}, 0.0, {-4, -4, 0});
  test::rigid_transform(b, {1, 0, 0}, 1.5707963267948966, {-4, 0.37, -4.21});  // the plane y = 0.37
  const Index offset = a.topology.num_vertices;
  for (const auto& p : b.frame.positions) a.frame.positions.push_back(p);
  for (const auto& t : b.topology.triangles)
    a.topology.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  a.topology.num_vertices += b.topology.num_vertices;
  return a;
}

TEST(VisibilityRobustness, CrossingChainsAreCountedAndHandled) {
  const auto mesh = crossing_sheets();
  const SlicingPlan plan = make_diffuse_plan(mesh.topology, mesh.frame, {});
  const FrameVisibility vis = compute_visibility(mesh.topology, mesh.frame, plan);
  EXPECT_GT(vis.stats.crossing_slices, 0u);
  EXPECT_GT(vis.stats.chain_crossings, 0u);
  expect_sane(mesh, vis);
}

TEST(VisibilityRobustness, SheetLyingInTheSlicingPlanes) {
  // Every vertex is exactly on the planes z = 0 of orientation (0,0,1) placed through them.
  const auto sheet = test::flat_sheet(8, 8);
  SlicingPlan plan = make_diffuse_plan(sheet.topology, sheet.frame, {});
  plan.planes.push_back(make_plane({0, 0, 1}, 0.0, 2));
  plan.planes.push_back(make_plane({1, 0, 0}, 3.0, 0));  // through a column of vertices
  const FrameVisibility vis = compute_visibility(sheet.topology, sheet.frame, plan);
  for (Index v = 0; v < sheet.topology.num_vertices; ++v)
    for (Side s : kBothSides) EXPECT_NEAR(vis.measure(s, v).sky_visibility, 1.0, 1e-9);
}

TEST(VisibilityRobustness, DegenerateNonManifoldAndTinyInput) {
  auto mesh = test::flat_sheet(5, 5);
  test::rigid_transform(mesh, {1, 1, 0}, 0.7, {0, 0, 0});
  mesh.topology.triangles.push_back({0, 1, 2});      // zero area: three collinear vertices of the first row
  mesh.topology.triangles.push_back({0, 6, 1});      // a third face on edge (0, 1)... and duplicate-ish
  mesh.topology.triangles.push_back({0, 1, 6});      // the same face reversed
  mesh.frame.positions.emplace_back(100, 100, 100);  // an isolated vertex
  mesh.topology.num_vertices += 1;
  const SlicingPlan plan = make_diffuse_plan(mesh.topology, mesh.frame, {});
  const FrameVisibility vis = compute_visibility(mesh.topology, mesh.frame, plan);
  expect_sane(mesh, vis);

  test::TestMesh one;
  one.topology.num_vertices = 3;
  one.topology.triangles.push_back({0, 1, 2});
  one.frame.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const FrameVisibility vis1 =
      compute_visibility(one.topology, one.frame, make_diffuse_plan(one.topology, one.frame, {}));
  expect_sane(one, vis1);

  test::TestMesh empty;
  const FrameVisibility vis0 =
      compute_visibility(empty.topology, empty.frame, make_diffuse_plan(empty.topology, empty.frame, {}));
  EXPECT_TRUE(vis0.measures[0].empty());
}

}  // namespace
}  // namespace pleat
