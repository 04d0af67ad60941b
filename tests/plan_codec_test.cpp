// The slicing plan's one codec (static_core/plan_codec.hpp) and the rule tables (static_core/cone_rules.hpp):
// bytes and JSON round-trip every field of every rule, the fingerprint sees every field, and a plan saved
// by `pleat visibility --save-plan` with a nearest-circle reconstruction cuts and reconstructs the same when
// read back with --plan.
#include "static_core/plan_codec.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include "static_core/cone_rules.hpp"
#include "support/input_error.hpp"
#include "test_support.hpp"

namespace pleat {
namespace {

// Every field of the plan: a field added to either struct must be added to the codec and here (the sizes
// say so when it was not).
static_assert(sizeof(SlicingPlane) == 3 * sizeof(glm::dvec3) + sizeof(double) + sizeof(double),
              "SlicingPlane changed: add the field to static_core/plan_codec.cpp and to expect_every_field");
static_assert(sizeof(SlicingPlan) == 2 * sizeof(std::vector<int>) + 2 * sizeof(double),
              "SlicingPlan changed: add the field to static_core/plan_codec.cpp and to expect_every_field");

void expect_every_field(const SlicingPlan& a, const SlicingPlan& b, bool planes = true) {
  EXPECT_EQ(a.storage, b.storage);
  EXPECT_EQ(a.reconstruction, b.reconstruction);
  EXPECT_EQ(a.spacing, b.spacing);
  EXPECT_EQ(a.orientations, b.orientations);
  if (!planes) return;
  ASSERT_EQ(a.planes.size(), b.planes.size());
  for (std::size_t i = 0; i < a.planes.size(); ++i) {
    EXPECT_EQ(a.planes[i].orientation, b.planes[i].orientation) << i;
    EXPECT_EQ(a.planes[i].offset, b.planes[i].offset) << i;
    EXPECT_EQ(a.planes[i].normal, b.planes[i].normal) << i;
    EXPECT_EQ(a.planes[i].u, b.planes[i].u) << i;
    EXPECT_EQ(a.planes[i].w, b.planes[i].w) << i;
  }
}

/// A listed plan whose every field differs from its default, with doubles that need all 17 digits.
SlicingPlan listed_plan(ConeStorage storage, ConeReconstruction reconstruction) {
  SlicingPlan plan;
  plan.storage = storage;
  plan.reconstruction = reconstruction;
  plan.orientations = {glm::normalize(glm::dvec3(1, 2, 3)), glm::normalize(glm::dvec3(-0.1, 0.7, 1e-9))};
  for (int k = 0; k < 5; ++k) {
    SlicingPlane p = make_plane(plan.orientations[std::size_t(k % 2)], 0.1 * k - 1.0 / 3.0, k % 2);
    p.u = glm::dvec3(1.0 / 3.0, 1e-300, -k);  // any bits, kept as they are
    plan.planes.push_back(p);
  }
  return plan;
}

TEST(PlanCodec, BytesAndJsonRoundTripEveryFieldOfEveryRule) {
  for (std::size_t s = 0; s < cone_storage_rules().size(); ++s)
    for (std::size_t r = 0; r < cone_reconstruction_rules().size(); ++r) {
      SCOPED_TRACE(std::string(cone_storage_rules()[s]->name) + ", " +
                   std::string(cone_reconstruction_rules()[r]->name));
      const SlicingPlan listed = listed_plan(ConeStorage(s), ConeReconstruction(r));
      expect_every_field(listed, plan_from_bytes(plan_to_bytes(listed)));
      expect_every_field(listed, plan_from_json(plan_to_json(listed), "p.json"));
      SlicingPlan lattice = listed;
      lattice.spacing = 0.1 + 1e-17;
      expect_every_field(lattice, plan_from_bytes(plan_to_bytes(lattice)));
      const SlicingPlan read = plan_from_json(plan_to_json(lattice), "p.json");
      expect_every_field(lattice, read, false);  // a lattice's planes are its frames' (planes_for_frame)
      EXPECT_TRUE(read.planes.empty());
    }
}

TEST(PlanCodec, TheFingerprintSeesEveryField) {
  const SlicingPlan plan = listed_plan(ConeStorage::AimedOnFan, ConeReconstruction::Grouped);
  std::set<std::uint64_t> seen{plan_fingerprint(plan)};
  auto differs = [&](auto change) {
    SlicingPlan changed = plan;
    change(changed);
    EXPECT_TRUE(seen.insert(plan_fingerprint(changed)).second);
  };
  differs([](SlicingPlan& p) { p.storage = ConeStorage::NearestOnFan; });
  differs([](SlicingPlan& p) { p.reconstruction = ConeReconstruction::NearestCircle; });
  differs([](SlicingPlan& p) { p.spacing = 0.5; });
  differs([](SlicingPlan& p) { p.orientations[1].z += 1e-12; });
  differs([](SlicingPlan& p) { p.planes[2].normal.x += 1e-12; });
  differs([](SlicingPlan& p) { p.planes[2].offset += 1e-12; });
  differs([](SlicingPlan& p) { p.planes[2].u.y += 1e-12; });
  differs([](SlicingPlan& p) { p.planes[2].w.z += 1e-12; });
  differs([](SlicingPlan& p) { p.planes[2].orientation = 1 - p.planes[2].orientation; });
  EXPECT_EQ(plan_fingerprint(plan), plan_fingerprint(plan_from_bytes(plan_to_bytes(plan))));
}

TEST(PlanCodec, BadBytesAndRuleNamesAreRefused) {
  const std::string bytes = plan_to_bytes(listed_plan(ConeStorage::AimedOnFan, ConeReconstruction::Grouped));
  EXPECT_THROW(plan_from_bytes(bytes.substr(0, bytes.size() - 1)), std::runtime_error);
  std::string no_rule = bytes;
  const std::uint64_t id = cone_storage_rules().size();  // the first value: the storage rule's id
  std::memcpy(no_rule.data(), &id, sizeof id);
  EXPECT_THROW(plan_from_bytes(no_rule), std::invalid_argument);
  const std::string text = R"({"pleat_plan": 1, "storage": "aimed-on-fan", "reconstruction": "best",
                               "orientations": [[0, 0, 1]], "spacing": 0.1})";
  try {
    plan_from_json(text, "p.json");
    FAIL() << "an unknown reconstruction rule";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("p.json"), std::string::npos) << what;
    EXPECT_NE(what.find("reconstruction"), std::string::npos) << what;
    EXPECT_NE(what.find(cone_reconstruction_names()), std::string::npos) << what;
  }
}

