// Angular sets (static_core/angular_set.hpp): the O(k) half-turn clip of the 3D assembly against the general
// intersection (intersect_wedges) on random united sets, including wedges that wrap past 2pi, full turns,
// ends exactly on the half-turn's ends, and half-turns that wrap; the blend of two sets (blend_wedges, the
// interpolated-on-fan storage) against the set built directly from known end motions; wrap_angle against its
// definition by fmod.
#include "static_core/angular_set.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <glm/geometric.hpp>
#include <tuple>
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

/// wrap_angle skips fmod within a turn, where fmod returns its argument: bit for bit the definition, on
/// random angles of a few turns and on the boundaries.
TEST(AngularSet, WrapAngleIsItsDefinitionByFmod) {
  auto definition = [](double a) {
    a = std::fmod(a, kTwoPi);
    if (a < 0) a += kTwoPi;
    return a >= kTwoPi ? 0.0 : a;
  };
  std::vector<double> angles = {0.0,
                                -0.0,
                                kTwoPi,
                                -kTwoPi,
                                kTwoPi / 2,
                                -kTwoPi / 2,
                                1e-300,
                                -1e-300,
                                std::nextafter(kTwoPi, 0.0),
                                -std::nextafter(kTwoPi, 0.0),
                                std::nextafter(kTwoPi, 10.0),
                                -std::nextafter(kTwoPi, 10.0),
                                3 * kTwoPi,
                                1e9};
  std::uint64_t state = 12345;
  for (int i = 0; i < 100000; ++i) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    angles.push_back((double(state >> 11) / double(1ull << 53) - 0.5) * 8 * kTwoPi);
  }
  for (const double a : angles) {
    const double got = wrap_angle(a), want = definition(a);
    EXPECT_TRUE(got == want && std::signbit(got) == std::signbit(want)) << a << ": " << got << " vs " << want;
  }
  EXPECT_TRUE(std::isnan(wrap_angle(std::nan(""))));
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
  std::vector<AngularInterval> scratch;
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

/// k disjoint wedges from 2k distinct angles round the circle, and for each end a motion small enough to keep
/// the order: the sets at both ends of a blend, and what the blend must be in between.
struct MovingWedges {
  std::vector<Wedge> at0;
  std::vector<std::pair<double, double>> moves;  // per wedge: the turn of its start and of its end
  std::vector<Wedge> at(double t) const {
    std::vector<Wedge> out;
    for (std::size_t i = 0; i < at0.size(); ++i) {
      const double start = at0[i].start + t * moves[i].first;
      out.push_back({wrap_angle(start), at0[i].end() + t * moves[i].second - start});
    }
    return out;
  }
};

MovingWedges gen_moving_wedges(int k) {
  // 2k gaps of random positive weights round the circle from a random origin.
  std::vector<double> gaps(2 * k);
  double total = 0;
  for (double& g : gaps) total += g = *rc::gen::inRange(1, 101);
  double least = kTwoPi;
  for (double& g : gaps) least = std::min(least, g *= kTwoPi / total);
  double at = *rc::gen::inRange(0, 1 << 20) * (kTwoPi / (1 << 20));
  MovingWedges m;
  for (int i = 0; i < k; ++i) {
    const double start = at;
    at += gaps[2 * i];
    m.at0.push_back({wrap_angle(start), gaps[2 * i]});
    at += gaps[2 * i + 1];
    // Each end moves by less than a third of the narrowest gap, so the order is kept.
    auto move = [&] { return *rc::gen::inRange(-1000, 1001) / 1000.0 * least / 3.0; };
    const double ds = move(), de = move();
    m.moves.emplace_back(ds, de);
  }
  return m;
}

std::vector<Wedge> united(const std::vector<Wedge>& raw) {
  std::vector<AngularInterval> scratch;
  std::vector<Wedge> out;
  unite_wedges(raw, scratch, out);
  return out;
}

RC_GTEST_PROP(AngularSet, BlendMovesEveryEndLinearly, ()) {
  const MovingWedges m = gen_moving_wedges(*rc::gen::inRange(1, 6));
  const std::vector<Wedge> a = united(m.at(0.0)), b = united(m.at(1.0));
  RC_ASSERT(a.size() == m.at0.size() && b.size() == m.at0.size());
  const double t = *rc::gen::element(0.0, 1.0, 0.5, *rc::gen::inRange(0, 1001) / 1000.0);
  WedgeScratch scratch;
  std::vector<Wedge> blend, reverse;
  RC_ASSERT(blend_wedges(a, b, t, scratch, blend));
  RC_ASSERT(is_united(blend));
  RC_ASSERT(difference(blend, m.at(t)) < 1e-12);
  RC_ASSERT(std::abs(AngularSet::from_wedges(blend).measure() -
                     ((1 - t) * AngularSet::from_wedges(a).measure() +
                      t * AngularSet::from_wedges(b).measure())) < 1e-12);
  RC_ASSERT(blend_wedges(b, a, 1.0 - t, scratch, reverse));  // symmetric
  RC_ASSERT(difference(blend, reverse) < 1e-12);
  std::vector<Wedge> same;
  RC_ASSERT(blend_wedges(a, a, t, scratch, same));
  RC_ASSERT(difference(same, a) < 1e-12);
}

