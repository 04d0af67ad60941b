// MeshConnectivity (OpenMesh's half-edge structure and the flat arrays derived from it) against the
// brute-force oracle of tests/oracles/mesh_topology_oracle.hpp: the old sorted-key edge extraction and
// union-find counts, and fans read off vertex links. Random triangle soups (non-manifold and flipped edges,
// bow-ties, repeated corners, duplicate faces, isolated vertices), grids with holes and flipped faces in any
// face order, closed surfaces with holes; and the cases one by one.
#include "static_core/mesh_connectivity.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <string>

#include "oracles/mesh_topology_oracle.hpp"
#include "oracles/test_meshes.hpp"
#include "sim_io/mesh_report.hpp"
#include "support/input_error.hpp"

namespace pleat {
namespace {

/// A permutation drawn from rapidcheck (its seed is rapidcheck's: the run is reproducible).
template <class T>
std::vector<T> shuffled(std::vector<T> items) {
  std::mt19937 rng(*rc::gen::arbitrary<std::uint32_t>());
  std::shuffle(items.begin(), items.end(), rng);
  return items;
}

bool is_manifold_soup(const MeshTopology& topology, const test::OracleEdges& oracle) {
  for (const Triangle& t : topology.triangles)
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return false;
  for (unsigned sides : oracle.face_sides)
    if (sides > 2) return false;
  return test::oracle_count_topology(topology).inconsistent_edges == 0;
}

/// Everything MeshConnectivity derives, compared with the oracle; "" when they agree.
std::string compare(const MeshTopology& topology) {
  const MeshConnectivity c(topology);
  const test::OracleEdges o = test::oracle_edges(topology);
  if (c.num_vertices() != topology.num_vertices) return "vertex count";
  if (c.endpoints() != o.endpoints) return "endpoints";
  if (c.of_face() != o.of_face) return "of_face";
  for (Index v = 0; v < topology.num_vertices; ++v) {
    const auto nb = c.neighbours(v);
    if (!std::equal(nb.begin(), nb.end(), o.neighbours[v].begin(), o.neighbours[v].end()))
      return "neighbours of " + std::to_string(v);
    for (std::size_t i = 0; i < nb.size(); ++i) {
      const std::array<Index, 2> e = {std::min(v, nb[i]), std::max(v, nb[i])};
      if (c.endpoints()[c.incident_edges(v)[i]] != e) return "incident edges of " + std::to_string(v);
    }
    std::vector<Index> faces(c.faces_around(v).begin(), c.faces_around(v).end());
    std::sort(faces.begin(), faces.end());
    if (faces != o.faces_around[v] || faces.size() != c.faces_around(v).size())
      return "faces around " + std::to_string(v);
    if (c.is_isolated(v) != o.faces_around[v].empty()) return "isolated " + std::to_string(v);
    // A closed fan is one the oracle sees; conversely, where nothing was split, every fan the oracle sees.
    const bool closed = test::oracle_closed_fan(topology, v);
    if (c.has_closed_fan(v) && !closed)
      return "closed fan at " + std::to_string(v) + " the oracle does not see";
    if (c.split_faces().empty() && closed && !c.has_closed_fan(v))
      return "closed fan at " + std::to_string(v) + " missed";
  }
  for (Index e = 0; e < c.num_edges(); ++e)
    if (c.face_sides(e) != o.face_sides[e]) return "face sides of edge " + std::to_string(e);
  if (is_manifold_soup(topology, o) != c.split_faces().empty() && !is_manifold_soup(topology, o))
    return "a non-manifold soup with nothing split";
  const TopologyCounts a = count_topology(topology), b = test::oracle_count_topology(topology);
  if (a.edges != b.edges || a.boundary_edges != b.boundary_edges || a.boundary_loops != b.boundary_loops ||
      a.non_manifold_edges != b.non_manifold_edges || a.inconsistent_edges != b.inconsistent_edges ||
      a.isolated_vertices != b.isolated_vertices || a.components != b.components)
    return "counts";
  if (c.boundary_loops() != b.boundary_loops || c.components() != b.components) return "loops or components";
  return "";
}

MeshTopology gen_soup() {
  MeshTopology t;
  t.num_vertices = Index(*rc::gen::inRange(0, 9));
  if (t.num_vertices == 0) return t;
  const int faces = *rc::gen::inRange(0, 13);
  const bool repeats = *rc::gen::inRange(0, 4) == 0;
  for (int f = 0; f < faces; ++f) {
    Triangle tri;
    for (Index& v : tri) v = Index(*rc::gen::inRange(0, int(t.num_vertices)));
    if (!repeats && (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2])) continue;
    t.triangles.push_back(tri);
  }
  return t;
}

/// A grid or an icosphere, holes punched, some faces flipped or repeated, relabelled and shuffled.
MeshTopology gen_surface() {
  MeshTopology t = *rc::gen::inRange(0, 3) == 0
                       ? test::icosphere(*rc::gen::inRange(0, 2)).topology
                       : test::flat_sheet(*rc::gen::inRange(2, 7), *rc::gen::inRange(2, 7)).topology;
  const int holes = *rc::gen::inRange(0, 4);
  for (int h = 0; h < holes && !t.triangles.empty(); ++h)
    t.triangles.erase(t.triangles.begin() + *rc::gen::inRange(0, int(t.triangles.size())));
  if (*rc::gen::inRange(0, 3) == 0 && !t.triangles.empty()) {  // flipped winding
    Triangle& f = t.triangles[std::size_t(*rc::gen::inRange(0, int(t.triangles.size())))];
    std::swap(f[1], f[2]);
  }
  if (*rc::gen::inRange(0, 4) == 0 && !t.triangles.empty()) {  // a face twice, either winding
    Triangle f = t.triangles[std::size_t(*rc::gen::inRange(0, int(t.triangles.size())))];
    if (*rc::gen::arbitrary<bool>()) std::swap(f[1], f[2]);
    t.triangles.push_back(f);
  }
  const int isolated = *rc::gen::inRange(0, 3);
  t.num_vertices += Index(isolated);
  std::vector<Index> label(t.num_vertices);
  std::iota(label.begin(), label.end(), Index(0));
  label = shuffled(std::move(label));
  for (Triangle& f : t.triangles)
    for (Index& v : f) v = label[v];
  t.triangles = shuffled(std::move(t.triangles));
  return t;
}

RC_GTEST_PROP(MeshConnectivity, MatchesTheOracleOnTriangleSoups, ()) {
  const MeshTopology t = gen_soup();
  const std::string why = compare(t);
  RC_ASSERT(why == "");
}

RC_GTEST_PROP(MeshConnectivity, MatchesTheOracleOnSurfacesWithHoles, ()) {
  const MeshTopology t = gen_surface();
  const std::string why = compare(t);
  RC_ASSERT(why == "");
}

RC_GTEST_PROP(MeshConnectivity, ManifoldSurfacesSplitNothingInAnyFaceOrder, ()) {
  MeshTopology t = test::flat_sheet(*rc::gen::inRange(2, 7), *rc::gen::inRange(2, 7)).topology;
  if (*rc::gen::arbitrary<bool>()) t = test::icosphere(1).topology;
  t.triangles = shuffled(std::move(t.triangles));
  const MeshConnectivity c(t);
  RC_ASSERT(c.split_faces().empty());
  for (Index v = 0; v < t.num_vertices; ++v) RC_ASSERT(c.has_closed_fan(v) == test::oracle_closed_fan(t, v));
}

MeshTopology topology_of(Index n, std::vector<Triangle> triangles) { return {n, std::move(triangles)}; }

TEST(MeshConnectivity, SheetWithAHole) {
  const auto sheet = test::flat_sheet(5, 5).topology;  // 16 quads, 32 triangles
  MeshTopology holed = sheet;
  holed.triangles.erase(holed.triangles.begin() + 10, holed.triangles.begin() + 12);  // one interior quad
  EXPECT_EQ(compare(holed), "");
  const MeshConnectivity c(holed);
  EXPECT_EQ(c.boundary_loops(), 2u);
  EXPECT_EQ(c.components(), 1u);
  EXPECT_TRUE(c.split_faces().empty());
  std::size_t closed = 0;
  for (Index v = 0; v < holed.num_vertices; ++v) closed += c.has_closed_fan(v);
  EXPECT_EQ(closed, 9u - 4u);  // the 3x3 interior vertices but the hole's four corners
}

TEST(MeshConnectivity, ThirdPageOfABookIsSplitAndItsEdgeNonManifold) {
  const auto book = topology_of(5, {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}});
  EXPECT_EQ(compare(book), "");
  testing::internal::CaptureStderr();
  const MeshConnectivity c(book);
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");  // OpenMesh's refusal is not printed
  EXPECT_EQ(c.split_faces(), std::vector<Index>{2});
  EXPECT_EQ(c.kind(c.of_face()[0][0]), EdgeKind::NonManifold);
  EXPECT_EQ(c.face_sides(c.of_face()[0][0]), 3u);
  EXPECT_EQ(c.num_edges(), 7u);
  EXPECT_EQ(count_topology(book).non_manifold_edges, 1u);
}

