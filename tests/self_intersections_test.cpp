// self_intersecting_faces: hand-made cases for every kind of contact (shared edge, shared vertex, disjoint,
// coplanar, degenerate, non-manifold), and a cross-check of the Polygon_mesh_processing path against the
// triangle-soup path on random crumpled grids.
#include "sim_io/self_intersections.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <stdexcept>

namespace pleat {
namespace {

using Pairs = std::vector<std::pair<Index, Index>>;

struct Mesh {
  MeshTopology topology;
  Frame frame;
  Index add(double x, double y, double z) {
    frame.positions.push_back({x, y, z});
    return topology.num_vertices++;
  }
  void face(Index a, Index b, Index c) { topology.triangles.push_back({a, b, c}); }
  Pairs intersections() const { return self_intersecting_faces(topology, frame); }
};

// An n x n grid over [0,1]^2 with heights z(i, j), consistently wound.
Mesh grid(int n, const std::function<double(int, int)>& z) {
  Mesh m;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) m.add(double(i) / (n - 1), double(j) / (n - 1), z(i, j));
  auto v = [n](int i, int j) { return Index(j * n + i); };
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      m.face(v(i, j), v(i + 1, j), v(i + 1, j + 1));
      m.face(v(i, j), v(i + 1, j + 1), v(i, j + 1));
    }
  return m;
}

