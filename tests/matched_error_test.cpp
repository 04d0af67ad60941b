// The frame-coherence benchmark's accuracy measures (bench/coherence/matched_error): error statistics and
// flicker against hand-computed values and a brute-force sort; matched_rays against an exact power law (where
// log-log interpolation is exact) and, on random ladders, against the brute-force bracket and monotonicity.
#include "bench/coherence/matched_error.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace pleat::bench {
namespace {

TEST(MatchedError, ErrorStatsPoolFramesAndSkipUnestimatedValues) {
  const std::vector<SkyValues> a{{0.5, 0.2, 0.9}, {1.0, 0.0, 0.3}};
  const std::vector<SkyValues> ref{{0.4, NAN, 0.9}, {0.7, 0.1, NAN}};
  const ErrorStats s = error_stats(a, ref);
  EXPECT_EQ(s.count, 4u);
  EXPECT_NEAR(s.mean, (0.1 + 0.0 + 0.3 + 0.1) / 4, 1e-15);
  EXPECT_NEAR(s.p95, 0.3, 1e-15);
  EXPECT_THROW(error_stats(a, std::vector<SkyValues>{{0.1, 0.2, 0.3}}), std::invalid_argument);
  EXPECT_THROW(error_stats(a, std::vector<SkyValues>{{0.1}, {0.2}}), std::invalid_argument);
}

RC_GTEST_PROP(MatchedError, P95IsTheSortedValueAtTheCeiling, ()) {
  const auto values = *rc::gen::nonEmpty(rc::gen::container<std::vector<int>>(rc::gen::inRange(0, 1000)));
  SkyValues a, ref;
  for (int v : values) a.push_back(v / 1000.0), ref.push_back(0.0);
  std::vector<double> sorted = a;
  std::sort(sorted.begin(), sorted.end());
  const std::size_t k = static_cast<std::size_t>(std::ceil(0.95 * double(sorted.size()))) - 1;
  const ErrorStats s = error_stats(std::vector<SkyValues>{a}, std::vector<SkyValues>{ref});
  RC_ASSERT(s.p95 == sorted[k]);
}

TEST(MatchedError, FlickerIsTheChangeNotInTheReference) {
  // The estimate is the reference plus a constant bias: no flicker, however large the bias.
  const std::vector<SkyValues> ref{{0.1, 0.5}, {0.3, 0.4}, {0.2, 0.9}};
  std::vector<SkyValues> biased = ref;
  for (auto& f : biased)
    for (double& x : f) x += 0.25;
  EXPECT_NEAR(flicker(biased, ref), 0.0, 1e-15);
  // A constant estimate flickers by the reference's own changes: |0.2|, |0.1|, |0.1|, |0.5| -> mean 0.225.
  const std::vector<SkyValues> still{{0.5, 0.5}, {0.5, 0.5}, {0.5, 0.5}};
  EXPECT_NEAR(flicker(still, ref), (0.2 + 0.1 + 0.1 + 0.5) / 4, 1e-15);
  EXPECT_TRUE(std::isnan(flicker(std::vector<SkyValues>{{0.5}}, std::vector<SkyValues>{{0.4}})));
}

TEST(MatchedError, PowerLawIsRecoveredExactly) {
  // err = 0.4 / sqrt(K), ms = 0.02 K: straight lines in log-log, so interpolation is exact.
  std::vector<Rung> ladder;
  for (double k : {8, 12, 16, 24, 32, 48, 64, 96, 128, 256, 1024})
    ladder.push_back({k, 0.02 * k, 0.4 / std::sqrt(k), 0.1 / std::sqrt(k)});
  for (double target : {0.1, 0.05, 0.037, 0.02, 0.0125}) {
    const MatchedRays m = matched_rays(ladder, target);
    const double k = std::pow(0.4 / target, 2);
    EXPECT_EQ(m.bound, MatchedRays::Bound::Inside) << target;
    EXPECT_NEAR(m.rays, k, 1e-9 * k) << target;
    EXPECT_NEAR(m.ms, 0.02 * k, 1e-9 * k) << target;
    EXPECT_NEAR(m.flicker, 0.1 / std::sqrt(k), 1e-12) << target;
  }
  const MatchedRays below = matched_rays(ladder, 0.5);  // worse than 8 rays
  EXPECT_EQ(below.bound, MatchedRays::Bound::Below);
  EXPECT_EQ(below.rays, 8);
  const MatchedRays above = matched_rays(ladder, 0.001);  // better than 1024 rays
  EXPECT_EQ(above.bound, MatchedRays::Bound::Above);
  EXPECT_EQ(above.rays, 1024);
  EXPECT_THROW(matched_rays({}, 0.1), std::invalid_argument);
  std::vector<Rung> unsorted{{16, 1, 0.1, 0}, {8, 1, 0.2, 0}};
  EXPECT_THROW(matched_rays(unsorted, 0.1), std::invalid_argument);
}

RC_GTEST_PROP(MatchedError, KStarLiesInTheBruteForceBracket, ()) {
  // Random noisy ladders (errors not monotone): K* is between the first rung with error <= target and the
  // rung before it, found by a linear scan; its time between theirs.
  const int n = *rc::gen::inRange(2, 12);
  std::vector<Rung> ladder;
  double k = 4;
  for (int i = 0; i < n; ++i) {
    k *= 1.2 + *rc::gen::inRange(0, 100) / 50.0;
    ladder.push_back(
        {k, 0.01 * k * (1 + *rc::gen::inRange(0, 10) / 100.0), *rc::gen::inRange(1, 1000) / 1000.0, 0.01});
  }
  const double target = *rc::gen::inRange(1, 1000) / 1000.0;
  const MatchedRays m = matched_rays(ladder, target);
  std::size_t first = 0;
  while (first < ladder.size() && ladder[first].error > target) ++first;
  if (first == 0) {
    RC_ASSERT(m.bound ==
              (ladder[0].error == target ? MatchedRays::Bound::Inside : MatchedRays::Bound::Below));
    RC_ASSERT(m.rays == ladder[0].rays);
  } else if (first == ladder.size()) {
    RC_ASSERT(m.bound == MatchedRays::Bound::Above);
    RC_ASSERT(m.rays == ladder.back().rays);
  } else {
    const Rung& lo = ladder[first - 1];
    const Rung& hi = ladder[first];
    RC_ASSERT(m.bound == MatchedRays::Bound::Inside);
    RC_ASSERT(m.rays >= lo.rays * (1 - 1e-12) && m.rays <= hi.rays * (1 + 1e-12));
    RC_ASSERT(m.ms >= std::min(lo.ms, hi.ms) * (1 - 1e-12) && m.ms <= std::max(lo.ms, hi.ms) * (1 + 1e-12));
  }
}

}  // namespace
}  // namespace pleat::bench
