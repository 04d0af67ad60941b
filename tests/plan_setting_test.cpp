// The benchmarks' plan settings (bench/coherence/plan_setting): "orientations:spacing:storage[:spiral]"
// parsed into a DiffusePlanParams and a storage rule, written back by setting_name, and every malformed text
// refused with a message that names the flag and the text.
#include "bench/coherence/plan_setting.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace pleat::bench {
namespace {

TEST(PlanSetting, ParsesEveryField) {
  const Setting s = parse_setting("12:0.75:interpolated-on-fan", "--plans");
  EXPECT_EQ(s.plan.orientations, 12);
  EXPECT_DOUBLE_EQ(s.plan.spacing_in_edges, 0.75);
  EXPECT_TRUE(s.plan.relaxed);
  EXPECT_EQ(s.storage, ConeStorage::InterpolatedOnFan);
  const Setting spiral = parse_setting("8:1:nearer-endpoint:spiral", "--plans");
  EXPECT_FALSE(spiral.plan.relaxed);
  EXPECT_EQ(spiral.storage, ConeStorage::NearerEndpoint);
}

TEST(PlanSetting, TheDefaultSettingIsTheEnginesDefaultPlan) {
  const Setting d;
  EXPECT_EQ(d.plan.orientations, DiffusePlanParams{}.orientations);
  EXPECT_EQ(d.plan.spacing_in_edges, DiffusePlanParams{}.spacing_in_edges);
  EXPECT_EQ(d.storage, SlicingPlan{}.storage);
}

TEST(PlanSetting, NamesReadBack) {
  for (const std::string text : {"6:1:nearer-endpoint", "8:0.5:aimed-on-fan", "24:0.45:nearest-on-fan:spiral",
                                 "16:1.25:interpolated-on-fan"}) {
    EXPECT_EQ(setting_name(parse_setting(text, "--plans")), text);
  }
  EXPECT_EQ(setting_name(setting(12, 0.5, ConeStorage::AimedOnFan)), "12:0.5:aimed-on-fan");
}

TEST(PlanSetting, RefusesMalformedTextNamingFlagAndText) {
  for (const std::string text :
       {"", "12", "12:0.5", "x:0.5:aimed-on-fan", "0:0.5:aimed-on-fan", "-3:0.5:aimed-on-fan",
        "12a:0.5:aimed-on-fan", "12:0:aimed-on-fan", "12:-1:aimed-on-fan", "12:nan:aimed-on-fan",
        "12:inf:aimed-on-fan", "12:0.5x:aimed-on-fan", "12:0.5:aimed", "12:0.5:aimed-on-fan:spiralx",
        "12:0.5:aimed-on-fan:"}) {
    try {
      parse_setting(text, "--plans");
      ADD_FAILURE() << "accepted '" << text << "'";
    } catch (const std::invalid_argument& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("--plans"), std::string::npos) << what;
      EXPECT_NE(what.find("'" + text + "'"), std::string::npos) << what;
    }
  }
}

}  // namespace
}  // namespace pleat::bench
