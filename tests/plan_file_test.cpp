// Plan files (sim_io/plan_file.hpp): exact round trips of lattice and listed plans, and one clear error per
// malformed file naming the place.
#include "sim_io/plan_file.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "sim_io/cloth_generators.hpp"
#include "static_core/adaptive_plan.hpp"
#include "support/input_error.hpp"
#include "test_support.hpp"

namespace pleat {
namespace {

void expect_same_bits(const SlicingPlan& a, const SlicingPlan& b) {
  EXPECT_EQ(a.storage, b.storage);
  EXPECT_EQ(a.reconstruction, b.reconstruction);
  EXPECT_EQ(a.spacing, b.spacing);
  EXPECT_EQ(a.orientations, b.orientations);
  ASSERT_EQ(a.planes.size(), b.planes.size());
  for (std::size_t i = 0; i < a.planes.size(); ++i) {
    EXPECT_EQ(a.planes[i].orientation, b.planes[i].orientation) << i;
    EXPECT_EQ(a.planes[i].offset, b.planes[i].offset) << i;
    EXPECT_EQ(a.planes[i].normal, b.planes[i].normal) << i;
    EXPECT_EQ(a.planes[i].u, b.planes[i].u) << i;
    EXPECT_EQ(a.planes[i].w, b.planes[i].w) << i;
  }
}

TEST(PlanFile, LatticePlanRoundTripsAndCoversAgainToTheSamePlanes) {
  test::TempDir dir;
  const ClothGenerator cloth(ClothKind::Roll, {16, 2, 24.0, 0});
  const Frame frame = cloth.frame(0);
  DiffusePlanParams params;
  params.orientations = 11;
  SlicingPlan plan = make_diffuse_plan(cloth.topology(), frame, params);
  plan.storage = ConeStorage::NearestOnFan;
  write_plan_file(dir / "p.json", plan);
  SlicingPlan read = read_plan_file(dir / "p.json");
  EXPECT_TRUE(read.planes.empty());  // a lattice is stored without its planes
  cover_with_planes(read, cloth_bounds(cloth.topology(), frame));
  expect_same_bits(plan, read);
}

TEST(PlanFile, TheReconstructionRuleRoundTrips) {
  // A nearest-circle plan read back as grouped gave other values, silently.
  test::TempDir dir;
  const ClothGenerator cloth(ClothKind::Roll, {16, 2, 24.0, 0});
  SlicingPlan plan = make_diffuse_plan(cloth.topology(), cloth.frame(0), {});
  for (const ConeReconstruction rule : {ConeReconstruction::NearestCircle, ConeReconstruction::Grouped}) {
    plan.reconstruction = rule;
    write_plan_file(dir / "p.json", plan);
    EXPECT_EQ(read_plan_file(dir / "p.json").reconstruction, rule);
  }
  // A file without one (written before it was saved) holds a grouped plan; a bad name is refused.
  std::ofstream(dir / "old.json")
      << R"({"pleat_plan": 1, "storage": "aimed-on-fan", "orientations": [[0, 0, 1]],
                                         "spacing": 0.1})";
  EXPECT_EQ(read_plan_file(dir / "old.json").reconstruction, ConeReconstruction::Grouped);
  std::ofstream(dir / "bad.json") << R"({"pleat_plan": 1, "storage": "aimed-on-fan", "reconstruction": "best",
                                         "orientations": [[0, 0, 1]], "spacing": 0.1})";
  try {
    read_plan_file(dir / "bad.json");
    FAIL() << "an unknown reconstruction rule";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("reconstruction"), std::string::npos) << e.what();
  }
}

TEST(PlanFile, ListedPlanRoundTripsBitForBit) {
  test::TempDir dir;
  const ClothGenerator cloth(ClothKind::Flag, {15, 2, 24.0, 2});
  const Frame frame = cloth.frame(1);
  for (const SlicingPlan& plan : {make_adaptive_plan(cloth.topology(), frame, {7, 0.1}),
                                  make_point_light_plan(cloth.topology(), frame, {0.3, 2.0, -1.0}),
                                  make_diffuse_plan(cloth.topology(), frame, {5, 0.0, 9})}) {
    ASSERT_EQ(plan.spacing, 0.0);
    ASSERT_FALSE(plan.planes.empty());
    write_plan_file(dir / "p.json", plan);
    expect_same_bits(plan, read_plan_file(dir / "p.json"));
  }
}

TEST(PlanFile, MalformedFilesNameTheFileAndThePlace) {
  test::TempDir dir;
  const std::string lattice =
      R"({"pleat_plan": 1, "storage": "nearest-on-fan", "orientations": [[0, 0, 1]], )";
  const std::pair<std::string, std::string> cases[] = {
      {"{\"pleat_plan\": 1, ", "byte"},
      {"[1, 2]", "no \"pleat_plan\""},
      {R"({"pleat_plan": 2})", "pleat_plan: version 2"},
      {R"({"pleat_plan": 1, "storage": "sideways", "orientations": [[0, 0, 1]], "spacing": 1})", "storage:"},
      {R"({"pleat_plan": 1, "storage": "nearest-on-fan", "orientations": [], "spacing": 1})",
       "orientations:"},
      {lattice + R"("spacing": 0})", "spacing: must be positive"},
      {lattice + R"("spacing": "wide"})", "spacing: expected a number"},
      {R"({"pleat_plan": 1, "storage": "nearest-on-fan", "orientations": [[0, 0, 0]], "spacing": 1})",
       "orientations[0]: a zero direction"},
      {lattice + R"("spacing": 1, "planes": []})", "either"},
      {lattice + R"("planes": [{"orientation": 3, "offset": 0, "normal": [0, 0, 1], "u": [1, 0, 0],
          "w": [0, 1, 0]}]})",
       "planes[0]: orientation 3 does not exist"},
      {lattice + R"("planes": [{"orientation": 0, "offset": 0, "normal": [0, 0, 1], "u": [1, 0]}]})",
       "planes[0].u: expected [x, y, z]"},
  };
  for (const auto& [text, expected] : cases) {
    std::ofstream(dir / "bad.json") << text;
    try {
      read_plan_file(dir / "bad.json");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find((dir / "bad.json").string()), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what() << " for " << text;
    }
  }
  EXPECT_THROW(read_plan_file(dir / "missing.json"), InputError);
}

}  // namespace
}  // namespace pleat
