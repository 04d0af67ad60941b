// Occluders as shadows (static_core/internal/occluder_shadows.hpp): the cloth's chains triangulated, the
// occluders' chains cast as shadows, against the brute-force angular sweep over every chain of the slice —
// random chains (nested loops, dangling pieces, collinear and duplicate points) split at random into cloth
// and occluders, convex loops wrapped by the cloth (a sleeve on an arm), cloth in an occluder's pocket.
#include "static_core/internal/occluder_shadows.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "oracles/random_slices.hpp"
#include "oracles/visibility_2d_oracle.hpp"
#include "static_core/internal/slice_triangulation.hpp"

namespace pleat {
namespace {

struct Chains {
  std::vector<std::vector<glm::dvec2>> points;
  std::vector<bool> closed;
};

/// The chains of a slice, walked along its edges.
Chains chains_of(const Slice& slice) {
  Chains out;
  std::vector<char> seen(slice.vertices.size(), 0);
  for (Index start = 0; start < slice.vertices.size(); ++start) {
    if (seen[start]) continue;
    Index first = start;
    for (std::size_t steps = 0; steps < slice.vertices.size(); ++steps) {
      const std::int32_t e = slice.in_edge[first];
      if (e < 0 || slice.edges[e].from == start) break;
      first = slice.edges[e].from;
    }
    std::vector<glm::dvec2> chain;
    bool closed = false;
    for (Index x = first; !seen[x];) {
      seen[x] = 1;
      chain.push_back(slice.vertices[x].point);
      const std::int32_t e = slice.out_edge[x];
      if (e < 0) break;
      x = slice.edges[e].to;
      closed = x == first;
    }
    out.points.push_back(std::move(chain));
    out.closed.push_back(closed);
  }
  return out;
}

std::size_t g_shadowed = 0;    // cones a shadow changed, over the comparisons
std::size_t g_in_contact = 0;  // cloth vertices inside a closed occluder, over the comparisons

/// The brute-force contact rule (docs/method.md §6.2), in doubles: whether p lies inside the closed loops of
/// `occluders` (even-odd over all of them), and then the nearest point q of their segments and the segment.
bool in_contact(const Chains& occluders, const glm::dvec2& p, glm::dvec2& q, std::array<glm::dvec2, 2>& at) {
  bool inside = false;
  double best = INFINITY;
  for (std::size_t c = 0; c < occluders.points.size(); ++c) {
    if (!occluders.closed[c]) continue;
    const auto& loop = occluders.points[c];
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const glm::dvec2 a = loop[i], b = loop[(i + 1) % loop.size()];
      if ((a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y)) inside = !inside;
      const double t = std::clamp(glm::dot(p - a, b - a) / glm::dot(b - a, b - a), 0.0, 1.0);
      const glm::dvec2 near = a + t * (b - a);
      if (glm::distance(p, near) < best) {
        best = glm::distance(p, near);
        q = near;
        at = {a, b};
      }
    }
  }
  return inside;
}

/// Whether the ray from q in direction `angle` meets a segment of `occluders` other than `at` (the one q lies
/// on) and those ending at q, in doubles.
bool blocked_from(const Chains& occluders, const glm::dvec2& q, const std::array<glm::dvec2, 2>& at,
                  double angle) {
  const glm::dvec2 d(std::cos(angle), std::sin(angle));
  for (std::size_t c = 0; c < occluders.points.size(); ++c) {
    const auto& chain = occluders.points[c];
    const std::size_t segments = occluders.closed[c] ? chain.size() : chain.size() - 1;
    for (std::size_t i = 0; i < segments && chain.size() > 1; ++i) {
      const glm::dvec2 a = chain[i], b = chain[(i + 1) % chain.size()];
      if ((a == at[0] && b == at[1]) || a == q || b == q) continue;
      const glm::dvec2 e = b - a, w = a - q;
      const double den = d.x * e.y - d.y * e.x;
      if (den == 0.0) continue;
      const double t = (w.x * e.y - w.y * e.x) / den, u = (w.x * d.y - w.y * d.x) / den;
      if (t > 1e-12 && u >= 0.0 && u <= 1.0) return true;
    }
  }
  return false;
}

/// For a cloth vertex in contact: where the computed cone differs from the cloth's own cone (the oracle on
/// the cloth alone) less what the occluders block seen from q, sampled at 3600 directions; "" when nowhere.
std::string contact_mismatch(const Chains& occluders, const glm::dvec2& q,
                             const std::array<glm::dvec2, 2>& at, const AngularSet& own,
                             const AngularSet& computed) {
  int differ = 0;
  for (int k = 0; k < 3600; ++k) {
    const double angle = (k + 0.5) * 2 * M_PI / 3600;
    differ += computed.contains(angle) != (own.contains(angle) && !blocked_from(occluders, q, at, angle));
  }
  return differ > 2 ? std::to_string(differ) + " of 3600 directions differ seen from the contact point" : "";
}

/// The cloth's chains triangulated and the occluders' cast as shadows, against the oracle on the slice of
/// both: "" when every cloth vertex's cones match on both sides.
std::string compare(const Chains& cloth, const Chains& occluders) {
  const Slice cloth_slice = test::make_slice(cloth.points, cloth.closed);
  const Slice occluder_slice = test::make_slice(occluders.points, occluders.closed);
  Chains both = cloth;
  both.points.insert(both.points.end(), occluders.points.begin(), occluders.points.end());
  both.closed.insert(both.closed.end(), occluders.closed.begin(), occluders.closed.end());
  auto expected = oracle::brute_force_slice_cones(test::make_slice(both.points, both.closed));
  const auto own = oracle::brute_force_slice_cones(cloth_slice);
  SliceTriangulation triangulation;
  triangulation.build(cloth_slice);
  SliceConeScratch scratch;
  SliceCones cones;
  compute_slice_cones(cloth_slice, triangulation, scratch, cones);
  const SliceCones unshadowed = cones;
  ShadowScratch shadow_scratch;
  OccluderChains chains;
  gather_occluder_chains(occluder_slice, shadow_scratch, chains);
  cast_occluder_shadows(cloth_slice, chains, {}, 0.0, shadow_scratch, cones);
  for (Index x = 0; x < cloth_slice.vertices.size(); ++x) {
    for (Side side : kBothSides) {
      const auto now = cones.cone(x, side), before = unshadowed.cone(x, side);
      g_shadowed +=
          oracle::angular_difference(AngularSet::from_wedges({now.begin(), now.end()}),
                                     AngularSet::from_wedges({before.begin(), before.end()})) > 1e-9;
    }
    // Inside a solid occluder: seen from the nearest point of its surface (the contact rule).
    glm::dvec2 q;
    std::array<glm::dvec2, 2> at;
    if (!in_contact(occluders, cloth_slice.vertices[x].point, q, at)) continue;
    ++g_in_contact;
    for (Side side : kBothSides) {
      const auto now = cones.cone(x, side);
      const AngularSet computed = AngularSet::from_wedges({now.begin(), now.end()});
      if (std::string m = contact_mismatch(occluders, q, at, own[x][int(side)], computed); !m.empty())
        return "slice vertex " + std::to_string(x) + " side " + std::to_string(int(side)) + ": " + m;
      expected[x][int(side)] = computed;  // checked here, not by the sweep of the slice of both
    }
  }
  return oracle::first_mismatch(cloth_slice, cones, expected, "shadows");
}

/// A slice's chains split at random into cloth and occluders. A chain with a point in the same place as
/// another chain's goes to the cloth: where cloth and occluder share a vertex, the slice of both bounds the
/// cloth's side ranges by the occluder's edges there, while a shadow blocks only what the occluder's segments
/// subtend (a measure-zero difference of conventions, never met by simulated cloth held off its colliders).
std::string compare_split(const Slice& slice, std::mt19937_64& rng) {
  const Chains all = chains_of(slice);
  Chains cloth, occluders;
  for (std::size_t c = 0; c < all.points.size(); ++c) {
    bool shared = false;
    for (std::size_t d = 0; d < all.points.size() && !shared; ++d)
      for (const glm::dvec2& p : all.points[c])
        shared = shared || (d != c && std::count(all.points[d].begin(), all.points[d].end(), p) > 0);
    Chains& to = shared || rng() % 2 ? cloth : occluders;
    to.points.push_back(all.points[c]);
    to.closed.push_back(all.closed[c]);
  }
  return compare(cloth, occluders);
}

/// A regular n-gon of radius r about c, counter-clockwise.
std::vector<glm::dvec2> polygon(glm::dvec2 c, double r, int n, double phase = 0.1) {
  std::vector<glm::dvec2> out;
  for (int i = 0; i < n; ++i) {
    const double a = phase + 2 * M_PI * i / n;
    out.push_back(c + r * glm::dvec2(std::cos(a), std::sin(a)));
  }
  return out;
}

TEST(OccluderShadows, ASleeveWrappedLooselyRoundAnArm) {
  // A wrinkled sleeve round a 96-gon arm, open at one place, and a strip of cloth beside both.
  std::vector<glm::dvec2> sleeve;
  for (int i = 0; i < 60; ++i) {
    const double a = 0.3 + 5.9 * i / 59.0;
    const double r = 1.3 + 0.15 * std::sin(7 * a);
    sleeve.push_back(r * glm::dvec2(std::cos(a), std::sin(a)));
  }
  const Chains cloth{{sleeve, {{2.0, -1.0}, {2.5, 0.0}, {2.1, 1.0}, {2.6, 2.0}}}, {false, false}};
  const Chains arm{{polygon({0.0, 0.0}, 1.0, 96)}, {true}};
  g_shadowed = 0;
  EXPECT_EQ(compare(cloth, arm), "");
  EXPECT_GT(g_shadowed, 5u);  // the arm shows through the sleeve's opening and from the strip
}

TEST(OccluderShadows, ClothInAPocketOfAnOccluder) {
  // A U-shaped table section (a pocket under its top), cloth hanging into the pocket and over the top: some
  // cloth vertices inside the occluder's hull (the union of its segments' ranges), some outside (tangents).
  const std::vector<glm::dvec2> table = {{-2, 0},  {-2, 2},    {2, 2},      {2, 0},
                                         {1.8, 0}, {1.8, 1.8}, {-1.8, 1.8}, {-1.8, 0}};
  const std::vector<glm::dvec2> cloth_over = {{-2.5, 0.5}, {-2.1, 2.05}, {0, 2.1}, {1.0, 1.6}, {1.2, 0.4}};
  const Chains cloth{{cloth_over, {{-1.0, 0.3}, {0.0, 1.0}, {1.0, 0.2}}}, {false, false}};
  const Chains occluder{{table}, {true}};
  g_shadowed = 0;
  EXPECT_EQ(compare(cloth, occluder), "");
  EXPECT_GT(g_shadowed, 3u);
}

/// What the cloth's first slice vertex sees on either side, the occluders cast as shadows.
AngularSet seen_from_first_vertex(const Slice& cloth, const Slice& occluders) {
  SliceTriangulation triangulation;
  triangulation.build(cloth);
  SliceConeScratch scratch;
  SliceCones cones;
  compute_slice_cones(cloth, triangulation, scratch, cones);
  ShadowScratch shadow_scratch;
  OccluderChains chains;
  gather_occluder_chains(occluders, shadow_scratch, chains);
  cast_occluder_shadows(cloth, chains, {}, 0.0, shadow_scratch, cones);
  const auto front = cones.cone(0, Side::Front), back = cones.cone(0, Side::Back);
  return AngularSet::from_wedges({front.begin(), front.end()})
      .unite(AngularSet::from_wedges({back.begin(), back.end()}));
}

TEST(OccluderShadows, AClothPointOnAnOpenOccluderSeesBothWays) {
  // A cloth strip hanging from a point on the flat bottom of an open occluder chain (a U with its arms up):
  // the bottom through the point blocks nothing, the arms block a range each, and both gaps — between the
  // arms, and the lower half-plane — stay visible.
  const Slice cloth = test::make_slice({{{0, 0}, {0, -1}}}, {false});
  const Slice u = test::make_slice({{{-2, 1}, {-1, 0}, {1, 0}, {2, 1}}}, {false});
  const AngularSet seen = seen_from_first_vertex(cloth, u);
  const double arm = std::atan2(1.0, 2.0);  // the arms' far ends seen from the point
  const AngularSet expected = AngularSet::from_wedges({{arm, M_PI - 2 * arm}, {M_PI, M_PI}});
  EXPECT_LT(oracle::angular_difference(seen, expected), 1e-9);
}

TEST(OccluderShadows, DegenerateChainsBlockOnlyWhatTheyCover) {
  // An occluder on one point, one along a line (collinear points), one passing close by a cloth vertex, two
  // points in one place; cloth on the line's extension.
  const Chains cloth{{{{-1, 0}, {0, 0}, {0.5, 1}}, {{3, 3}, {4, 3}}}, {false, false}};
  const Chains occluders{
      {{{1, 1}}, {{1, 0}, {2, 0}, {3, 0}}, {{0.5 + 1e-9, 0.5}, {0.5 + 1e-9, 2}}, {{5, 5}, {5, 5}}},
      {false, false, false, false}};
  EXPECT_EQ(compare(cloth, occluders), "");
}

TEST(OccluderShadows, ClothTouchingAnOccluderSeesAlongItsSurface) {
  // A cloth strip standing on the top edge of a square occluder, its end vertex on that edge: the square
  // blocks the open lower half-plane (its other segments), the edge through the vertex blocks nothing.
  const Slice cloth = test::make_slice({{{0, 0}, {0, 1}}}, {false});
  const Slice square = test::make_slice({{{-1, -1}, {1, -1}, {1, 0}, {-1, 0}}}, {true});
  EXPECT_LT(oracle::angular_difference(seen_from_first_vertex(cloth, square),
                                       AngularSet::from_wedges({{0.0, M_PI}})),
            1e-9);
}

RC_GTEST_PROP(OccluderShadows, MatchTheAngularSweepOnRandomChains, ()) {
  std::mt19937_64 rng(*rc::gen::arbitrary<std::uint64_t>());
  for (int k = 0; k < 10; ++k) {
    const std::string mismatch = compare_split(test::random_chain_slice(rng), rng);
    RC_ASSERT(mismatch == "");
  }
}

TEST(OccluderShadows, ClothInsideASolidSeesFromItsSurface) {
  // Cloth sunk into a square and a 40-gon (sections of a box and an arm): every vertex inside is seen from
  // the nearest point of the surface, so the square's top blocks none of what lies above it.
  const Chains occluders{{{{-1, -1}, {1, -1}, {1, 0}, {-1, 0}}, polygon({4.0, 0.0}, 1.0, 40)}, {true, true}};
  const Chains cloth{{{{-0.8, -0.001}, {-0.2, 0.01}, {0.5, -0.002}}, {{3.2, 0.8}, {3.9, 0.98}, {4.6, 0.7}}},
                     {false, false}};
  g_in_contact = 0;
  EXPECT_EQ(compare(cloth, occluders), "");
  EXPECT_EQ(g_in_contact, 4u);
  // The first vertex, 1 mm into the square's top: above, the whole half-plane; below, nothing.
  const Slice slice = test::make_slice({cloth.points[0]}, {false});
  const Slice square = test::make_slice({occluders.points[0]}, {true});
  EXPECT_LT(oracle::angular_difference(seen_from_first_vertex(slice, square),
                                       AngularSet::from_wedges({{0.0, M_PI}})),
            0.02);
}

RC_GTEST_PROP(OccluderShadows, MatchTheAngularSweepOnSlicedSurfaces, ()) {
  const auto seed = *rc::gen::arbitrary<std::uint64_t>();
  std::mt19937_64 rng(seed);
  for (const Slice& slice : test::random_surface_slices(seed, 10)) {
    const std::string mismatch = compare_split(slice, rng);
    RC_ASSERT(mismatch == "");
  }
}

}  // namespace
}  // namespace pleat