TEST(ConeRules, EveryRowIsNamedOnceAndFoundByItsName) {
  std::set<std::string_view> names;
  for (std::size_t i = 0; i < cone_storage_rules().size(); ++i) {
    const ConeStorageRule& rule = *cone_storage_rules()[i];
    EXPECT_TRUE(names.insert(rule.name).second) << rule.name;
    EXPECT_EQ(cone_storage_from_name(rule.name), ConeStorage(i));
    EXPECT_EQ(cone_storage_name(ConeStorage(i)), rule.name);
    EXPECT_NE(cone_storage_names().find(rule.name), std::string::npos);
  }
  for (std::size_t i = 0; i < cone_reconstruction_rules().size(); ++i) {
    const ConeReconstructionRule& rule = *cone_reconstruction_rules()[i];
    EXPECT_TRUE(names.insert(rule.name).second) << rule.name;
    EXPECT_EQ(cone_reconstruction_from_name(rule.name), ConeReconstruction(i));
    EXPECT_TRUE(rule.make() != nullptr);
  }
  EXPECT_THROW(cone_storage_from_name("nearest"), std::invalid_argument);
  EXPECT_THROW(cone_reconstruction_from_name("best"), std::invalid_argument);
}

std::string slurp_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(PlanCodec, ASavedNearestCirclePlanReadsBackAsOne) {
  test::TempDir dir;
  ASSERT_EQ(test::run_pleat("generate flag -o " + (dir / "f.obj").string() + " --resolution 9 --frames 3")
                .exit_code,
            0);
  const std::string input = (dir / "f.obj").string() + " --cache " + (dir / "f.pc2").string();
  auto visibility = [&](const std::string& name, const std::string& options) {
    const auto result =
        test::run_pleat("visibility " + input + " -q -o " + (dir / name).string() + " " + options);
    EXPECT_EQ(result.exit_code, 0) << result.output;
    return slurp_file(dir / name);
  };
  const std::string nearest =
      visibility("n.csv", "--cone-reconstruction nearest-circle --save-plan " + (dir / "plan.json").string());
  const std::string grouped = visibility("g.csv", "");
  EXPECT_NE(nearest, grouped);  // the rule changes the values
  EXPECT_NE(slurp_file(dir / "plan.json").find("\"nearest-circle\""), std::string::npos);
  EXPECT_EQ(visibility("p.csv", "--plan " + (dir / "plan.json").string()), nearest);
  // A name of no rule: the table's names in the message, no output.
  const auto bad = test::run_pleat("visibility " + input + " -o " + (dir / "bad.csv").string() +
                                   " --cone-reconstruction best");
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("nearest-circle"), std::string::npos) << bad.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "bad.csv"));
}

}  // namespace
}  // namespace pleat
