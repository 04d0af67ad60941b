// on_or_above, the slicer's side-of-plane predicate: its floating-point filter must give CGAL's exact answer
// on every input — random planes and points, points exactly on a plane and one ulp off it, tiny and huge
// magnitudes, subnormal products.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <limits>

#include "static_core/mesh_slicer.hpp"

namespace pleat {
namespace {

/// A double of one of several kinds: small integers (exact sums), dyadic fractions, arbitrary values of
/// various scales, subnormals, zero.
double gen_coordinate() {
  switch (*rc::gen::inRange(0, 6)) {
    case 0:
      return *rc::gen::inRange(-8, 9);
    case 1:
      return *rc::gen::inRange(-(1 << 20), 1 << 20) / double(1 << 12);
    case 2:
      return *rc::gen::inRange(-1000000, 1000001) * 1e-6 * std::pow(10.0, *rc::gen::inRange(-12, 13));
    case 3:
      return *rc::gen::inRange(-1000, 1001) * std::numeric_limits<double>::denorm_min();
    case 4:
      return *rc::gen::inRange(-1000, 1001) * 1e-150;
    default:
      return 0.0;
  }
}

RC_GTEST_PROP(PlaneSide, TheFilterAgreesWithTheExactPredicate, ()) {
  SlicingPlane plane;
  plane.normal = {gen_coordinate(), gen_coordinate(), gen_coordinate()};
  glm::dvec3 p(gen_coordinate(), gen_coordinate(), gen_coordinate());
  const bool cancelling = *rc::gen::inRange(0, 3) == 0;
  if (cancelling) {  // catastrophic cancellation: two huge terms and a small one
    const double big = std::ldexp(1.0, *rc::gen::inRange(53, 61));
    plane.normal = {1.0, *rc::gen::inRange(-3, 4) * 0.5, -1.0};
    p = {big, *rc::gen::inRange(-8, 9) * 0.25, big + *rc::gen::inRange(-3, 4) * std::ldexp(big, -52)};
  }
  switch (cancelling ? 4 : *rc::gen::inRange(0, 4)) {
    case 4:  // of the order of the small term: the rounded sum often has the wrong sign
      plane.offset = *rc::gen::inRange(-4, 5) * 0.125;
      break;
    case 0:  // any offset
      plane.offset = gen_coordinate();
      break;
    case 1:  // the rounded dot product: on the plane, or within rounding of it
      plane.offset = glm::dot(plane.normal, p);
      break;
    default: {  // one or a few ulps either side of it
      const double d = glm::dot(plane.normal, p);
      const int steps = *rc::gen::inRange(-3, 4);
      plane.offset = d;
      for (int i = 0; i < std::abs(steps); ++i)
        plane.offset = std::nextafter(plane.offset, steps > 0 ? INFINITY : -INFINITY);
    }
  }
  RC_ASSERT(on_or_above(plane, p) == on_or_above_exact(plane, p));
}

TEST(PlaneSide, PointsExactlyOnAPlaneAreOnOrAbove) {
  // Integer normals and points: the dot product is exact, so the point lies on the plane exactly; the
  // filter cannot decide (d = 0) and CGAL says on. One ulp of offset moves it off to either side.
  SlicingPlane plane;
  plane.normal = {1.0, -2.0, 3.0};
  const glm::dvec3 p(5.0, 7.0, -11.0);
  plane.offset = glm::dot(plane.normal, p);  // -42, exact
  EXPECT_TRUE(on_or_above(plane, p));
  plane.offset = std::nextafter(plane.offset, INFINITY);
  EXPECT_FALSE(on_or_above(plane, p));
  plane.offset = std::nextafter(plane.offset, -INFINITY);
  plane.offset = std::nextafter(plane.offset, -INFINITY);
  EXPECT_TRUE(on_or_above(plane, p));
}

TEST(PlaneSide, ARoundedDotProductThatLiesIsCorrected) {
  // n . p = 1e16 + 1 - 1e16 = 1 exactly, but the rounded sum is 0 (1e16 + 1 rounds to 1e16): a filter that
  // trusted the rounded value would put the point below the plane n . x = 0.5. It must defer to CGAL.
  SlicingPlane plane;
  plane.normal = {1.0, 1.0, -1.0};
  plane.offset = 0.5;
  const glm::dvec3 p(1e16, 1.0, 1e16);
  EXPECT_TRUE(on_or_above(plane, p));
  EXPECT_EQ(on_or_above(plane, p), on_or_above_exact(plane, p));
}

}  // namespace
}  // namespace pleat