RC_GTEST_PROP(AngularSet, BlendGrowsAWedgeOrAGapFromNothing, ()) {
  // b has k wedges; a lacks one of them (a gap closes between the planes) or the gap after one of them (an
  // occluder rises between them): the blend grows the missing wedge or gap from nothing at its middle, by
  // t of its width at b, while every other end moves linearly.
  const int k = *rc::gen::inRange(2, 6);
  const MovingWedges m = gen_moving_wedges(k);
  const std::vector<Wedge> at0 = m.at(0.0), at1 = m.at(1.0);
  const std::size_t i = *rc::gen::inRange(0, k), next = (i + 1) % k;
  const bool gap = *rc::gen::arbitrary<bool>();
  const double t = *rc::gen::element(0.0, 1.0, 0.5, *rc::gen::inRange(0, 1001) / 1000.0);
  std::vector<Wedge> a_raw, expected = m.at(t);
  if (!gap) {
    RC_PRE(at1[i].width / 2 < kMaxBlendTurn);
    for (std::size_t j = 0; j < at0.size(); ++j)
      if (j != i) a_raw.push_back(at0[j]);
    const double middle = at1[i].start + at1[i].width / 2;
    expected[i] = {wrap_angle(middle - t * at1[i].width / 2), t * at1[i].width};
  } else {
    const double width = wrap_angle(at1[next].start - at1[i].end());  // of b's gap after wedge i
    RC_PRE(width / 2 < kMaxBlendTurn);
    for (std::size_t j = 0; j < at0.size(); ++j)
      if (j != i && j != next) a_raw.push_back(at0[j]);
    a_raw.push_back({at0[i].start, wrap_angle(at0[next].end() - at0[i].start)});  // i and next as one
    const double middle = at1[i].end() + width / 2;
    expected[i].width = wrap_angle(middle - t * width / 2 - expected[i].start);
    const double end = expected[next].end();
    expected[next] = {wrap_angle(middle + t * width / 2), wrap_angle(end - (middle + t * width / 2))};
  }
  const std::vector<Wedge> a = united(a_raw), b = united(at1);
  RC_ASSERT(a.size() + 1 == b.size());
  WedgeScratch scratch;
  std::vector<Wedge> blend, reverse;
  RC_ASSERT(blend_wedges(a, b, t, scratch, blend));
  RC_ASSERT(is_united(blend) || blend.empty());
  RC_ASSERT(difference(blend, expected) < 1e-9);
  RC_ASSERT(blend_wedges(b, a, 1.0 - t, scratch, reverse));  // symmetric
  RC_ASSERT(difference(blend, reverse) < 1e-9);
}

TEST(AngularSet, BlendRefusesSetsThatDoNotMatch) {
  WedgeScratch scratch;
  std::vector<Wedge> out;
  const std::vector<Wedge> one{{1.0, 0.5}}, three{{1.0, 0.2}, {2.0, 0.3}, {3.0, 0.3}}, full{{0.0, kTwoPi}};
  EXPECT_FALSE(blend_wedges(one, three, 0.5, scratch, out));  // two wedges appear
  EXPECT_FALSE(blend_wedges({}, one, 0.5, scratch, out));     // a wedge from an empty set
  EXPECT_FALSE(blend_wedges(one, full, 0.5, scratch, out));   // a full turn against a wedge
  const std::vector<Wedge> far{{1.0 + kTwoPi / 2, 0.5}};
  EXPECT_FALSE(blend_wedges(one, far, 0.5, scratch, out));  // ends that would turn by half a turn
  const std::vector<Wedge> complement{{1.5, kTwoPi - 0.5}};
  EXPECT_FALSE(blend_wedges(one, complement, 0.5, scratch, out));  // same ends, the other way round
  EXPECT_TRUE(out.empty());
  EXPECT_TRUE(blend_wedges(full, full, 0.3, scratch, out));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].width, kTwoPi);
  out.clear();
  EXPECT_TRUE(blend_wedges({}, {}, 0.3, scratch, out));
  EXPECT_TRUE(out.empty());
  // Across 0: a wedge that wraps blends with one that no longer does.
  const std::vector<Wedge> wraps{{6.2, 0.3}}, after{{0.1, 0.3}};
  EXPECT_TRUE(blend_wedges(wraps, after, 0.5, scratch, out));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(std::remainder(out[0].start - (6.2 + 0.5 * (0.1 + kTwoPi - 6.2)), kTwoPi), 0.0, 1e-12);
  EXPECT_NEAR(out[0].width, 0.3, 1e-12);
}

