// StaticVisibility reuses memory across frames; every compute() must still be a full recompute: equal,
// bit for bit, to the one-shot compute_visibility of the same frame, whatever frames came before.
#include <gtest/gtest.h>

#include "sim_io/cloth_generators.hpp"
#include "static_core/visibility.hpp"

namespace pleat {
namespace {

void expect_same(const FrameVisibility& a, const FrameVisibility& b) {
  ASSERT_EQ(a.measures[0].size(), b.measures[0].size());
  for (int s = 0; s < 2; ++s)
    for (std::size_t v = 0; v < a.measures[s].size(); ++v) {
      ASSERT_EQ(a.measures[s][v].sky_visibility, b.measures[s][v].sky_visibility)
          << "side " << s << " vertex " << v;
      ASSERT_EQ(a.cones[s][v].pieces, b.cones[s][v].pieces) << "side " << s << " vertex " << v;
    }
  EXPECT_EQ(a.stats.slice_vertices, b.stats.slice_vertices);
  EXPECT_EQ(a.stats.filled_fraction, b.stats.filled_fraction);
}

TEST(StaticVisibility, EveryFrameEqualsAOneShotRecomputeInAnyOrder) {
  for (ClothKind kind : {ClothKind::Curtain, ClothKind::Sleeve}) {
    const ClothGenerator cloth(kind, {20, 8, 24.0, 5});
    const SlicingPlan plan = make_diffuse_plan(cloth.topology(), cloth.frame(0), {});
    for (bool parallel : {false, true}) {
      StaticVisibility engine(cloth.topology(), plan, {parallel});
      for (std::size_t f : {0, 3, 7, 1, 3, 6}) {
        const Frame frame = cloth.frame(f);
        expect_same(engine.compute(frame), compute_visibility(cloth.topology(), frame, plan, {false}));
      }
    }
  }
}

}  // namespace
}  // namespace pleat