TEST(MeshConnectivity, FlippedNeighbourIsSplit) {
  const auto flipped = topology_of(4, {{0, 1, 2}, {0, 1, 3}});
  EXPECT_EQ(compare(flipped), "");
  const MeshConnectivity c(flipped);
  EXPECT_EQ(c.split_faces(), std::vector<Index>{1});
  EXPECT_EQ(c.kind(c.of_face()[0][0]), EdgeKind::Flipped);
  EXPECT_EQ(c.neighbours(0).size(), 3u);  // the split face's edges are still 0's
}

TEST(MeshConnectivity, BowTieIsLinkedAndOneBoundaryLoop) {
  // Two triangles touching at vertex 0: OpenMesh links both (two fans at 0), 0 has no closed fan.
  const auto bow_tie = topology_of(5, {{0, 1, 2}, {0, 3, 4}});
  EXPECT_EQ(compare(bow_tie), "");
  const MeshConnectivity c(bow_tie);
  EXPECT_TRUE(c.split_faces().empty());
  EXPECT_FALSE(c.has_closed_fan(0));
  EXPECT_EQ(c.boundary_loops(), 1u);  // the two loops touch at 0
  EXPECT_EQ(c.components(), 1u);
}

TEST(MeshConnectivity, TwoClosedFansAtAVertexSplitTheLastFace) {
  // Two closed square pyramids (apex 0) would make 0 a vertex with two closed fans.
  MeshTopology t = topology_of(9, {});
  for (Index base : {1u, 5u})
    for (Index i = 0; i < 4; ++i) t.triangles.push_back({0, base + i, base + (i + 1) % 4});
  for (Index base : {1u, 5u}) {  // close each pyramid's bottom (two triangles)
    t.triangles.push_back({base, base + 3, base + 2});
    t.triangles.push_back({base, base + 2, base + 1});
  }
  EXPECT_EQ(compare(t), "");
  const MeshConnectivity c(t);
  EXPECT_FALSE(c.split_faces().empty());
  EXPECT_FALSE(c.has_closed_fan(0));
}