// aim_wedges: a 2D cone at one apex seen from another viewpoint through the horizon points its ends carry.

/// The visible set from `x` of a wall, the segment [p, q] (x not on its line): the complement of the wedge
/// the wall blocks, its ends carrying their reaches to the wall's ends.
std::vector<Wedge> visible_past_wall(const glm::dvec2& x, const glm::dvec2& p, const glm::dvec2& q) {
  const glm::dvec2 dp = p - x, dq = q - x;
  const bool left = dp.x * dq.y - dp.y * dq.x > 0;  // the wall spans p -> q counter-clockwise
  return united({left ? wedge_between(dq, dp) : wedge_between(dp, dq)});
}

glm::dvec2 gen_point(double scale) {
  return {scale * (*rc::gen::inRange(-1000, 1001) / 1000.0),
          scale * (*rc::gen::inRange(-1000, 1001) / 1000.0)};
}

double cross2(const glm::dvec2& a, const glm::dvec2& b) { return a.x * b.y - a.y * b.x; }

RC_GTEST_PROP(AngularSet, AimingAtAWallsEndsSeesItFromTheEye, ()) {
  // A wall's silhouette points are its ends, whatever the viewpoint: the cone at the apex, aimed from the
  // eye, is the eye's own cone exactly (while no end turns by more than kMaxAimTurn).
  const glm::dvec2 p = gen_point(10.0), q = gen_point(10.0);
  const glm::dvec2 apex = gen_point(1.0), eye = apex + gen_point(0.3);
  RC_PRE(glm::length(q - p) > 1.0);
  RC_PRE(std::abs(cross2(q - p, apex - p)) > 0.5 * glm::length(q - p));  // well off the wall's line
  RC_PRE(std::abs(cross2(q - p, eye - p)) > 0.5 * glm::length(q - p));
  RC_PRE(cross2(q - p, apex - p) * cross2(q - p, eye - p) > 0);  // the same side of it
  const std::vector<Wedge> from_apex = visible_past_wall(apex, p, q), from_eye = visible_past_wall(eye, p, q);
  for (const glm::dvec2& end : {p, q}) {  // within the aiming's reach
    const double turn =
        std::acos(std::clamp(glm::dot(glm::normalize(end - apex), glm::normalize(end - eye)), -1.0, 1.0));
    RC_PRE(turn < kMaxAimTurn - 1e-6);
  }
  WedgeScratch scratch;
  std::vector<Wedge> aimed;
  RC_ASSERT(aim_wedges(from_apex, apex, from_apex, apex, 0.0, eye, scratch, aimed));
  RC_ASSERT(is_united(aimed));
  RC_ASSERT(difference(aimed, from_eye) < 1e-5);  // reaches are floats
}

RC_GTEST_PROP(AngularSet, AimingBetweenTwoPlanesFollowsAStraightEdge, ()) {
  // Two parallel planes at heights 0 and 1 cut a wall whose ends are straight lines: its ends lie at p0, q0
  // in the lower plane and p1, q1 in the upper one (one 2D frame). An eye at height t sees the wall's cut
  // there, whose ends are the blends at t: aiming the two planes' cones from the eye gives exactly the eye's
  // cone.
  const glm::dvec2 p0 = gen_point(10.0), q0 = gen_point(10.0);
  const glm::dvec2 p1 = p0 + gen_point(0.5), q1 = q0 + gen_point(0.5);
  const glm::dvec2 apex0 = gen_point(1.0), apex1 = apex0 + gen_point(0.3);
  const double t = *rc::gen::inRange(0, 1001) / 1000.0;
  const glm::dvec2 eye = apex0 + t * (apex1 - apex0) + gen_point(0.1);
  const glm::dvec2 pt = p0 + t * (p1 - p0), qt = q0 + t * (q1 - q0);
  for (const auto& [x, a, b] :
       {std::tuple{apex0, p0, q0}, std::tuple{apex1, p1, q1}, std::tuple{eye, pt, qt}}) {
    RC_PRE(glm::length(b - a) > 1.0);
    RC_PRE(std::abs(cross2(b - a, x - a)) > 0.5 * glm::length(b - a));
    RC_PRE(cross2(b - a, x - a) * cross2(q0 - p0, apex0 - p0) > 0);
  }
  const std::vector<Wedge> lo = visible_past_wall(apex0, p0, q0), hi = visible_past_wall(apex1, p1, q1);
  const std::vector<Wedge> expected = visible_past_wall(eye, pt, qt);
  WedgeScratch scratch;
  std::vector<Wedge> blended, aimed;
  RC_PRE(blend_wedges(lo, hi, t, scratch, blended));  // the two cones match
  RC_ASSERT(aim_wedges(lo, apex0, hi, apex1, t, eye, scratch, aimed));
  // Where the blended angle and the eye's own differ by more than kMaxAimTurn the end is left blended.
  RC_PRE(aimed.size() == 1 && expected.size() == 1);
  RC_PRE(std::abs(aimed[0].start - blended[0].start) < kMaxAimTurn - 1e-6);
  RC_ASSERT(difference(aimed, expected) < 1e-5);  // reaches are floats
}

