// Spherical polygons: Lambert's formula, vector irradiance, the cosine-weighted moment, the solid angle,
// hemisphere clipping, the point-in-polygon test and its bounding cap, against closed forms (octant,
// hemisphere) and against numeric integration over random star-shaped polygons (Gauss–Legendre in polar
// coordinates about the star centre, an integrator that shares nothing with the edge sums under test). Seeds
// are fixed.
#include "static_core/spherical_polygon.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <glm/geometric.hpp>
#include <random>
#include <vector>

namespace pleat {
namespace {

constexpr double kPi = 3.14159265358979323846;

// ---- numeric integration over a star-shaped spherical polygon --------------------------------------------

struct GaussLegendre {
  std::vector<double> x, w;  // on [-1, 1]
  explicit GaussLegendre(int n) {
    for (int i = 0; i < n; ++i) {
      double z = std::cos(kPi * (i + 0.75) / (n + 0.5));
      double dp = 0.0;
      for (int it = 0; it < 100; ++it) {
        double p0 = 1.0, p1 = z;
        for (int k = 2; k <= n; ++k) {
          const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
          p0 = p1;
          p1 = p2;
        }
        dp = n * (z * p1 - p0) / (z * z - 1.0);
        const double dz = p1 / dp;
        z -= dz;
        if (std::abs(dz) < 1e-16) break;
      }
      x.push_back(z);
      w.push_back(2.0 / ((1.0 - z * z) * dp * dp));
    }
  }
};

/// A polygon star-shaped about `centre`: vertex k at polar angle radius[k] and azimuth azimuth[k]
/// (strictly increasing) in the frame (t1, t2, centre).
struct StarPolygon {
  glm::dvec3 centre, t1, t2;
  std::vector<double> azimuth, radius;
  SphericalPolygon vertices;

