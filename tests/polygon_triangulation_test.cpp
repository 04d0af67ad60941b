// Polygons triangulated in their plane over their own corners (sim_io/polygon_triangulation.hpp): convex
// ones fanned as before, concave ones (a U, random star-shaped polygons in random planes) tiled exactly —
// n - 2 triangles, each turning the polygon's way, their areas summing to the polygon's — and polygons with
// no proper triangulation (a bow-tie, no area) fanned.
#include "sim_io/polygon_triangulation.hpp"

#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>
#include <vector>

#include "test_support.hpp"

namespace pleat {
namespace {

using Triangles = std::vector<std::array<std::size_t, 3>>;

Triangles fan(std::size_t n) {
  Triangles triangles;
  for (std::size_t k = 1; k + 1 < n; ++k) triangles.push_back({0, k, k + 1});
  return triangles;
}

glm::dvec3 area_vector(const std::vector<glm::dvec3>& polygon) {
  glm::dvec3 sum(0.0);
  for (std::size_t k = 0; k < polygon.size(); ++k)
    sum += glm::cross(polygon[k] - polygon[0], polygon[(k + 1) % polygon.size()] - polygon[0]);
  return 0.5 * sum;
}

// The triangles tile the planar polygon: n - 2 of them over distinct corners, each with a positive area
// along the polygon's normal, their areas summing to the polygon's (so none overlaps another).
void expect_tiles(const std::vector<glm::dvec3>& polygon, const Triangles& triangles) {
  ASSERT_EQ(triangles.size(), polygon.size() - 2);
  const glm::dvec3 area = area_vector(polygon);
  const glm::dvec3 normal = glm::normalize(area);
  double sum = 0.0;
  for (const auto& t : triangles) {
    ASSERT_LT(std::max({t[0], t[1], t[2]}), polygon.size());
    ASSERT_TRUE(t[0] != t[1] && t[1] != t[2] && t[0] != t[2]);
    const double a =
        0.5 * glm::dot(glm::cross(polygon[t[1]] - polygon[t[0]], polygon[t[2]] - polygon[t[0]]), normal);
    EXPECT_GT(a, 0.0);
    sum += a;
  }
  EXPECT_NEAR(sum, glm::length(area), 1e-9 * glm::length(area));
}

// A flat U of 8 corners in the plane y = 0, its notch between x = 1 and 2 up to z = 2 (reflex corners 5 and
// 6): the fan from corner 0 would cover the notch.
std::vector<glm::dvec3> u_shape() {
  return {{0, 0, 0}, {0, 0, 3}, {3, 0, 3}, {3, 0, 0}, {2, 0, 0}, {2, 0, 2}, {1, 0, 2}, {1, 0, 0}};
}

TEST(PolygonTriangulation, AConvexPolygonIsFannedFromItsFirstCorner) {
  const std::vector<glm::dvec3> hexagon = {{2, 0, 0},  {1, 1.7, 0},   {-1, 1.7, 0},
                                           {-2, 0, 0}, {-1, -1.7, 0}, {1, -1.7, 0}};
  EXPECT_EQ(triangulate_polygon(hexagon), fan(6));
  const std::vector<glm::dvec3> quad = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0.1}, {0, 1, 0}};  // warped a little
  EXPECT_EQ(triangulate_polygon(quad), fan(4));
}

TEST(PolygonTriangulation, AConcaveUIsTiledNotFanned) {
  const std::vector<glm::dvec3> u = u_shape();
  const Triangles triangles = triangulate_polygon(u);
  EXPECT_NE(triangles, fan(8));
  expect_tiles(u, triangles);
  // Wound the other way: the triangles follow.
  std::vector<glm::dvec3> reversed(u.rbegin(), u.rend());
  expect_tiles(reversed, triangulate_polygon(reversed));
  // A dart (a concave quad) whose reflex corner is the last: split along its inner diagonal 1-3, not 0-2.
  const std::vector<glm::dvec3> dart = {{0, 2, 0}, {0, 0, 0}, {2, 0, 0}, {0.5, 0.5, 0}};
  EXPECT_NE(triangulate_polygon(dart), fan(4));
  expect_tiles(dart, triangulate_polygon(dart));
}

TEST(PolygonTriangulation, PolygonsWithoutAProperTriangulationKeepTheFan) {
  const std::vector<glm::dvec3> bow_tie = {{0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0}, {0.5, 2, 0}};
  EXPECT_EQ(triangulate_polygon(bow_tie).size(), 3u);
  const std::vector<glm::dvec3> line = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
  EXPECT_EQ(triangulate_polygon(line), fan(4));
  const std::vector<glm::dvec3> repeated = {{0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  EXPECT_EQ(triangulate_polygon(repeated).size(), 3u);
  EXPECT_EQ(triangulate_polygon(std::vector<glm::dvec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}), fan(3));
}

RC_GTEST_PROP(PolygonTriangulation, RandomStarShapedPolygonsInRandomPlanesAreTiled, ()) {
  // A polygon star-shaped about its centre (corners at increasing angles, random radii: simple, often
  // concave), in the plane through a random point with a random normal.
  const int n = *rc::gen::inRange(4, 40);
  std::vector<int> radii = *rc::gen::container<std::vector<int>>(std::size_t(n), rc::gen::inRange(1, 100));
  const glm::dvec3 normal = test::gen_unit_direction();
  const glm::dvec3 other = std::abs(normal.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 u = glm::normalize(glm::cross(other, normal)), w = glm::cross(normal, u);
  const glm::dvec3 origin(*rc::gen::inRange(-50, 50), *rc::gen::inRange(-50, 50), *rc::gen::inRange(-50, 50));
  std::vector<glm::dvec3> polygon;
  for (int k = 0; k < n; ++k) {
    const double angle = 2 * std::numbers::pi * k / n;
    polygon.push_back(origin + radii[k] * 0.01 * (std::cos(angle) * u + std::sin(angle) * w));
  }
  const Triangles triangles = triangulate_polygon(polygon);
  RC_ASSERT(triangles.size() == std::size_t(n - 2));
  const glm::dvec3 area = area_vector(polygon);
  double sum = 0.0;
  for (const auto& t : triangles) {
    const double a = 0.5 * glm::dot(glm::cross(polygon[t[1]] - polygon[t[0]], polygon[t[2]] - polygon[t[0]]),
                                    glm::normalize(area));
    RC_ASSERT(a > 0.0);
    sum += a;
  }
  RC_ASSERT(std::abs(sum - glm::length(area)) <= 1e-9 * glm::length(area));
}

}  // namespace
}  // namespace pleat
