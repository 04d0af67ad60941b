// `--progress lines` within a long frame (cli/progress.hpp, cli/run_chunks.hpp): while one frame of a large
// cloth is computed, lines say how far it is (slices, then vertices), so a log shows life before the first
// frame ends; and the counters the engines advance reach the frame's totals (static_core/visibility.hpp).
#include <gtest/gtest.h>

#include <regex>
#include <string>

#include "kinetic/engine.hpp"
#include "sim_io/cloth_generators.hpp"
#include "static_core/slicing_plan.hpp"
#include "static_core/visibility.hpp"
#include "test_support.hpp"

namespace pleat {
namespace {

TEST(Progress, LinesWithinALongFrame) {
  // About 2 million slice vertices in one frame, on one thread: several seconds.
  test::TempDir dir;
  ASSERT_EQ(
      test::run_pleat("generate curtain -o " + (dir / "c.obj").string() + " --resolution 300 --frames 1")
          .exit_code,
      0);
  const auto run =
      test::run_pleat("visibility " + (dir / "c.obj").string() + " --cache " + (dir / "c.pc2").string() +
                      " -o " + (dir / "v.csv").string() + " --threads 1 --progress lines");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::regex within(R"(pleat: visibility 0/1 frames [0-9.]+% [0-9.]+ frames/s eta [0-9]+ s  frame 0: )"
                          R"([0-9]+/[0-9]+ slices(, [0-9]+/90000 vertices)?\n)");
  EXPECT_TRUE(std::regex_search(run.output, within)) << run.output;
  EXPECT_NE(run.output.find("pleat: visibility 1/1 frames 100.0%"), std::string::npos) << run.output;
}

TEST(Progress, TheEnginesCountEverySliceAndVertex) {
  const ClothGenerator cloth(ClothKind::Sleeve, {20, 3, 24.0, 0});
  const SlicingPlan plan = make_diffuse_plan(cloth.topology(), cloth.frame(0), {});
  const Index vertices = cloth.topology().num_vertices;
  for (const EngineKind kind : {EngineKind::Static, EngineKind::Kinetic}) {
    FrameProgress progress;
    Engine engine(cloth.topology(), plan, {kind, true, {}, {}, &progress});
    for (std::size_t f = 0; f < 3; ++f) {
      progress.reset();
      engine.compute(cloth.frame(f));
      std::vector<SlicingPlane> planes;
      planes_for_frame(plan, cloth_vertices(cloth.topology()), cloth.frame(f), planes);
      EXPECT_EQ(progress.planes.load(), planes.size()) << engine_kind_name(kind) << " frame " << f;
      EXPECT_EQ(progress.slices.load(), planes.size()) << engine_kind_name(kind) << " frame " << f;
      EXPECT_EQ(progress.vertices.load(), vertices / 64 * 64) << engine_kind_name(kind) << " frame " << f;
    }
  }
}

}  // namespace
}  // namespace pleat
