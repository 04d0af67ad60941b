// The cone of a vertex's fan (static_core/internal/fan_cone.hpp): fan_local_ranges against the fan itself
// (which side of it a short step in each direction lands on), fan_cone against a direction-by-direction
// statement of its rule, on random and degenerate input; and the engine on a crease's closed forms. (What the
// rule buys against ray casting: visibility_accuracy_test, SharpFans…)
#include "static_core/internal/fan_cone.hpp"

#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <optional>
#include <vector>

#include "oracles/test_meshes.hpp"
#include "static_core/internal/frame_assembly.hpp"
#include "static_core/mesh_connectivity.hpp"
#include "static_core/visibility.hpp"

namespace pleat {
namespace {

constexpr double kPi = 3.14159265358979323846;

bool contains(std::span<const AngularInterval> set, double angle) {
  for (const AngularInterval& x : set)
    if (x.lo <= angle && angle <= x.hi) return true;
  return false;
}

bool contains(std::span<const Wedge> set, double angle) {
  for (const Wedge& w : set)
    if (wrap_angle(angle - w.start) <= w.width) return true;
  return false;
}

/// Angular distance from `angle` to the nearest of `ends`.
double distance_to(const std::vector<double>& ends, double angle) {
  double d = INFINITY;
  for (double e : ends) d = std::min(d, std::abs(std::remainder(angle - e, 2 * kPi)));
  return d;
}

// ---- fan_local_ranges ------------------------------------------------------------------------------------

/// A closed fan around vertex 0 at the origin, a height field over z = 0: `n` neighbours at increasing
/// angles (counter-clockwise seen from +z) with the given radii and heights; triangles (0, i, i + 1).
struct Fan {
  MeshTopology topology;
  Frame frame;
};

Fan make_fan(const std::vector<double>& angles, const std::vector<double>& radii,
             const std::vector<double>& z) {
  Fan fan;
  const Index n = static_cast<Index>(angles.size());
  fan.topology.num_vertices = n + 1;
  fan.frame.positions.push_back(glm::dvec3(0.0));
  for (Index i = 0; i < n; ++i)
    fan.frame.positions.push_back({radii[i] * std::cos(angles[i]), radii[i] * std::sin(angles[i]), z[i]});
  for (Index i = 0; i < n; ++i) fan.topology.triangles.push_back({0, 1 + i, 1 + (i + 1) % n});
  return fan;
}

/// Which side of the fan (a height field over the xy-plane) point p lies on: true above it (the front,
/// which the counter-clockwise triangles' normals face), false below; nullopt when p projects onto no
/// triangle's sector or lies on the fan.
std::optional<bool> above_fan(const Fan& fan, const glm::dvec3& p) {
  const auto& q = fan.frame.positions;
  const double at = std::atan2(p.y, p.x);
  for (const Triangle& t : fan.topology.triangles) {
    const glm::dvec3 &a = q[t[1]], &b = q[t[2]];
    const double width = wrap_angle(std::atan2(b.y, b.x) - std::atan2(a.y, a.x));
    const double from_a = wrap_angle(at - std::atan2(a.y, a.x));
    if (!(from_a < width)) continue;
    const glm::dvec3 n = glm::cross(a, b);  // through the origin (vertex 0)
    const double side = glm::dot(n, p);
    if (side == 0) return std::nullopt;
    return side > 0;
  }
  return std::nullopt;
}

RC_GTEST_PROP(FanLocalRanges, ARandomFansTwoSidesAreTheDirectionsAboveAndBelowIt, ()) {
  {
    const int n = *rc::gen::inRange(3, 9);
    std::vector<double> angles, radii, z;
    double at = 0;
    for (int i = 0; i < n; ++i) {  // gaps below a half-turn each: the fan is a height field around 0
      at += (2 * kPi / n) * (0.55 + 0.9 * *rc::gen::inRange(0, 1000) / 1000.0);
      angles.push_back(at);
    }
    for (double& a : angles) a *= 2 * kPi / at;  // closed: the last gap ends where the first began
    for (int i = 0; i < n; ++i) {
      radii.push_back(0.5 + *rc::gen::inRange(0, 1000) / 1000.0);
      z.push_back((*rc::gen::inRange(-1000, 1001) / 1000.0) * 1.5 * radii.back());
    }
    const Fan fan = make_fan(angles, radii, z);
    const MeshConnectivity connectivity(fan.topology);
    const glm::dvec3 normal = glm::normalize(
        glm::dvec3(*rc::gen::inRange(-100, 101), *rc::gen::inRange(-100, 101), *rc::gen::inRange(-100, 101)) +
        glm::dvec3(1e-3, 2e-3, 3e-3));
    const SlicingPlane plane = make_plane(normal, 0.0, 0);
    std::vector<AngularInterval> front, back;
    if (!fan_local_ranges(fan.topology, connectivity, fan.frame, 0, plane, front, back)) {
      // Only a fan the plane through its apex does not cross has no range: every neighbour on one side.
      bool below = false, above = false;
      for (Index i = 1; i <= Index(n); ++i)
        (glm::dot(normal, fan.frame.positions[i]) > 0 ? above : below) = true;
      RC_ASSERT(!(above && below));
      return;
    }
    std::vector<double> ends;
    for (const auto* set : {&front, &back})
      for (const AngularInterval& x : *set) ends.insert(ends.end(), {x.lo, x.hi});
    for (int k = 0; k < 720; ++k) {
      const double angle = (k + 0.5) * 2 * kPi / 720;
      if (distance_to(ends, angle) < 1e-6) continue;
      const glm::dvec3 d = std::cos(angle) * plane.u + std::sin(angle) * plane.w;
      const std::optional<bool> truth = above_fan(fan, 1e-4 * d);
      if (!truth) continue;
      RC_ASSERT(contains(front, angle) == *truth);
      RC_ASSERT(contains(back, angle) == !*truth);
    }
  }
}

TEST(FanLocalRanges, AnOpenFanBoundsNeitherSide) {
  // The fan of a vertex on the mesh's boundary (one triangle of a closed fan left out): its two sides meet
  // round the boundary, every direction of every plane is in both ranges.
  Fan fan = make_fan({0, 1.5, 3, 4.5}, {1, 1, 1, 1}, {0, 0, 0, 0});
  fan.topology.triangles.pop_back();
  const MeshConnectivity connectivity(fan.topology);
  ASSERT_FALSE(connectivity.has_closed_fan(0));
  std::vector<AngularInterval> front, back;
  for (const glm::dvec3& normal : {glm::dvec3(0, 0, 1), glm::dvec3(1, 0, 0), glm::dvec3(0.3, -0.5, 0.8)}) {
    ASSERT_TRUE(fan_local_ranges(fan.topology, connectivity, fan.frame, 0,
                                 make_plane(glm::normalize(normal), 0.0, 0), front, back));
    ASSERT_EQ(front.size(), 1u);
    ASSERT_EQ(back.size(), 1u);
    EXPECT_EQ(front[0].lo, 0.0);
    EXPECT_EQ(front[0].hi, 2 * kPi);
    EXPECT_EQ(back[0].lo, 0.0);
    EXPECT_EQ(back[0].hi, 2 * kPi);
  }
  // mark_whole_fans takes it, flat as it is (no triangle turns far from its normal).
  std::vector<std::uint8_t> whole;
  mark_whole_fans(fan.topology, connectivity, fan.frame, area_weighted_normals(fan.topology, fan.frame),
                  whole);
  EXPECT_EQ(whole[0], 1);
}

TEST(FanLocalRanges, AFanThePlaneOnlyTouchesGivesNone) {
  // A cone's apex: every neighbour below the horizontal plane through it.
  const Fan fan = make_fan({0, 2, 4}, {1, 1, 1}, {-0.5, -0.2, -0.9});
  const MeshConnectivity connectivity(fan.topology);
  std::vector<AngularInterval> front, back;
  EXPECT_FALSE(
      fan_local_ranges(fan.topology, connectivity, fan.frame, 0, make_plane({0, 0, 1}, 0.0, 0), front, back));
  EXPECT_TRUE(front.empty() && back.empty());
  // A vertical plane crosses it twice: the upper half-turn is the front.
  ASSERT_TRUE(
      fan_local_ranges(fan.topology, connectivity, fan.frame, 0, make_plane({1, 0, 0}, 0.0, 0), front, back));
  const SlicingPlane plane = make_plane({1, 0, 0}, 0.0, 0);
  const double up =
      direction_angle({glm::dot(plane.u, glm::dvec3(0, 0, 1)), glm::dot(plane.w, glm::dvec3(0, 0, 1))});
  EXPECT_TRUE(contains(front, up));
  EXPECT_FALSE(contains(back, up));
}

// ---- fan_cone -------------------------------------------------------------------------------------------

/// Random cuts: per cut, its chain edge angles (or NaN: a chain's end) and its cones on both sides, each
/// within its local range; a vertex range.
struct Cuts {
  std::vector<glm::dvec2> angles;
  SliceCones cones;
  std::vector<AngularInterval> vertex_range;
};

std::vector<Wedge> random_wedges(int count) {
  std::vector<Wedge> w;
  for (int i = 0; i < count; ++i)
    w.push_back({*rc::gen::inRange(0, 6283) / 1000.0, 0.01 + *rc::gen::inRange(0, 3000) / 1000.0});
  return w;
}

Cuts random_cuts(int k) {
  Cuts c;
  c.cones.offsets.push_back(0);
  WedgeScratch scratch;
  std::vector<AngularInterval> iv;
  for (int x = 0; x < k; ++x) {
    const bool chain_end = *rc::gen::inRange(0, 8) == 0;
    // Ranges often repeated or sharing an end: the degenerate cases of nearby cuts.
    const double to_next = *rc::gen::inRange(0, 4) == 0 && x > 0 && !std::isnan(c.angles[0].x)
                               ? c.angles[0].x
                               : *rc::gen::inRange(0, 6283) / 1000.0;
    const double to_previous = wrap_angle(to_next + 0.2 + *rc::gen::inRange(0, 5800) / 1000.0);
    c.angles.push_back(chain_end ? glm::dvec2(NAN) : glm::dvec2(to_next, to_previous));
    for (Side side : kBothSides) {
      std::vector<Wedge> cone = random_wedges(*rc::gen::inRange(0, 4));
      if (!chain_end) {  // within the local range
        const double from = side == Side::Front ? to_next : to_previous;
        const double to = side == Side::Front ? to_previous : to_next;
        const Wedge range{from, wrap_angle(to - from) > 0 ? wrap_angle(to - from) : 2 * kPi};
        std::vector<Wedge> clipped;
        intersect_wedges(cone, std::span<const Wedge>(&range, 1), scratch, clipped);
        cone = clipped;
      }
      std::vector<Wedge> united;
      unite_wedges(cone, iv, united);
      c.cones.wedges.insert(c.cones.wedges.end(), united.begin(), united.end());
      c.cones.offsets.push_back(static_cast<std::uint32_t>(c.cones.wedges.size()));
    }
  }
  std::vector<Wedge> range;
  if (*rc::gen::inRange(0, 5) == 0)
    range.push_back({0.0, 2 * kPi});
  else
    range = random_wedges(*rc::gen::inRange(1, 3));
  std::vector<Wedge> united;
  unite_wedges(range, iv, united);
  split_into_intervals(united, c.vertex_range);
  return c;
}

RC_GTEST_PROP(FanCone, EachDirectionTakesTheNearestCutWhoseRangeHoldsIt, ()) {
  {
    const int k = *rc::gen::inRange(1, 7);
    const Cuts c = random_cuts(k);
    std::vector<Index> order(k);
    for (int i = 0; i < k; ++i) order[i] = Index(i);
    FanConeScratch scratch;
    std::vector<Wedge> out;
    for (Side side : kBothSides) {
      fan_cone(order, c.cones, c.angles, side, c.vertex_range, scratch, out);
      RC_ASSERT(is_united(out));
      std::vector<double> ends;
      for (const AngularInterval& x : c.vertex_range) ends.insert(ends.end(), {x.lo, x.hi});
      for (int x = 0; x < k; ++x) {
        ends.insert(ends.end(), {c.angles[x].x, c.angles[x].y});
        for (const Wedge& w : c.cones.cone(Index(x), side)) ends.insert(ends.end(), {w.start, w.end()});
      }
      for (int s = 0; s < 1000; ++s) {
        const double angle = (s + 0.5) * 2 * kPi / 1000;
        if (distance_to(ends, angle) < 1e-9) continue;
        // The rule, direction by direction.
        bool expected = false;
        if (contains(c.vertex_range, angle))
          for (int x = 0; x < k; ++x) {
            if (std::isnan(c.angles[x].x)) {  // a chain's end ranges over the whole turn
              expected = contains(c.cones.cone(Index(x), side), angle);
              break;
            }
            const double from = side == Side::Front ? c.angles[x].x : c.angles[x].y;
            const double to = side == Side::Front ? c.angles[x].y : c.angles[x].x;
            if (!(wrap_angle(angle - from) <= wrap_angle(to - from))) continue;
            expected = contains(c.cones.cone(Index(x), side), angle);
            break;
          }
        RC_ASSERT(contains(out, angle) == expected);
      }
    }
  }
}

TEST(FanCone, TheNearestCutAloneCoveringTheRangeGivesItsOwnConeThere) {
  // One cut whose range holds the whole vertex range: its cone, cut to the range, reaches kept.
  Cuts c;
  c.angles = {{0.0, kPi}};                                // front: the upper half-turn
  c.cones.wedges = {{0.3, 1.0, 2.5f, 4.0f}, {1.0, 1.0}};  // front; back
  c.cones.offsets = {0, 1, 2};
  c.vertex_range = {{0.1, 3.0}};
  FanConeScratch scratch;
  std::vector<Wedge> out;
  const Index only = 0;
  fan_cone(std::span<const Index>(&only, 1), c.cones, c.angles, Side::Front, c.vertex_range, scratch, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_DOUBLE_EQ(out[0].start, 0.3);
  EXPECT_DOUBLE_EQ(out[0].width, 1.0);
  EXPECT_EQ(out[0].start_reach, 2.5f);
  EXPECT_EQ(out[0].end_reach, 4.0f);
  fan_cone(std::span<const Index>(&only, 1), c.cones, c.angles, Side::Back, c.vertex_range, scratch, out);
  EXPECT_TRUE(out.empty());  // the back cone lies outside the vertex range
}

// ---- in the engine -------------------------------------------------------------------------------------

TEST(FanCone, ACreaseAndItsRidgeKeepTheirClosedForms) {
  // A V-fold's bottom line, its arms turned by pi/2 - alpha from its normal: sharp where sin(alpha) is below
  // kSharpFan. Inside, the lune between the arms (A = sin(alpha)); the outside is a ridge whose arms fall
  // away: the whole hemisphere (A = 1).
  for (double alpha : {kPi / 6, kPi / 4, kPi / 3}) {
    const auto fold = test::v_fold(alpha, 41, 21, 20.0, 10.0);
    FrameMarks marks;
    mark_whole_fans(fold.topology, MeshConnectivity(fold.topology), fold.frame,
                    area_weighted_normals(fold.topology, fold.frame), marks.whole_fans);
    EXPECT_EQ(marks.whole_fans[fold.marked_vertex] != 0, std::sin(alpha) < kSharpFan) << alpha;
    const SlicingPlan plan = make_diffuse_plan(fold.topology, fold.frame, {});
    const FrameVisibility vis = compute_visibility(fold.topology, fold.frame, plan);
    EXPECT_NEAR(vis.measure(Side::Back, fold.marked_vertex).sky_visibility, 1.0, 2e-3) << alpha;
    EXPECT_NEAR(vis.measure(Side::Front, fold.marked_vertex).sky_visibility, std::sin(alpha), 0.01) << alpha;
  }
}

}  // namespace
}  // namespace pleat