TEST(MeshConnectivity, RepeatedCornersDuplicatesAndIsolatedVertices) {
  // (0, 0, 1) has the edge (0, 0); (1, 2, 3) twice, once reversed; vertex 4 in no face.
  const auto t = topology_of(5, {{0, 0, 1}, {1, 2, 3}, {1, 3, 2}, {0, 1, 0}});
  EXPECT_EQ(compare(t), "");
  const MeshConnectivity c(t);
  EXPECT_EQ(c.endpoints()[0], (std::array<Index, 2>{0, 0}));
  EXPECT_EQ(c.kind(0), EdgeKind::Degenerate);
  EXPECT_EQ(c.split_faces(), (std::vector<Index>{0, 3}));
  EXPECT_TRUE(c.is_isolated(4));
  EXPECT_TRUE(c.has_closed_fan(2));  // the reversed copy closes a two-face pillow around 2 and 3
  EXPECT_EQ(c.faces_around(0).size(), 2u);
}

TEST(MeshConnectivity, EmptyAndOutOfRange) {
  EXPECT_EQ(compare(MeshTopology{}), "");
  EXPECT_EQ(compare(topology_of(3, {})), "");
  EXPECT_THROW(MeshConnectivity(topology_of(2, {{0, 1, 2}})), InputError);
}

}  // namespace
}  // namespace pleat
