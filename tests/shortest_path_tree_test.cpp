// The funnel trees of static_core (the funnel as an array searched by bisection) against the oracle that
// walks each funnel chain from its outer end (tests/oracles/funnel_walk_oracle): the same parent for every
// corner, from both ends of every window of every region without holes, on random chains (dangling, nested,
// snapped to a grid for collinear and duplicate points), on slices of random folded height fields (planes
// through vertices), and on every slice of the generated cloth kinds, the roll's spiral included.
#include "static_core/internal/shortest_path_tree.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <numeric>
#include <string>

#include "oracles/funnel_walk_oracle.hpp"
#include "oracles/random_slices.hpp"
#include "sim_io/cloth_generators.hpp"
#include "static_core/mesh_connectivity.hpp"
#include "static_core/slicing_plan.hpp"

namespace pleat {
namespace {

struct Compared {
  std::size_t trees = 0;
  std::string mismatch;  ///< empty when every tree matched
};

/// Grows every tree of `slice` both ways; the first difference, if any.
void compare_trees(const Slice& slice, Compared& out) {
  SliceTriangulation triangulation;
  triangulation.build(slice);
  if (triangulation.dimension() < 2) return;
  FunnelScratch scratch;
  std::vector<int> fast(triangulation.num_corners()), slow(triangulation.num_corners());
  for (std::size_t r = 0; r < triangulation.num_regions() && out.mismatch.empty(); ++r) {
    const SliceRegion region = triangulation.region(r);
    if (region.has_holes) continue;
    for (const SliceWindow& window : region.windows)
      for (const bool from_b : {false, true}) {
        std::fill(fast.begin(), fast.end(), -1);
        std::fill(slow.begin(), slow.end(), -1);
        grow_shortest_path_tree(triangulation, window, from_b, fast, scratch);
        test::walk_shortest_path_tree(triangulation, window, from_b, slow);
        ++out.trees;
        for (std::size_t c = 0; c < fast.size(); ++c)
          if (fast[c] != slow[c]) {
            out.mismatch = "region " + std::to_string(r) + ", corner " + std::to_string(c) + ": parent " +
                           std::to_string(fast[c]) + ", the walk's " + std::to_string(slow[c]) + " (" +
                           std::to_string(slice.vertices.size()) + " slice vertices)";
            return;
          }
      }
  }
}

RC_GTEST_PROP(ShortestPathTree, BisectedFunnelsGrowTheWalksTreesOnRandomChains, ()) {
  std::mt19937_64 rng(*rc::gen::arbitrary<std::uint64_t>());
  Compared compared;
  for (int k = 0; k < 10 && compared.mismatch.empty(); ++k)
    compare_trees(test::random_chain_slice(rng), compared);
  RC_ASSERT(compared.mismatch == "");
}

TEST(ShortestPathTree, TheRandomChainsCompareManyTrees) {
  // A fixed batch of the property above: it must compare trees, not only slices without simple regions.
  std::mt19937_64 rng(7);
  Compared compared;
  for (int k = 0; k < 200 && compared.mismatch.empty(); ++k)
    compare_trees(test::random_chain_slice(rng), compared);
  EXPECT_EQ(compared.mismatch, "");
  EXPECT_GT(compared.trees, 500u);
}

RC_GTEST_PROP(ShortestPathTree, BisectedFunnelsGrowTheWalksTreesOnSlicedSurfaces, ()) {
  Compared compared;
  for (const Slice& slice : test::random_surface_slices(*rc::gen::arbitrary<std::uint64_t>(), 10))
    if (compared.mismatch.empty()) compare_trees(slice, compared);
  RC_ASSERT(compared.mismatch == "");
}

// Long slices with deep funnels (where bisection and the walk differ most in cost), and the roll's spiral,
// whose chains wind round and round: every slice of the default plan, at a folded frame of each kind.
TEST(ShortestPathTree, BisectedFunnelsGrowTheWalksTreesOnGeneratedCloth) {
  for (const ClothKind kind : kAllClothKinds) {
    const ClothGenerator cloth(kind, {.resolution = 40, .frames = 13});
    const Frame frame = cloth.frame(12);
    const SlicingPlan plan = make_diffuse_plan(cloth.topology(), frame, DiffusePlanParams{});
    const MeshConnectivity connectivity(cloth.topology());
    const auto faces = candidate_faces_per_plane(cloth.topology(), frame, plan);
    SlicerScratch scratch;
    Slice slice;
    Compared compared;
    for (std::size_t p = 0; p < plan.planes.size() && compared.mismatch.empty(); ++p) {
      slice_mesh(cloth.topology(), connectivity, frame, plan.planes[p], faces[p], scratch, slice);
      compare_trees(slice, compared);
    }
    EXPECT_EQ(compared.mismatch, "") << cloth_kind_name(kind);
    EXPECT_GT(compared.trees, 1000u) << cloth_kind_name(kind);
  }
}

}  // namespace
}  // namespace pleat