  glm::dvec3 direction(double psi, double r) const {
    return std::cos(r) * centre + std::sin(r) * (std::cos(psi) * t1 + std::sin(psi) * t2);
  }
  /// Polar angle of the boundary at azimuth psi on edge i.
  double boundary(std::size_t i, double psi) const {
    const glm::dvec3 g = glm::cross(vertices[i], vertices[(i + 1) % vertices.size()]);
    const glm::dvec3 u = std::cos(psi) * t1 + std::sin(psi) * t2;
    double r = std::atan2(-glm::dot(g, centre), glm::dot(g, u));
    if (r <= 0.0) r += kPi;
    return r;
  }
  std::size_t edge_at(double psi) const {
    const std::size_t n = azimuth.size();
    for (std::size_t i = 0; i + 1 < n; ++i)
      if (psi >= azimuth[i] && psi < azimuth[i + 1]) return i;
    return n - 1;
  }
  bool contains(const glm::dvec3& w) const {
    const double r = std::acos(std::clamp(glm::dot(w, centre), -1.0, 1.0));
    double psi = std::atan2(glm::dot(w, t2), glm::dot(w, t1));
    while (psi < azimuth[0]) psi += 2 * kPi;
    while (psi >= azimuth[0] + 2 * kPi) psi -= 2 * kPi;
    return r < boundary(edge_at(psi), psi);
  }
  /// integral over the polygon of f, per component, by composite Gauss–Legendre in (azimuth, polar angle).
  template <class F>
  auto integrate(F f, int cells, const GaussLegendre& gl) const {
    using R = decltype(f(glm::dvec3()));
    R sum{};
    const std::size_t n = vertices.size();
    for (std::size_t i = 0; i < n; ++i) {
      const double a0 = azimuth[i];
      const double a1 = i + 1 < n ? azimuth[i + 1] : azimuth[0] + 2 * kPi;
      const double ha = (a1 - a0) / cells;
      for (int ca = 0; ca < cells; ++ca) {
        for (std::size_t qa = 0; qa < gl.x.size(); ++qa) {
          const double psi = a0 + ha * (ca + 0.5 * (gl.x[qa] + 1.0));
          const double rmax = boundary(i, psi);
          const double hr = rmax / cells;
          R inner{};
          for (int cr = 0; cr < cells; ++cr)
            for (std::size_t qr = 0; qr < gl.x.size(); ++qr) {
              const double r = hr * (cr + 0.5 * (gl.x[qr] + 1.0));
              inner += (0.5 * hr * gl.w[qr] * std::sin(r)) * f(direction(psi, r));
            }
          sum += (0.5 * ha * gl.w[qa]) * inner;
        }
      }
    }
    return sum;
  }
};

glm::dvec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  glm::dvec3 v(g(rng), g(rng), g(rng));
  return glm::normalize(v);
}

void frame_about(const glm::dvec3& c, glm::dvec3& t1, glm::dvec3& t2) {
  const glm::dvec3 h = std::abs(c.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  t1 = glm::normalize(glm::cross(h, c));
  t2 = glm::cross(c, t1);
}

StarPolygon make_star(const glm::dvec3& centre, const std::vector<double>& azimuth,
                      const std::vector<double>& radius) {
  StarPolygon s;
  s.centre = centre;
  frame_about(centre, s.t1, s.t2);
  s.azimuth = azimuth;
  s.radius = radius;
  for (std::size_t k = 0; k < azimuth.size(); ++k) s.vertices.push_back(s.direction(azimuth[k], radius[k]));
  return s;
}

/// Whether every edge of the star is a minor arc whose azimuth about the centre increases monotonically
/// and stays away from the antipode (so the polar integrator sees each meridian cross it once).
bool is_valid_star(const StarPolygon& s) {
  const std::size_t n = s.vertices.size();
  for (std::size_t i = 0; i < n; ++i) {
    const glm::dvec3 a = s.vertices[i], b = s.vertices[(i + 1) % n];
    if (glm::dot(a, b) < -0.95) return false;
    double prev = s.azimuth[i];
    const double end = i + 1 < n ? s.azimuth[i + 1] : s.azimuth[0] + 2 * kPi;
    if (end - prev > kPi - 0.2) return false;
    for (int k = 1; k <= 64; ++k) {
      const glm::dvec3 p = glm::normalize(a + (b - a) * (k / 64.0));
      if (glm::dot(p, s.centre) < -0.98) return false;
      double psi = std::atan2(glm::dot(p, s.t2), glm::dot(p, s.t1));
      while (psi < prev - kPi) psi += 2 * kPi;
      while (psi > prev + kPi) psi -= 2 * kPi;
      if (psi < prev - 1e-12) return false;
      prev = psi;
    }
    if (std::abs(prev - end) > 1e-9) return false;
  }
  return true;
}

StarPolygon random_star(std::mt19937& rng, double max_radius) {
  std::uniform_int_distribution<int> count(3, 9);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  while (true) {
    const int n = count(rng);
    std::vector<double> az(n), rad(n);
    for (int k = 0; k < n; ++k) az[k] = 2 * kPi * unit(rng);
    std::sort(az.begin(), az.end());
    for (int k = 0; k < n; ++k) rad[k] = 0.15 + (max_radius - 0.15) * unit(rng);
    StarPolygon s = make_star(random_unit(rng), az, rad);
    if (is_valid_star(s)) return s;
  }
}

SphericalPolygon octant() { return {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}; }

void expect_near_vec(const glm::dvec3& a, const glm::dvec3& b, double tol) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

// ---- closed forms ---------------------------------------------------------------------------------------

TEST(SphericalPolygon, OctantClosedForms) {
  const SphericalPolygon o = octant();
  EXPECT_NEAR(projected_solid_angle(o, {0, 0, 1}), kPi / 4, 1e-14);
  EXPECT_NEAR(projected_solid_angle(o, {1, 0, 0}), kPi / 4, 1e-14);
  EXPECT_NEAR(projected_solid_angle(o, glm::normalize(glm::dvec3(1, 1, 1))), 3 * kPi / 4 / std::sqrt(3.0),
              1e-14);
  EXPECT_NEAR(solid_angle(o), kPi / 2, 1e-14);
  expect_near_vec(vector_irradiance(o), glm::dvec3(kPi / 4), 1e-14);
  // integral over the octant of w w_z: (1/3, 1/3, pi/6)
  expect_near_vec(cosine_weighted_moment(o, {0, 0, 1}), {1.0 / 3, 1.0 / 3, kPi / 6}, 1e-14);
  EXPECT_TRUE(contains_direction(o, glm::normalize(glm::dvec3(1, 1, 1))));
  EXPECT_FALSE(contains_direction(o, glm::normalize(glm::dvec3(-1, 1, 1))));
  EXPECT_FALSE(contains_direction(o, glm::normalize(glm::dvec3(-1, -1, -1))));
}

TEST(SphericalPolygon, HemisphereClosedForms) {
  const glm::dvec3 n = glm::normalize(glm::dvec3(0.3, -0.2, 0.9));
  const SphericalPolygon h = hemisphere_polygon(n);
  EXPECT_NEAR(projected_solid_angle(h, n), kPi, 1e-13);
  EXPECT_NEAR(solid_angle(h), 2 * kPi, 1e-13);
  expect_near_vec(cosine_weighted_moment(h, n), (2 * kPi / 3) * n, 1e-13);
  EXPECT_TRUE(contains_direction(h, n));
  EXPECT_FALSE(contains_direction(h, -n));
  // The horizon polygon lies on the closed hemisphere: clipping keeps it.
  EXPECT_NEAR(projected_solid_angle(clip_to_hemisphere(h, n), n), kPi, 1e-13);
  // Clipped against the opposite hemisphere only the horizon is left: no area.
  EXPECT_NEAR(projected_solid_angle(clip_to_hemisphere(h, -n), -n), 0.0, 1e-13);
}

TEST(SphericalPolygon, OrientationConventions) {
  // Counter-clockwise seen from outside = interior on the left = positive measures.
  SphericalPolygon o = octant();
  SphericalPolygon r(o.rbegin(), o.rend());
  EXPECT_NEAR(projected_solid_angle(r, {0, 0, 1}), -kPi / 4, 1e-14);
  // Reversed, the polygon is the complement of the octant.
  EXPECT_NEAR(solid_angle(r), 4 * kPi - kPi / 2, 1e-13);
  EXPECT_FALSE(contains_direction(r, glm::normalize(glm::dvec3(1, 1, 1))));
  EXPECT_TRUE(contains_direction(r, glm::normalize(glm::dvec3(-1, 1, 1))));
  // The complement clipped to the upper hemisphere is the other three quarters: 3 pi / 4.
  EXPECT_NEAR(projected_solid_angle(clip_to_hemisphere(r, {0, 0, 1}), {0, 0, 1}), 3 * kPi / 4, 1e-13);
}

TEST(SphericalPolygon, VerticesOnTheHorizon) {
  // The octant touches the lower hemisphere of z only along its edge x-y.
  const SphericalPolygon o = octant();
  EXPECT_NEAR(projected_solid_angle(clip_to_hemisphere(o, {0, 0, 1}), {0, 0, 1}), kPi / 4, 1e-14);
  EXPECT_NEAR(projected_solid_angle(clip_to_hemisphere(o, {0, 0, -1}), {0, 0, -1}), 0.0, 1e-14);
  // Split by the plane x = y through its corner z: two halves of pi/8 each.
  const glm::dvec3 m = glm::normalize(glm::dvec3(1, -1, 0));
  EXPECT_NEAR(projected_solid_angle(clip_to_hemisphere(o, m), {0, 0, 1}), kPi / 8, 1e-14);
  EXPECT_NEAR(projected_solid_angle(clip_to_hemisphere(o, -m), {0, 0, 1}), kPi / 8, 1e-14);
}

// ---- numeric integration ----------------------------------------------------------------------------

TEST(SphericalPolygon, RandomPolygonsAgainstQuadrature) {
  std::mt19937 rng(20240611);
  const GaussLegendre gl(12);
  for (int trial = 0; trial < 60; ++trial) {
    const double max_radius = trial % 2 == 0 ? 1.4 : 2.5;  // also polygons larger than a hemisphere
    const StarPolygon s = random_star(rng, max_radius);
    const glm::dvec3 n = random_unit(rng);
    const double area = s.integrate([](const glm::dvec3&) { return 1.0; }, 16, gl);
    const glm::dvec3 first = s.integrate([](const glm::dvec3& w) { return w; }, 16, gl);
    const glm::dvec3 moment = s.integrate([&](const glm::dvec3& w) { return w * glm::dot(n, w); }, 16, gl);
    SCOPED_TRACE(trial);
    EXPECT_NEAR(solid_angle(s.vertices), area, 1e-7);
    expect_near_vec(vector_irradiance(s.vertices), first, 1e-7);
    EXPECT_NEAR(projected_solid_angle(s.vertices, n), glm::dot(n, first), 1e-7);
    expect_near_vec(cosine_weighted_moment(s.vertices, n), moment, 1e-7);
    for (int k = 0; k < 20; ++k) {
      const glm::dvec3 w = random_unit(rng);
      EXPECT_EQ(contains_direction(s.vertices, w), s.contains(w));
    }
  }
}

/// The bounding cap never rules out a direction the polygon holds (random stars, small, up to a hemisphere
/// and beyond; the same stars reversed, which enclose the rest of the sphere; directions on and next to
/// the boundary and near the cap's rim), and it rules out most directions beyond a small polygon.
TEST(SphericalPolygon, BoundingCapHoldsEveryDirectionThePolygonHolds) {
  std::mt19937 rng(20261128);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::size_t ruled_out = 0, beyond_small = 0, random_small = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const double max_radius = trial % 4 == 0 ? 2.5 : trial % 4 == 1 ? kPi / 2 : trial % 4 == 2 ? 1.2 : 0.4;
    const StarPolygon s = random_star(rng, max_radius);
    for (const bool reversed : {false, true}) {
      SphericalPolygon poly = s.vertices;
      if (reversed) std::reverse(poly.begin(), poly.end());
      const double area = solid_angle(poly);
      const BoundingCap cap = bounding_cap(poly, area);
      SCOPED_TRACE(::testing::Message() << "trial " << trial << (reversed ? " reversed" : ""));
      auto check = [&](const glm::dvec3& w, bool random = false) {
        const bool small = random && !reversed && max_radius < 1;
        random_small += small;
        const bool inside = contains_direction(poly, w, area);
        if (!may_contain(cap, w)) {
          ++ruled_out;
          beyond_small += small;
          ASSERT_FALSE(inside) << "the cap rules out a direction the polygon holds";
        }
      };
      for (int k = 0; k < 40; ++k) check(random_unit(rng), true);
      for (std::size_t i = 0; i < poly.size(); ++i) {  // the boundary: vertices, points on and beside edges
        const glm::dvec3 a = poly[i], b = poly[(i + 1) % poly.size()];
        check(a);
        const glm::dvec3 on = glm::normalize(a + unit(rng) * (b - a));
        check(on);
        const glm::dvec3 g = glm::normalize(glm::cross(a, b));
        for (double step : {1e-12, 1e-9, 1e-6}) {
          check(glm::normalize(on + step * g));
          check(glm::normalize(on - step * g));
        }
      }
      if (cap.min_cos > -1.0) {  // beside the cap's rim, inside and out
        glm::dvec3 t1, t2;
        frame_about(cap.centre, t1, t2);
        const double r = std::acos(cap.min_cos);
        for (double dr : {-1e-9, -1e-12, 0.0, 1e-12, 1e-9, 1e-6}) {
          const double psi = 2 * kPi * unit(rng);
          check(std::cos(r + dr) * cap.centre + std::sin(r + dr) * (std::cos(psi) * t1 + std::sin(psi) * t2));
        }
      }
      if (area > 2 * kPi) EXPECT_EQ(cap.min_cos, -1.0) << "a polygon about its large side has no cap";
    }
  }
  // Not vacuous: most random directions lie beyond a small polygon's cap.
  EXPECT_GT(beyond_small, random_small * 3 / 4);
  EXPECT_GT(ruled_out, beyond_small);
}

TEST(SphericalPolygon, BoundingCapOfDegeneratePolygons) {
  const glm::dvec3 z(0, 0, 1);
  // Fewer than three vertices, repeated vertices, a hemisphere (vertices on the horizon), an octant.
  EXPECT_EQ(bounding_cap({}, 0.0).min_cos, -1.0);
  EXPECT_EQ(bounding_cap({z, z}, 0.0).min_cos, -1.0);
  const SphericalPolygon h = hemisphere_polygon(z);
  EXPECT_EQ(bounding_cap(h, solid_angle(h)).min_cos, -1.0);
  const SphericalPolygon o = octant();
  const BoundingCap cap = bounding_cap(o, solid_angle(o));
  ASSERT_GT(cap.min_cos, 0.0);
  for (const glm::dvec3& v : o) EXPECT_TRUE(may_contain(cap, v));
  EXPECT_TRUE(may_contain(cap, glm::normalize(glm::dvec3(1, 1, 1))));
  EXPECT_FALSE(may_contain(cap, glm::normalize(glm::dvec3(-1, -1, -1))));
  // A sliver: three nearly collinear vertices.
  const SphericalPolygon sliver = {glm::normalize(glm::dvec3(1, 0, 1)),
                                   glm::normalize(glm::dvec3(0, 1e-14, 1)),
                                   glm::normalize(glm::dvec3(-1, 0, 1))};
  const BoundingCap thin = bounding_cap(sliver, solid_angle(sliver));
  for (const glm::dvec3& v : sliver) EXPECT_TRUE(may_contain(thin, v));
  EXPECT_FALSE(contains_direction(sliver, -z));
  EXPECT_FALSE(may_contain(thin, -z));
}

/// Checks clip_to_hemisphere and HemisphereClipper against quadrature of the clipped integrands.
void check_clip(const StarPolygon& s, const glm::dvec3& n, int expected_pieces = -1) {
  static const GaussLegendre gl(4);
  const double cells = 48;  // the integrand has a kink along the horizon: many small cells
  const double lambert =
      s.integrate([&](const glm::dvec3& w) { return std::max(0.0, glm::dot(n, w)); }, cells, gl);
  const glm::dvec3 moment =
      s.integrate([&](const glm::dvec3& w) { return w * std::max(0.0, glm::dot(n, w)); }, cells, gl);
  const double area =
      s.integrate([&](const glm::dvec3& w) { return glm::dot(n, w) >= 0.0 ? 1.0 : 0.0; }, cells, gl);

  const SphericalPolygon joined = clip_to_hemisphere(s.vertices, n);
  EXPECT_NEAR(projected_solid_angle(joined, n), lambert, 2e-4);
  expect_near_vec(cosine_weighted_moment(joined, n), moment, 2e-4);

  HemisphereClipper clipper;
  SphericalPolygonList pieces;
  const std::size_t count = clipper.clip(s.vertices, n, pieces);
  ASSERT_EQ(count, pieces.size);
  if (expected_pieces >= 0) {
    EXPECT_EQ(static_cast<int>(count), expected_pieces);
  }
  double sum = 0.0, sum_area = 0.0;
  for (std::size_t k = 0; k < count; ++k) {
    const SphericalPolygon& p = pieces[k];
    for (std::size_t i = 0; i < p.size(); ++i) {
      EXPECT_GE(glm::dot(n, p[i]), -1e-12);
      EXPECT_GT(glm::dot(p[i], p[(i + 1) % p.size()]), -0.999) << "an arc reaches pi";
    }
    sum += projected_solid_angle(p, n);
    sum_area += solid_angle(p);
  }
  EXPECT_NEAR(sum, lambert, 2e-4);
  EXPECT_NEAR(sum_area, area, 1.5e-2);  // the indicator's jump limits the quadrature here
}

TEST(SphericalPolygon, RandomClipsAgainstQuadrature) {
  std::mt19937 rng(777);
  for (int trial = 0; trial < 40; ++trial) {
    SCOPED_TRACE(trial);
    const StarPolygon s = random_star(rng, trial % 2 == 0 ? 1.2 : 2.4);
    // Random n biased towards crossing the polygon.
    const glm::dvec3 n = glm::normalize(random_unit(rng) + 0.3 * s.vertices[0]);
    check_clip(s, n);
  }
}

TEST(SphericalPolygon, ClipPolygonContainingNormalWithNotch) {
  // Star about n, boundary below the horizon except one vertex that reaches up to 30 degrees from n:
  // the hemisphere minus a notch.
  const glm::dvec3 n = glm::normalize(glm::dvec3(0.1, 0.2, 1.0));
  std::vector<double> az, rad;
  for (int k = 0; k < 8; ++k) {
    az.push_back(2 * kPi * k / 8);
    rad.push_back(k == 3 ? 0.5 : 2.2);
  }
  const StarPolygon s = make_star(n, az, rad);
  ASSERT_TRUE(is_valid_star(s));
  check_clip(s, n, 1);
  EXPECT_LT(projected_solid_angle(clip_to_hemisphere(s.vertices, n), n), kPi);
}

TEST(SphericalPolygon, ClipTwoFingers) {
  // Star about -n, below the horizon except two fingers poking up into the hemisphere: two components.
  const glm::dvec3 n = glm::normalize(glm::dvec3(-0.3, 0.5, 0.8));
  std::vector<double> az, rad;
  for (int k = 0; k < 10; ++k) {
    az.push_back(2 * kPi * k / 10);
    rad.push_back(k == 2 || k == 7 ? 2.3 : 1.0);
  }
  const StarPolygon s = make_star(-n, az, rad);
  ASSERT_TRUE(is_valid_star(s));
  check_clip(s, n, 2);
}

TEST(SphericalPolygon, ClipBoundaryBelowHorizon) {
  const glm::dvec3 n = glm::normalize(glm::dvec3(1.0, -1.0, 0.5));
  std::vector<double> az, rad_big, rad_small;
  for (int k = 0; k < 6; ++k) {
    az.push_back(2 * kPi * k / 6 + 0.1);
    rad_big.push_back(2.0 + 0.1 * k);
    rad_small.push_back(0.3 + 0.1 * k);
  }
  // Contains all of the hemisphere: the clip is the hemisphere.
  const StarPolygon big = make_star(n, az, rad_big);
  ASSERT_TRUE(is_valid_star(big));
  EXPECT_NEAR(projected_solid_angle(clip_to_hemisphere(big.vertices, n), n), kPi, 1e-13);
  // Entirely in the other hemisphere: nothing.
  const StarPolygon small = make_star(-n, az, rad_small);
  EXPECT_TRUE(clip_to_hemisphere(small.vertices, n).empty());
}

TEST(SphericalPolygon, ClipVertexJustBelowOrAboveTheHorizon) {
  // Regression (a cone of the 'drape' sequence): a near-hemisphere piece with one vertex 1e-20 below the
  // horizon. Its exit and entry crossings round to the same point in the wrong order; taken naively the
  // horizon arc between them went the full turn and doubled A.
  const glm::dvec3 n(1.5565402379239612e-05, 0.99999999986710997, -4.8475113438766443e-06);
  const SphericalPolygon piece = {{0, 0.031844367089983082, 0.99949283953645129},
                                  {0.29734291146679481, 0, 0.95477075416062585},
                                  {0.99976488384278173, 0.021683566008145336, 0},
                                  {0.99975657383635863, 0.015601170965442949, -0.015601170965442949},
                                  {0.70701251913179874, 0.016327754953319285, -0.70701251913179897},
                                  {0.70703830931603395, 0.013916117240398247, -0.70703830931603417},
                                  {0.49085002261344934, 0, -0.87124408480079607},
                                  {0, 0.010288411339643018, -0.99994707289541396},
                                  {-0.005494162079855887, 0.0054941620798558887, -0.99996981372743476},
                                  {-0.99996423648657029, 0.0059802068455218436, -0.0059802068455218436},
                                  {-0.9999824026120866, 0.0059324924069702363, 0},
                                  {-0.7070991497368454, 0.0046459533855062246, 0.70709914973684562},
                                  {-0.70707267842148158, 0.0098211435049045774, 0.7070726784214818},
                                  {-0.03700559691884605, 0.037005596918846063, 0.99862964686281963}};
  const double unclipped = projected_solid_angle(piece, n);
  EXPECT_NEAR(projected_solid_angle(clip_to_hemisphere(piece, n), n), unclipped, 1e-12);

  // Synthetic: the hemisphere about z with one vertex dipping 1e-20 below, or a polygon below the horizon
  // with one vertex 1e-20 above (a bump of no area), in many rotations.
  std::mt19937 rng(8);
  for (int trial = 0; trial < 200; ++trial) {
    const double phase = 2 * kPi * trial / 200.0;
    SphericalPolygon dip, bump;
    for (int k = 0; k < 8; ++k) {
      const double a = phase + 2 * kPi * k / 8;
      const double z = k == 3 ? -1e-20 * (1 + trial) : 0.0;
      dip.push_back(glm::normalize(glm::dvec3(std::cos(a), std::sin(a), z)));
      bump.push_back(
          glm::normalize(glm::dvec3(std::cos(a), std::sin(a), k == 3 ? 1e-20 * (1 + trial) : -0.3)));
    }
    const glm::dvec3 z(0, 0, 1);
    EXPECT_NEAR(projected_solid_angle(clip_to_hemisphere(dip, z), z), kPi, 1e-12) << trial;
    std::reverse(bump.begin(), bump.end());  // counter-clockwise about its interior, below the horizon
    EXPECT_NEAR(projected_solid_angle(clip_to_hemisphere(bump, z), z), 0.0, 1e-12) << trial;
  }
}

TEST(SphericalPolygon, ClipperReusesStorage) {
  std::mt19937 rng(5);
  HemisphereClipper clipper;
  SphericalPolygonList pieces;
  for (int trial = 0; trial < 50; ++trial) {
    const StarPolygon s = random_star(rng, 2.0);
    const glm::dvec3 n = random_unit(rng);
    pieces.clear();
    clipper.clip(s.vertices, n, pieces);
    double sum = 0.0;
    for (std::size_t k = 0; k < pieces.size; ++k) sum += projected_solid_angle(pieces[k], n);
    EXPECT_NEAR(sum, projected_solid_angle(clip_to_hemisphere(s.vertices, n), n), 1e-12);
  }
}

}  // namespace
}  // namespace pleat
