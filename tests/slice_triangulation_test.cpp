// The constrained triangulation of SliceTriangulation::build against CGAL's own constraint insertion (the
// oracle): the same slice points inserted in the same order, and every chain edge by Cdt::insert_constraint.
// build marks chain edges that are already triangulation edges itself (cgal::insert_constraint), so the two
// must give the same triangulation face by face: the same vertices, the same triangles and the same
// constrained edges. On random chains (holes, dangling chains, grid-snapped collinear and duplicate points)
// and on slices of random folded height fields (some planes exactly through mesh vertices); and on hand-made
// cases where a constraint is already an edge, passes through a vertex, or crosses another constraint.
#include "static_core/internal/slice_triangulation.hpp"

#include <CGAL/spatial_sort.h>
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <numeric>
#include <set>
#include <string>
#include <vector>

#include "oracles/random_slices.hpp"

namespace pleat {
namespace {

using Triangle = std::array<std::pair<double, double>, 3>;
using Segment = std::array<std::pair<double, double>, 2>;

/// The finite triangles (corners rotated to start at the smallest point: orientation kept) and the
/// constrained edges (ends sorted) of a triangulation, by coordinates.
struct Shape {
  std::size_t vertices = 0;
  std::set<Triangle> triangles;
  std::set<Segment> constrained;
  bool operator==(const Shape&) const = default;
};

Shape shape_of(const cgal::Cdt& cdt) {
  auto xy = [](const cgal::Point2& p) { return std::make_pair(p.x(), p.y()); };
  Shape s;
  s.vertices = cdt.number_of_vertices();
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    Triangle t{xy(f->vertex(0)->point()), xy(f->vertex(1)->point()), xy(f->vertex(2)->point())};
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    s.triangles.insert(t);
  }
  for (auto e = cdt.constrained_edges_begin(); e != cdt.constrained_edges_end(); ++e) {
    Segment seg{xy(e->first->vertex(cdt.cw(e->second))->point()),
                xy(e->first->vertex(cdt.ccw(e->second))->point())};
    std::sort(seg.begin(), seg.end());
    s.constrained.insert(seg);
  }
  return s;
}

/// The oracle: build's insertion with CGAL's insert_constraint for every chain edge.
void build_with_cgal_constraints(const Slice& slice, cgal::Cdt& cdt) {
  const std::size_t n = slice.vertices.size();
  std::vector<cgal::Point2> points(n);
  for (std::size_t i = 0; i < n; ++i) points[i] = cgal::to_point(slice.vertices[i].point);
  std::vector<std::ptrdiff_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  using Traits = CGAL::Spatial_sort_traits_adapter_2<cgal::Kernel, cgal::Point2*>;
  CGAL::spatial_sort(order.begin(), order.end(), Traits(points.data()));
  std::vector<cgal::VertexHandle> vertex(n);
  cgal::FaceHandle hint;
  for (std::ptrdiff_t i : order) {
    vertex[i] = cdt.insert(points[i], hint);
    hint = vertex[i]->face();
  }
  for (const SliceEdge& e : slice.edges)
    if (vertex[e.from] != vertex[e.to]) cdt.insert_constraint(vertex[e.from], vertex[e.to]);
}

std::string compare_with_cgal(const Slice& slice) {
  SliceTriangulation built;
  built.build(slice);
  cgal::Cdt oracle;
  build_with_cgal_constraints(slice, oracle);
  if (!built.cdt().is_valid())
    return "build's triangulation is not a valid constrained Delaunay triangulation";
  const Shape a = shape_of(built.cdt()), b = shape_of(oracle);
  if (a.vertices != b.vertices) return "vertex counts differ";
  if (a.constrained != b.constrained) return "constrained edges differ";
  if (a.triangles != b.triangles) return "triangles differ";
  return {};
}

/// How many chain edges were already edges of the slice points' triangulation, and how many were not (counted
/// by count_paths): both paths of cgal::insert_constraint must be exercised.
std::size_t g_existing = 0, g_inserted = 0;

void count_paths(const Slice& slice) {
  cgal::Cdt cdt;
  std::vector<cgal::VertexHandle> vertex(slice.vertices.size());
  for (std::size_t i = 0; i < slice.vertices.size(); ++i)
    vertex[i] = cdt.insert(cgal::to_point(slice.vertices[i].point));
  for (const SliceEdge& e : slice.edges) {
    cgal::FaceHandle f;
    int i = 0;
    if (vertex[e.from] == vertex[e.to]) continue;
    ++(cdt.is_edge(vertex[e.from], vertex[e.to], f, i) ? g_existing : g_inserted);
    cgal::insert_constraint(cdt, vertex[e.from], vertex[e.to]);
  }
}

RC_GTEST_PROP(SliceTriangulation, SameTriangulationAsCgalsConstraintInsertionOnRandomChains, ()) {
  std::mt19937_64 rng(*rc::gen::arbitrary<std::uint64_t>());
  const Slice slice = test::random_chain_slice(rng);
  const std::string why = compare_with_cgal(slice);
  RC_ASSERT(why.empty());
}

RC_GTEST_PROP(SliceTriangulation, SameTriangulationAsCgalsConstraintInsertionOnSlicedSurfaces, ()) {
  for (const Slice& slice : test::random_surface_slices(*rc::gen::arbitrary<std::uint64_t>(), 4)) {
    const std::string why = compare_with_cgal(slice);
    RC_ASSERT(why.empty());
  }
}

TEST(SliceTriangulation, AFixedBatchExercisesBothConstraintPaths) {
  // The properties' slices, from fixed seeds: every one matches CGAL, and both paths of
  // cgal::insert_constraint (an edge already there, an edge CGAL inserts) were taken.
  g_existing = g_inserted = 0;
  std::mt19937_64 rng(11);
  for (int k = 0; k < 100; ++k) {
    const Slice slice = test::random_chain_slice(rng);
    count_paths(slice);
    ASSERT_EQ(compare_with_cgal(slice), "");
  }
  for (std::uint64_t seed = 0; seed < 20; ++seed)
    for (const Slice& slice : test::random_surface_slices(seed, 4)) {
      count_paths(slice);
      ASSERT_EQ(compare_with_cgal(slice), "");
    }
  EXPECT_GT(g_existing, 1000u);
  EXPECT_GT(g_inserted, 10u);
  std::printf("chain edges already triangulation edges: %zu; inserted by CGAL: %zu\n", g_existing,
              g_inserted);
}

TEST(SliceTriangulation, ConstraintThroughAVertexAndAcrossAnotherIsSplitAsCgalSplitsIt) {
  // A square with its centre and a point to the right: the diagonals (0,0)-(2,2) and (2,0)-(0,2) pass through
  // the vertex (1,1); (0,2)-(3,1) crosses the first diagonal at (1.5,1.5), where a vertex is added; the side
  // (0,0)-(2,0) is a hull edge already.
  const std::vector<cgal::Point2> points{{0, 0}, {2, 0}, {2, 2}, {0, 2}, {1, 1}, {3, 1}};
  const std::vector<std::pair<int, int>> constraints{{0, 1}, {0, 2}, {1, 3}, {1, 5}, {3, 5}};
  cgal::Cdt ours, theirs;
  std::vector<cgal::VertexHandle> a, b;
  for (const auto& p : points) {
    a.push_back(ours.insert(p));
    b.push_back(theirs.insert(p));
  }
  for (const auto& [i, j] : constraints) {
    cgal::insert_constraint(ours, a[i], a[j]);
    theirs.insert_constraint(b[i], b[j]);
  }
  EXPECT_TRUE(ours.is_valid());
  EXPECT_EQ(shape_of(ours), shape_of(theirs));
  EXPECT_EQ(ours.number_of_vertices(), 7u);
  // The side, the first diagonal in three, the second in two, (2,0)-(3,1), and (0,2)-(3,1) in two.
  EXPECT_EQ(shape_of(ours).constrained.size(), 9u);
}

TEST(SliceTriangulation, ConstraintsOfACollinearTriangulationAreCgals) {
  // Dimension 1: cgal::insert_constraint leaves every case to CGAL.
  cgal::Cdt ours, theirs;
  std::vector<cgal::VertexHandle> a, b;
  for (int i = 0; i < 4; ++i) {
    a.push_back(ours.insert({double(i), 0.0}));
    b.push_back(theirs.insert({double(i), 0.0}));
  }
  cgal::insert_constraint(ours, a[0], a[1]);
  theirs.insert_constraint(b[0], b[1]);
  cgal::insert_constraint(ours, a[1], a[3]);
  theirs.insert_constraint(b[1], b[3]);
  ASSERT_EQ(ours.dimension(), 1);
  EXPECT_EQ(shape_of(ours), shape_of(theirs));
  EXPECT_EQ(shape_of(ours).constrained.size(), 3u);
}

}  // namespace
}  // namespace pleat