RC_GTEST_PROP(AngularSet, AimingNeverTurnsAnEndFurtherThanItsLimit, ()) {
  // Whatever the reaches and the eye, each end of the aimed set lies within kMaxAimTurn of the blended one:
  // the aimed set lies within that margin of the blend, and without reaches aiming is blending.
  const MovingWedges m = gen_moving_wedges(*rc::gen::inRange(1, 5));
  std::vector<Wedge> a = united(m.at(0.0)), b = united(m.at(1.0));
  const bool with_reaches = *rc::gen::arbitrary<bool>();
  for (auto* set : {&a, &b})
    for (Wedge& w : *set) {
      w.start_reach = with_reaches ? float(*rc::gen::inRange(1, 2000) / 100.0) : INFINITY;
      w.end_reach = with_reaches ? float(*rc::gen::inRange(1, 2000) / 100.0) : INFINITY;
    }
  const double t = *rc::gen::inRange(0, 1001) / 1000.0;
  const glm::dvec2 apex_a = gen_point(1.0), apex_b = gen_point(1.0), eye = gen_point(3.0);
  WedgeScratch scratch;
  std::vector<Wedge> blended, aimed;
  RC_ASSERT(blend_wedges(a, b, t, scratch, blended));
  RC_ASSERT(aim_wedges(a, apex_a, b, apex_b, t, eye, scratch, aimed));
  RC_ASSERT(is_united(aimed) || aimed.size() <= 1);
  if (!with_reaches) RC_ASSERT(difference(aimed, blended) < 1e-12);
  // Every aimed direction is within kMaxAimTurn of a blended one.
  const AngularSet near_blend = [&] {
    std::vector<Wedge> grown;
    for (const Wedge& w : blended)
      grown.push_back({wrap_angle(w.start - kMaxAimTurn), std::min(kTwoPi, w.width + 2 * kMaxAimTurn)});
    return AngularSet::from_wedges(grown);
  }();
  RC_ASSERT(AngularSet::from_wedges(aimed).subtract(near_blend).measure() < 1e-9);
}

TEST(AngularSet, UnionsKeepTheReachesOfTheirEnds) {
  std::vector<AngularInterval> scratch;
  std::vector<Wedge> out;
  // Two overlapping wedges: the union runs from the first's start to the second's end, with their reaches;
  // a third wraps past 2pi onto the first.
  unite_wedges(std::vector<Wedge>{{1.0, 1.0, 5.0f, 6.0f}, {1.5, 1.0, 7.0f, 8.0f}, {6.0, 1.5, 9.0f, 10.0f}},
               scratch, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_DOUBLE_EQ(out[0].start, 6.0);
  EXPECT_NEAR(out[0].end(), kTwoPi + 2.5, 1e-12);
  EXPECT_EQ(out[0].start_reach, 9.0f);
  EXPECT_EQ(out[0].end_reach, 8.0f);
  // A clip to a half-turn cuts at the horizon, which no point bounds.
  std::vector<Wedge> clipped;
  clip_to_half_turn(std::vector<Wedge>{{1.0, 2.0, 5.0f, 6.0f}}, 1.5, clipped);
  ASSERT_EQ(clipped.size(), 1u);
  EXPECT_DOUBLE_EQ(clipped[0].start, 1.5);
  EXPECT_TRUE(std::isinf(clipped[0].start_reach));
  EXPECT_EQ(clipped[0].end_reach, 6.0f);
}

}  // namespace
}  // namespace pleat