// Deterministic uniform doubles in [0, 1) (splitmix64), the same on every platform.
struct Random {
  std::uint64_t state;
  double next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return double((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
  }
};

TEST(SelfIntersections, TwoCrossingTriangles) {
  Mesh m;
  m.face(m.add(0, 0, 0), m.add(1, 0, 0), m.add(0, 1, 0));
  m.face(m.add(0.2, 0.2, -1), m.add(0.3, 0.2, 1), m.add(0.2, 0.3, 1));
  EXPECT_EQ(m.intersections(), (Pairs{{0, 1}}));
}

TEST(SelfIntersections, SeparateTrianglesDoNotIntersect) {
  Mesh m;
  m.face(m.add(0, 0, 0), m.add(1, 0, 0), m.add(0, 1, 0));
  m.face(m.add(0, 0, 0.5), m.add(1, 0, 0.5), m.add(0, 1, 0.5));
  EXPECT_TRUE(m.intersections().empty());
}

TEST(SelfIntersections, FlatAndFoldedGridsAreClean) {
  EXPECT_TRUE(grid(8, [](int, int) { return 0.0; }).intersections().empty());  // coplanar neighbours
  EXPECT_TRUE(
      grid(8, [](int i, int j) { return std::sin(3.0 * i) * 2.0 + 0.1 * j; }).intersections().empty());
}

TEST(SelfIntersections, CoplanarNeighboursFoldedOntoEachOther) {
  // Shared edge (0,1); the far corners on the same side of it, in the same plane: they overlap.
  Mesh m;
  const Index a = m.add(0, 0, 0), b = m.add(1, 0, 0), c = m.add(0.5, 1, 0), d = m.add(0.5, 0.5, 0);
  m.face(a, b, c);
  m.face(b, a, d);
  EXPECT_EQ(m.intersections(), (Pairs{{0, 1}}));
  // The same with the far corner lifted out of the plane: they meet only along the edge.
  m.frame.positions[d].z = 0.01;
  EXPECT_TRUE(m.intersections().empty());
}

TEST(SelfIntersections, SharedVertexPiercing) {
  // Both triangles have vertex 0; the second's opposite edge passes through the first.
  Mesh m;
  const Index o = m.add(0, 0, 0);
  m.face(o, m.add(2, 0, 0), m.add(0, 2, 0));
  m.face(o, m.add(1, 1, -1), m.add(1, 1, 1));
  EXPECT_EQ(m.intersections(), (Pairs{{0, 1}}));
  // Shared vertex only: a fan around it, not intersecting.
  Mesh fan;
  const Index p = fan.add(0, 0, 0);
  fan.face(p, fan.add(1, 0, 0), fan.add(0, 1, 0));
  fan.face(p, fan.add(-1, 0, 0.3), fan.add(0, -1, 0.3));
  EXPECT_TRUE(fan.intersections().empty());
}

TEST(SelfIntersections, SharedVertexCoplanarOverlap) {
  Mesh m;
  const Index o = m.add(0, 0, 0);
  m.face(o, m.add(2, 0, 0), m.add(0, 2, 0));
  m.face(o, m.add(1, 0.5, 0), m.add(3, 3, 0));
  EXPECT_EQ(m.intersections(), (Pairs{{0, 1}}));
}

TEST(SelfIntersections, DegenerateFacesAreSkipped) {
  Mesh m;
  m.face(m.add(0, 0, 0), m.add(1, 0, 0), m.add(0, 1, 0));
  m.face(m.add(0.2, 0.2, -1), m.add(0.2, 0.2, 0), m.add(0.2, 0.2, 1));  // a needle through face 0
  EXPECT_TRUE(m.intersections().empty());  // a manifold mesh: the Surface_mesh path
  m.face(0, 0, 1);                         // a repeated index: the soup path
  EXPECT_TRUE(m.intersections().empty());
}

TEST(SelfIntersections, NonManifoldEdgeAndDuplicateFace) {
  // Three pages of a book on one edge: non-manifold, not intersecting.
  Mesh m;
  const Index a = m.add(0, 0, 0), b = m.add(0, 0, 1);
  m.face(a, b, m.add(1, 0, 0.5));
  m.face(b, a, m.add(-1, 0.2, 0.5));
  m.face(a, b, m.add(-1, -0.3, 0.5));
  EXPECT_TRUE(m.intersections().empty());
  // A fourth page crossing page 0.
  m.face(m.add(0.5, -1, 0.5), m.add(0.5, 1, 0.4), m.add(0.5, 1, 0.6));
  EXPECT_EQ(m.intersections(), (Pairs{{0, 3}}));
  // The same triangle twice overlaps itself entirely.
  m.face(m.topology.triangles[0][0], m.topology.triangles[0][1], m.topology.triangles[0][2]);
  EXPECT_EQ(m.intersections(), (Pairs{{0, 3}, {0, 4}, {3, 4}}));
}

TEST(SelfIntersections, BoundaryAndHoleAreFine) {
  Mesh m = grid(6, [](int i, int j) { return 0.3 * std::cos(1.7 * i + 0.4 * j); });
  m.topology.triangles.erase(m.topology.triangles.begin() + 20, m.topology.triangles.begin() + 24);
  EXPECT_TRUE(m.intersections().empty());
}

TEST(SelfIntersections, IndexOutOfRangeThrows) {
  Mesh m;
  m.add(0, 0, 0);
  m.face(0, 1, 2);
  EXPECT_THROW(m.intersections(), std::invalid_argument);
}

// The manifold input goes through Polygon_mesh_processing on a Surface_mesh; adding a far-away non-manifold
// book sends the same faces through the soup path. Both must report the same pairs.
TEST(SelfIntersections, SurfaceMeshAndSoupPathsAgree) {
  std::size_t total = 0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    Random random{seed};
    const double amplitude = 0.05 + 0.5 * random.next();
    Mesh m = grid(7, [&](int, int) { return amplitude * (random.next() - 0.5); });
    // Move some vertices within the plane so that coplanar and near-coplanar contacts occur too.
    for (auto& p : m.frame.positions)
      if (random.next() < 0.3) {
        p.x += 0.4 * (random.next() - 0.5);
        p.y += 0.4 * (random.next() - 0.5);
        if (random.next() < 0.5) p.z = 0;
      }
    const Pairs manifold = m.intersections();
    const std::size_t original = m.topology.triangles.size();
    const Index a = m.add(10, 10, 10), b = m.add(10, 10, 11);
    m.face(a, b, m.add(11, 10, 10.5));
    m.face(b, a, m.add(9, 10.2, 10.5));
    m.face(a, b, m.add(9, 9.7, 10.5));
    Pairs soup = m.intersections();
    std::erase_if(soup, [&](const auto& p) { return p.second >= original; });
    EXPECT_EQ(manifold, soup) << "seed " << seed;
    total += manifold.size();
  }
  EXPECT_GT(total, 20u);  // the random grids did intersect, so the comparison means something
}

}  // namespace
}  // namespace pleat
