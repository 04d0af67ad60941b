// Angular sets (static_core/angular_set.hpp): the O(k) half-turn clip of the 3D assembly against the general
// intersection (intersect_wedges) on random united sets, including wedges that wrap past 2pi, full turns,
// ends exactly on the half-turn's ends, and half-turns that wrap.
#include "static_core/angular_set.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <vector>

namespace pleat {
namespace {

/// Total angle where the two sets differ.
double difference(const std::vector<Wedge>& a, const std::vector<Wedge>& b) {
  const AngularSet x = AngularSet::from_wedges(a), y = AngularSet::from_wedges(b);
  return x.subtract(y).measure() + y.subtract(x).measure();
}

/// An angle from a small grid (so ends coincide often) or anywhere.
double gen_angle() {
  if (*rc::gen::inRange(0, 3) == 0) return *rc::gen::inRange(0, 16) * (kTwoPi / 16);
  return *rc::gen::inRange(0, 1 << 20) * (kTwoPi / (1 << 20));
}

TEST(AngularSet, HalfTurnClipOfAFullTurnIsTheHalfTurn) {
  std::vector<Wedge> out;
  const Wedge full[1] = {{1.0, kTwoPi}};
  clip_to_half_turn(full, 5.0, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].start, 5.0);
  EXPECT_DOUBLE_EQ(out[0].width, kTwoPi / 2);
}

TEST(AngularSet, UnitedFormIsRecognised) {
  EXPECT_TRUE(is_united(std::vector<Wedge>{{0.5, 1.0}, {2.0, 1.0}, {6.0, 0.5}}));
  EXPECT_FALSE(is_united(std::vector<Wedge>{{2.0, 1.0}, {0.5, 1.0}}));  // unsorted
  EXPECT_FALSE(is_united(std::vector<Wedge>{{0.5, 1.6}, {2.0, 1.0}}));  // overlapping
  EXPECT_FALSE(is_united(std::vector<Wedge>{{0.5, 1.0}, {6.0, 1.0}}));  // the last wraps onto the first
  EXPECT_FALSE(is_united(std::vector<Wedge>{{-0.1, 1.0}}));             // start outside [0, 2pi)
}

RC_GTEST_PROP(AngularSet, HalfTurnClipEqualsTheIntersection, ()) {
  std::vector<Wedge> raw;
  const int count = *rc::gen::inRange(0, 7);
  for (int i = 0; i < count; ++i) {
    const double width = *rc::gen::inRange(0, 8) == 0 ? kTwoPi : gen_angle() * 0.5 + 1e-9;
    raw.push_back({gen_angle(), width});
  }
  std::vector<std::pair<double, double>> scratch;
  std::vector<Wedge> united;
  unite_wedges(raw, scratch, united);
  RC_ASSERT(is_united(united) || united.size() == 1);
  const double h = wrap_angle(gen_angle());
  std::vector<Wedge> clipped, expected;
  clip_to_half_turn(united, h, clipped);
  WedgeScratch ws;
  const Wedge half[1] = {{h, kTwoPi / 2}};
  intersect_wedges(united, half, ws, expected);
  RC_ASSERT(difference(clipped, expected) < 1e-12);
  for (const Wedge& w : clipped)
    RC_ASSERT(w.start >= 0 && w.start < kTwoPi && w.width > 0 && w.width <= kTwoPi / 2);
}

}  // namespace
}  // namespace pleat
