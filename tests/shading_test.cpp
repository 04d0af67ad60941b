// Shading from visibility cones: every light type against closed forms or brute-force sampling of the same
// cone, the Stewart–Langer limits, the flat sheet, tone mapping, and the light spec / JSON parsers.
// Seeds are fixed; no timing assertions.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>
#include <random>
#include <vector>

#include "shading/cone_lighting.hpp"
#include "shading/environment_map.hpp"
#include "shading/lights.hpp"
#include "shading/shade.hpp"
#include "sim_io/cloth_generators.hpp"
#include "static_core/spherical_polygon.hpp"
#include "static_core/visibility.hpp"
#include "support/input_error.hpp"
#include "test_support.hpp"

namespace pleat {
namespace {

constexpr double kPi = 3.14159265358979323846;

void frame_about(const glm::dvec3& c, glm::dvec3& t1, glm::dvec3& t2) {
  const glm::dvec3 h = std::abs(c.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  t1 = glm::normalize(glm::cross(h, c));
  t2 = glm::cross(c, t1);
}

/// k vertices around `centre`, counter-clockwise, at polar angles alternating r_even / r_odd (a star when
/// they differ, a regular convex cap polygon when equal).
SphericalPolygon star(const glm::dvec3& centre, int k, double r_even, double r_odd, double phase = 0.0) {
  glm::dvec3 t1, t2;
  frame_about(centre, t1, t2);
  SphericalPolygon p;
  for (int i = 0; i < k; ++i) {
    const double psi = phase + 2 * kPi * i / k;
    const double r = i % 2 == 0 ? r_even : r_odd;
    p.push_back(std::cos(r) * centre + std::sin(r) * (std::cos(psi) * t1 + std::sin(psi) * t2));
  }
  return p;
}

VisibilityCone cone_of(std::vector<SphericalPolygon> pieces) { return VisibilityCone{std::move(pieces)}; }

glm::dvec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  return glm::normalize(glm::dvec3(g(rng), g(rng), g(rng)));
}

/// Brute force: stratified uniform samples of the hemisphere about m (area-preserving (cos, azimuth)
/// grid with jitter), summing f(w) (m.w) over samples inside any of the pieces.
template <class F>
glm::dvec3 brute_force(const std::vector<SphericalPolygon>& pieces, const glm::dvec3& m, F radiance, int grid,
                       unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(0.0, 1.0);
  glm::dvec3 t1, t2;
  frame_about(m, t1, t2);
  glm::dvec3 sum(0.0);
  const double weight = 2 * kPi / (double(grid) * grid);
  for (int i = 0; i < grid; ++i)
    for (int j = 0; j < grid; ++j) {
      const double z = (i + jitter(rng)) / grid;
      const double psi = 2 * kPi * (j + jitter(rng)) / grid;
      const double s = std::sqrt(std::max(0.0, 1 - z * z));
      const glm::dvec3 w = z * m + s * (std::cos(psi) * t1 + std::sin(psi) * t2);
      bool inside = false;
      for (const auto& p : pieces) inside = inside || contains_direction(p, w);
      if (inside) sum += weight * z * radiance(w);
    }
  return sum;
}

EnvironmentMap procedural_map(int width, int height, const EnvironmentOrientation& orientation = {}) {
  std::vector<glm::vec3> texels(static_cast<std::size_t>(width) * height);
  for (int r = 0; r < height; ++r)
    for (int c = 0; c < width; ++c) {
      const double u = (c + 0.5) / width, v = (r + 0.5) / height;
      glm::vec3 t(float(1.0 + 0.8 * std::sin(6 * kPi * u) * std::cos(3 * kPi * v)), float(0.5 + 0.5 * v * v),
                  float(0.3 + 0.6 * u));
      if (std::abs(u - 0.3) < 0.03 && std::abs(v - 0.35) < 0.04)
        t += glm::vec3(40.0f, 35.0f, 30.0f);    // a "sun"
      if ((c / 4 + r / 4) % 2 == 0) t *= 0.6f;  // texel-scale checker: sharp detail
      texels[static_cast<std::size_t>(r) * width + c] = t;
    }
  return EnvironmentMap(width, height, std::move(texels), orientation);
}

// ---- Lambert and the skies --------------------------------------------------------------------------

TEST(ConeLighting, UniformSkyOnHemisphereAndOctant) {
  Lighting lighting;
  lighting.lights.push_back(UniformSkyLight{glm::dvec3(2.0)});
  ConeLighting cl(lighting);
  const glm::dvec3 n(0, 0, 1);
  ConeIrradiance e = cl.evaluate(cone_of({hemisphere_polygon(n)}), glm::dvec3(0.0), n);
  EXPECT_NEAR(e.sky_visibility, 1.0, 1e-14);
  EXPECT_NEAR(e.irradiance.x, 2 * kPi, 1e-12);
  e = cl.evaluate(cone_of({{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}), glm::dvec3(0.0), n);
  EXPECT_NEAR(e.sky_visibility, 0.25, 1e-14);
  EXPECT_NEAR(e.irradiance.y, 2 * kPi / 4, 1e-12);
  // A cone piece reaching below the tangent plane counts only its upper part.
  e = cl.evaluate(cone_of({hemisphere_polygon(glm::normalize(glm::dvec3(1, 0, 1)))}), glm::dvec3(0.0), n);
  const double expected = (kPi / 2) * (1 + std::sin(kPi / 4)) / kPi;  // cap of a tilted hemisphere
  EXPECT_NEAR(e.sky_visibility, expected, 1e-12);
}

TEST(ConeLighting, CloudySkyOnAVerticalWall) {
  Lighting lighting;
  lighting.lights.push_back(HemisphereSkyLight{glm::dvec3(1.0), glm::dvec3(0, 0, 1)});
  ConeLighting cl(lighting);
  const glm::dvec3 n(1, 0, 0);
  // Half the hemisphere of a wall is above the horizon: pi/2 of projected solid angle.
  ConeIrradiance e = cl.evaluate(cone_of({hemisphere_polygon(n)}), glm::dvec3(0.0), n);
  EXPECT_NEAR(e.irradiance.x, kPi / 2, 1e-12);
  EXPECT_NEAR(e.sky_visibility, 1.0, 1e-14);
  // Facing down: nothing.
  e = cl.evaluate(cone_of({hemisphere_polygon({0, 0, -1})}), glm::dvec3(0.0), {0, 0, -1});
  EXPECT_NEAR(e.irradiance.x, 0.0, 1e-12);
}

TEST(ShadeFrame, StewartLangerLimits) {
  const double rho = 0.6, L = 1.5;
  auto radiance = [&](double a) { return stewart_langer_radiance(rho, glm::dvec3(kPi * L * a), a).x; };
  EXPECT_NEAR(radiance(1.0), rho * L, 1e-14);
  EXPECT_NEAR(radiance(0.0), 0.0, 1e-14);
  double prev = -1.0;
  for (int i = 0; i <= 100; ++i) {
    const double b = radiance(i / 100.0);
    EXPECT_GT(b, prev);
    EXPECT_NEAR(b, rho * L * (i / 100.0) / (1 - rho * (1 - i / 100.0)), 1e-14);
    prev = b;
  }
  // Inter-reflection only adds light: B >= rho E / pi.
  EXPECT_GT(stewart_langer_radiance(rho, glm::dvec3(1.0), 0.3).x, rho / kPi);
}

// ---- flat sheet --------------------------------------------------------------------------------------

struct FlatSheet {
  MeshTopology topology;
  Frame frame;
  FrameVisibility visibility;
  FlatSheet() {
    topology.num_vertices = 4;
    topology.triangles = {{0, 1, 2}, {0, 2, 3}};
    frame.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    visibility.normals.assign(4, glm::dvec3(0, 0, 1));
    for (int s = 0; s < 2; ++s) {
      const glm::dvec3 axis = s == 0 ? glm::dvec3(0, 0, 1) : glm::dvec3(0, 0, -1);
      visibility.cones[s].assign(4, cone_of({hemisphere_polygon(axis)}));
      visibility.measures[s].assign(4, ConeMeasures{1.0, axis, 2 * kPi});
    }
  }
};

TEST(ShadeFrame, FlatSheetUnderUniformSkyIsRhoL) {
  FlatSheet sheet;
  Lighting lighting;
  add_light_spec(lighting, "sky:1.25");
  ShadeParams params;
  params.albedo = 0.6;
  for (bool parallel : {false, true}) {
    params.parallel = parallel;
    const ShadedFrame shaded = shade_frame(sheet.topology, sheet.frame, sheet.visibility, lighting, params);
    for (int s = 0; s < 2; ++s)
      for (Index v = 0; v < 4; ++v) {
        EXPECT_NEAR(shaded.sky_visibility[s][v], 1.0, 1e-6);
        EXPECT_NEAR(shaded.radiance[s][v].x, 0.6 * 1.25, 1e-6);
        EXPECT_NEAR(shaded.radiance[s][v].z, 0.6 * 1.25, 1e-6);
      }
  }
  // Under a cloudy sky about +z only the front is lit, at rho L.
  Lighting cloudy;
  add_light_spec(cloudy, "cloudy:1.0,up=0,0,1");
  const ShadedFrame shaded = shade_frame(sheet.topology, sheet.frame, sheet.visibility, cloudy, params);
  EXPECT_NEAR(shaded.radiance[0][2].y, 0.6, 1e-6);
  EXPECT_NEAR(shaded.radiance[1][2].y, 0.0, 1e-6);
}

TEST(ShadeFrame, FastPathsEqualClippingEveryPiece) {
  // shade_frame's shortcuts (pieces used in place, A from the measures, the cloudy sky's whole-piece
  // cases) against the general path: every piece clipped (set_cone) and each light evaluated on the clip.
  GeneratorParams gen;
  gen.resolution = 14;
  gen.frames = 4;
  for (ClothKind kind : {ClothKind::Curtain, ClothKind::Roll}) {
    const ClothGenerator generator(kind, gen);
    const Frame frame = generator.frame(2);
    const FrameVisibility vis =
        compute_visibility(generator.topology(), frame, make_diffuse_plan(generator.topology(), frame, {}));
    for (const char* spec :
         {"sky:1.5", "cloudy:1,up=0,1,0", "cloudy:1,up=0,0,1", "dir:0.3,-0.5,-1,E=3",
          "point:0.3,-0.8,1.2,I=3", "area:-0.5,-1.5,2;0.5,-1.5,2;0.5,-0.5,2;-0.5,-0.5,2,L=4"}) {
      Lighting lighting;
      add_light_spec(lighting, spec);
      ShadeParams params;
      params.parallel = false;
      const ShadedFrame fast = shade_frame(generator.topology(), frame, vis, lighting, params);
      ConeLighting reference(lighting);
      for (int s = 0; s < 2; ++s)
        for (Index v = 0; v < generator.topology().num_vertices; ++v) {
          const glm::dvec3 axis = (s == 0 ? 1.0 : -1.0) * vis.normals[v];
          const double a = reference.set_cone(vis.cones[s][v], axis);
          glm::dvec3 e(0.0);
          lighting.for_each([&](const auto& l) { e += reference.irradiance(l, frame.positions[v]); });
          SCOPED_TRACE(std::string(spec) + " side " + std::to_string(s) + " vertex " + std::to_string(v));
          EXPECT_NEAR(fast.sky_visibility[s][v], a, 1e-6);
          EXPECT_NEAR(fast.irradiance[s][v].x, e.x, 1e-5 * (1.0 + std::abs(e.x)));
        }
    }
  }
}

TEST(ShadeFrame, RejectsMismatchedInput) {
  FlatSheet sheet;
  sheet.visibility.cones[1].pop_back();
  Lighting lighting;
  add_light_spec(lighting, "sky");
  EXPECT_THROW(shade_frame(sheet.topology, sheet.frame, sheet.visibility, lighting), std::invalid_argument);
}

// ---- point, directional and area lights -------------------------------------------------------------

TEST(ConeLighting, PointAndDirectionalInsideOutsideKnownCone) {
  // A convex cone of half-angle 30 degrees about +z, and a non-convex star about +z.
  const glm::dvec3 n(0, 0, 1);
  for (const SphericalPolygon& piece : {star(n, 8, 0.52, 0.52), star(n, 10, 0.8, 0.25)}) {
    Lighting lighting;
    add_light_spec(lighting, "point:0,0,2,I=8");
    add_light_spec(lighting, "point:2,0,1,I=8");  // 63 degrees off the axis: outside
    ConeLighting cl(lighting);
    cl.set_cone(cone_of({piece}), n);
    EXPECT_NEAR(cl.irradiance((*lighting.all<PointLight>()[0]), glm::dvec3(0.0)).x, 8.0 / 4.0, 1e-12);
    EXPECT_EQ(cl.irradiance((*lighting.all<PointLight>()[1]), glm::dvec3(0.0)).x, 0.0);
    // Inside but tilted: cosine and inverse-square falloff.
    const PointLight tilted{glm::dvec3(0.2, 0.0, 3.0), glm::dvec3(5.0)};
    const double d2 = 0.04 + 9.0;
    EXPECT_NEAR(cl.irradiance(tilted, glm::dvec3(0.0)).x, 5.0 * (3.0 / std::sqrt(d2)) / d2, 1e-12);

    DirectionalLight sun{glm::normalize(glm::dvec3(-0.1, 0.0, -1.0)), glm::dvec3(3.0)};
    EXPECT_NEAR(cl.irradiance(sun).x, 3.0 / std::sqrt(1.01), 1e-12);
    sun.direction = glm::normalize(glm::dvec3(-1.0, 0.0, -1.0));  // 45 degrees: outside both cones
    EXPECT_EQ(cl.irradiance(sun).x, 0.0);
    sun.direction = glm::dvec3(0, 0, 1);  // from below
    EXPECT_EQ(cl.irradiance(sun).x, 0.0);
  }
  // In a notch of the star (between two long arms, at polar angle 0.5): outside.
  const Lighting none;
  ConeLighting cl(none);
  cl.set_cone(cone_of({star(n, 10, 0.8, 0.25)}), n);
  glm::dvec3 t1, t2;
  frame_about(n, t1, t2);
  const double psi = 2 * kPi * 1 / 10;  // direction of a short arm
  const glm::dvec3 notch = std::cos(0.5) * n + std::sin(0.5) * (std::cos(psi) * t1 + std::sin(psi) * t2);
  EXPECT_EQ(cl.irradiance(DirectionalLight{-notch, glm::dvec3(1.0)}).x, 0.0);
  const double psi_long = 0.0;
  const glm::dvec3 arm =
      std::cos(0.5) * n + std::sin(0.5) * (std::cos(psi_long) * t1 + std::sin(psi_long) * t2);
  EXPECT_NEAR(cl.irradiance(DirectionalLight{-arm, glm::dvec3(1.0)}).x, std::cos(0.5), 1e-12);
}

TEST(ConeLighting, InsideConeTestAgreesWithWindingFan) {
  // The fast projected-winding test used for point and directional lights against the exact fan test.
  std::mt19937 rng(42);
  const Lighting none;
  ConeLighting cl(none);
  int inside = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const glm::dvec3 m = random_unit(rng);
    const SphericalPolygon piece =
        star(glm::normalize(m + 0.8 * random_unit(rng)), 6 + trial % 7, 1.4, 0.6, trial);
    cl.set_cone(cone_of({piece}), m);
    for (int k = 0; k < 20; ++k) {
      glm::dvec3 l = random_unit(rng);
      if (glm::dot(l, m) <= 0.0) l = -l;
      const bool expected = contains_direction(piece, l);
      inside += expected;
      EXPECT_EQ(cl.irradiance(DirectionalLight{-l, glm::dvec3(1.0)}).x > 0.0, expected) << trial << " " << k;
    }
  }
  EXPECT_GT(inside, 200);  // both outcomes exercised
}

TEST(ConeLighting, AreaLightCoveringTheConeEqualsTheSky) {
  // The cone (half-angle ~40 degrees about +z) lies inside a large square light at height 1: the area
  // light of radiance L gives the same irradiance as a sky of radiance L.
  const glm::dvec3 n(0, 0, 1);
  const VisibilityCone cone = cone_of({star(n, 9, 0.7, 0.5)});
  Lighting lighting;
  add_light_spec(lighting, "area:-10,-10,1;10,-10,1;10,10,1;-10,10,1,L=2");
  add_light_spec(lighting, "sky:2");
  ConeLighting cl(lighting);
  const double a = cl.set_cone(cone, n);
  const glm::dvec3 area = cl.irradiance((*lighting.all<AreaLight>()[0]), glm::dvec3(0.0));
  EXPECT_NEAR(area.x, cl.irradiance((*lighting.all<UniformSkyLight>()[0])).x, 1e-12);
  EXPECT_NEAR(area.x, 2 * kPi * a, 1e-12);
  // Clockwise vertex order (light facing down) gives the same for a two-sided light, nothing one-sided.
  Lighting reversed;
  add_light_spec(reversed, "area:-10,10,1;10,10,1;10,-10,1;-10,-10,1,L=2");
  add_light_spec(reversed, "area:-10,-10,1;10,-10,1;10,10,1;-10,10,1,L=2,sided=1");
  add_light_spec(reversed, "area:-10,10,1;10,10,1;10,-10,1;-10,-10,1,L=2,sided=1");
  EXPECT_NEAR(cl.irradiance((*reversed.all<AreaLight>()[0]), glm::dvec3(0.0)).x, area.x, 1e-12);
  EXPECT_EQ(cl.irradiance((*reversed.all<AreaLight>()[1]), glm::dvec3(0.0)).x,
            0.0);  // normal +z: emits away from the vertex
  EXPECT_NEAR(cl.irradiance((*reversed.all<AreaLight>()[2]), glm::dvec3(0.0)).x, area.x, 1e-12);
}

TEST(ConeLighting, AreaLightCoveringTheHemisphereConeEqualsTheSky) {
  // A flat-sheet cone (the hemisphere) under a huge light: its solid angle tends to the hemisphere, and the
  // result equals Lambert's formula for the light rectangle, which tends to pi L.
  const glm::dvec3 n(0, 0, 1);
  Lighting lighting;
  add_light_spec(lighting, "area:-1000,-1000,1;1000,-1000,1;1000,1000,1;-1000,1000,1,L=1");
  ConeLighting cl(lighting);
  cl.set_cone(cone_of({hemisphere_polygon(n)}), n);
  EXPECT_NEAR(cl.irradiance((*lighting.all<AreaLight>()[0]), glm::dvec3(0.0)).x, kPi, 2e-3);
}

TEST(ConeLighting, AreaLightPartialOverlapAgainstBruteForce) {
  std::mt19937 rng(99);
  const glm::dvec3 n = glm::normalize(glm::dvec3(0.2, -0.1, 1.0));
  Lighting lighting;
  add_light_spec(lighting, "area:0.3,-0.5,1.255;1.5,-0.2,1.36;1.2,0.9,1.275;0.2,0.6,1.19,L=1");
  ConeLighting cl(lighting);
  for (int trial = 0; trial < 3; ++trial) {
    const VisibilityCone cone =
        cone_of({star(glm::normalize(n + 0.4 * random_unit(rng)), 10, 1.0, 0.45, trial)});
    cl.set_cone(cone, n);
    const glm::dvec3 e = cl.irradiance((*lighting.all<AreaLight>()[0]), glm::dvec3(0.0));
    // Brute force: in the cone and in the light polygon (ray-plane hit inside the quad).
    const AreaLight& light = (*lighting.all<AreaLight>()[0]);
    SphericalPolygon seen;
    for (auto it = light.polygon.rbegin(); it != light.polygon.rend(); ++it)
      seen.push_back(glm::normalize(*it));
    if (solid_angle(seen) > 2 * kPi) std::reverse(seen.begin(), seen.end());
    const glm::dvec3 ref = brute_force(
        cone.pieces, n,
        [&](const glm::dvec3& w) { return contains_direction(seen, w) ? glm::dvec3(1.0) : glm::dvec3(0.0); },
        600, 7 + trial);
    SCOPED_TRACE(trial);
    EXPECT_GT(e.x, 0.0);
    EXPECT_NEAR(e.x, ref.x, 2e-3 * kPi);
  }
}

// ---- environment maps ---------------------------------------------------------------------------------

TEST(EnvironmentMap, ConstantMapEqualsUniformSky) {
  const int w = 64, h = 32;
  EnvironmentMap map(w, h, std::vector<glm::vec3>(w * h, glm::vec3(0.7f, 0.5f, 0.25f)));
  std::mt19937 rng(3);
  Lighting lighting;
  lighting.lights.push_back(EnvironmentLight{map, 2.0, {}});
  lighting.lights.push_back(UniformSkyLight{glm::dvec3(1.4, 1.0, 0.5)});
  ConeLighting cl(lighting);
  for (int trial = 0; trial < 20; ++trial) {
    const glm::dvec3 m = random_unit(rng);
    VisibilityCone cone =
        trial == 0 ? cone_of({hemisphere_polygon(m)})
                   : cone_of({star(glm::normalize(m + 0.7 * random_unit(rng)), 12, 1.3, 0.5, trial)});
    cl.set_cone(cone, m);
    const glm::dvec3 env = cl.irradiance((*lighting.all<EnvironmentLight>()[0]));
    const glm::dvec3 sky = cl.irradiance((*lighting.all<UniformSkyLight>()[0]));
    SCOPED_TRACE(trial);
    EXPECT_NEAR(env.x, sky.x, 1e-5 * (1 + sky.x));
    EXPECT_NEAR(env.y, sky.y, 1e-5 * (1 + sky.y));
    EXPECT_NEAR(env.z, sky.z, 1e-5 * (1 + sky.z));
  }
  // Whole-sphere moment of a constant map is zero; the polygon around the bottom pole uses it.
  EXPECT_NEAR(glm::length(map.sphere_moment(0)), 0.0, 1e-5);
  const glm::dvec3 down(0, 0, -1);
  EXPECT_NEAR(map.integrate_cosine(hemisphere_polygon(down), down).x, 0.7 * kPi, 1e-5);
}

TEST(EnvironmentMap, TexturedMapAgainstBruteForceBelowOnePercent) {
  // Green's-theorem integration against dense stratified sampling of the same (piecewise-constant) map
  // over the same cone. Cones: convex and star-shaped, small and large, one around the bottom pole, and
  // maps in two orientations.
  std::mt19937 rng(1234);
  EnvironmentOrientation tilted;
  tilted.up = glm::normalize(glm::dvec3(0.3, 1.0, 0.2));
  tilted.rotation_degrees = 40.0;
  const EnvironmentMap maps[2] = {procedural_map(256, 128), procedural_map(200, 100, tilted)};
  for (int trial = 0; trial < 10; ++trial) {
    const EnvironmentMap& map = maps[trial % 2];
    // Trial 0: the hemisphere around the bottom pole; trials 8, 9: vertical normals (n.U = 0, the poles on
    // the horizon and on the polygon's boundary), as for a hanging cloth under an upright map.
    glm::dvec3 m = trial == 0 ? glm::dvec3(0, 0, -1) : random_unit(rng);
    if (trial == 8) m = glm::dvec3(1, 0, 0);
    if (trial == 9) m = glm::normalize(glm::cross(tilted.up, glm::dvec3(0.3, -0.5, 0.8)));
    std::vector<SphericalPolygon> pieces;
    if (trial == 0 || trial >= 8) {
      pieces = {hemisphere_polygon(m)};
    } else {
      const glm::dvec3 c = glm::normalize(m + 0.5 * random_unit(rng));
      const SphericalPolygon raw = star(c, 6 + 2 * (trial % 4), 1.2, trial % 2 ? 0.5 : 1.2, 0.3 * trial);
      pieces = {clip_to_hemisphere(raw, m)};
    }
    glm::dvec3 fast(0.0);
    for (const auto& p : pieces) fast += map.integrate_cosine(p, m);
    const glm::dvec3 slow = brute_force(
        pieces, m, [&](const glm::dvec3& w) { return map.radiance(w); }, 700, trial);
    SCOPED_TRACE(trial);
    for (int k = 0; k < 3; ++k) {
      ASSERT_GT(slow[k], 0.0);
      const double error = std::abs(fast[k] - slow[k]) / slow[k];
      if (k == 0) std::printf("env trial %d: relative error %.2e\n", trial, error);
      EXPECT_LT(error, 0.01) << "channel " << k << ": " << fast[k] << " vs " << slow[k];
    }
  }
}

TEST(EnvironmentMap, LookupConventionMatchesBlenderForZUp) {
  // u = 0.5 + atan2(w.y, -w.x) / 2 pi, v = acos(w.z) / pi.
  const int w = 8, h = 4;
  std::vector<glm::vec3> texels(w * h);
  for (int i = 0; i < w * h; ++i) texels[i] = glm::vec3(float(i));
  EnvironmentMap map(w, h, texels);
  int c = 0, r = 0;
  map.texel_of(glm::normalize(glm::dvec3(-1.0, 0.01, 0.1)), c, r);  // -x: u just above 0.5
  EXPECT_EQ(c, 4);
  EXPECT_EQ(r, 1);
  map.texel_of(glm::normalize(glm::dvec3(-0.01, 1.0, -0.5)), c, r);  // +y: u just below 0.75
  EXPECT_EQ(c, 5);
  EXPECT_EQ(r, 2);
}

// ---- tone mapping -----------------------------------------------------------------------------------

TEST(ToneMapping, ClampAndReinhard) {
  ToneMapParams clamp;
  clamp.op = ToneMap::Clamp;
  EXPECT_NEAR(tone_map(glm::vec3(0.5f), clamp).x, 0.735357f, 1e-5);
  EXPECT_EQ(tone_map(glm::vec3(3.0f), clamp).x, 1.0f);
  EXPECT_EQ(tone_map(glm::vec3(0.0f), clamp).x, 0.0f);
  ToneMapParams reinhard;
  EXPECT_NEAR(tone_map(glm::vec3(4.0f), reinhard).x, 1.0f, 1e-5);  // the white point
  float prev = -1.0f;
  for (int i = 0; i <= 40; ++i) {
    const float y = tone_map(glm::vec3(i * 0.1f), reinhard).y;
    EXPECT_GT(y, prev);
    prev = y;
  }
  // Hue is kept: a colour's channel ratios survive before encoding.
  const glm::vec3 c = tone_map(glm::vec3(0.8f, 0.4f, 0.2f), reinhard);
  EXPECT_GT(c.x, c.y);
  EXPECT_GT(c.y, c.z);
  EXPECT_EQ(to_srgb(std::vector<glm::vec3>{glm::vec3(0.5f)}, 1.0).size(), 1u);
}

// ---- parsing ----------------------------------------------------------------------------------------

TEST(Lights, SpecStrings) {
  Lighting l;
  add_light_spec(l, "sky:1.0");
  add_light_spec(l, "cloudy:0.5,up=0,1,0,rgb=1,0.5,0.25");
  add_light_spec(l, "dir:0,0,-2,E=3");
  add_light_spec(l, "point:0,2,1,I=10");
  add_light_spec(l, "area:0,0,2;1,0,2;1,1,2;0,1,2,L=5");
  ASSERT_EQ(l.size(), 5u);
  EXPECT_EQ((*l.all<HemisphereSkyLight>()[0]).up, glm::dvec3(0, 1, 0));
  EXPECT_EQ((*l.all<HemisphereSkyLight>()[0]).radiance, glm::dvec3(0.5, 0.25, 0.125));
  EXPECT_EQ((*l.all<DirectionalLight>()[0]).direction, glm::dvec3(0, 0, -1));
  EXPECT_EQ((*l.all<DirectionalLight>()[0]).irradiance, glm::dvec3(3.0));
  EXPECT_EQ((*l.all<PointLight>()[0]).position, glm::dvec3(0, 2, 1));
  EXPECT_EQ((*l.all<PointLight>()[0]).intensity, glm::dvec3(10.0));
  EXPECT_EQ((*l.all<AreaLight>()[0]).polygon.size(), 4u);
  EXPECT_EQ((*l.all<AreaLight>()[0]).radiance, glm::dvec3(5.0));
  EXPECT_NEAR((*l.all<AreaLight>()[0]).normal.z, 1.0, 1e-15);
  EXPECT_FALSE(l.describe().empty());

  for (const char* bad :
       {"lamp:1", "sky:abc", "dir:0,0,0", "dir:0,0,-1,E=-1", "point:1,2", "point:0,0,1,Q=3",
        "area:0,0,0;1,0,0,L=1", "area:0,0,0;1,0,0;1,1,0;0.6,0.5,0,L=1", "area:0,0,0;2,1,0;0,1,0;2,0,0,L=1",
        "area:0,0,0;1,0,0;1,1,1;0,1,0,L=1", "env:/nonexistent/x.hdr", "sky:1,L=2,L=3"}) {
    Lighting x;
    EXPECT_THROW(add_light_spec(x, bad), InputError) << bad;
  }
}

TEST(Lights, JsonFilesAndSetups) {
  const std::string text = R"({"lights": [
      "sky:0.5",
      {"type": "point", "position": [0, 2, 1], "intensity": 10, "color": [1, 0.5, 0.5]},
      {"type": "area", "vertices": [[0,0,2],[1,0,2],[1,1,2]], "radiance": [1, 2, 3], "two_sided": false},
      {"type": "directional", "direction": [0, 0, -1], "irradiance": 2}]})";
  const Lighting l = parse_lighting_json(text, "test.json");
  EXPECT_EQ(l.size(), 4u);
  EXPECT_EQ((*l.all<PointLight>()[0]).intensity, glm::dvec3(10, 5, 5));
  EXPECT_FALSE((*l.all<AreaLight>()[0]).two_sided);
  EXPECT_EQ((*l.all<AreaLight>()[0]).radiance, glm::dvec3(1, 2, 3));

  try {
    parse_lighting_json(R"({"lights": [{"type": "point", "position": [0, 2]}]})", "bad.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "bad.json");
    EXPECT_EQ(e.place(), "lights[0].position");
  }
  EXPECT_THROW(parse_lighting_json("{", "bad.json"), InputError);
  EXPECT_THROW(parse_lighting_json(R"({"lights": [{"type": "sky", "radius": 1}]})", "bad.json"), InputError);

  const auto setups = parse_lighting_setups_json(
      R"({"setups": [{"name": "overcast", "lights": ["cloudy:1"]}, {"name": "lamp", "lights": ["point:0,0,3,I=9", "sky:0.1"]}]})",
      "setups.json");
  ASSERT_EQ(setups.size(), 2u);
  EXPECT_EQ(setups[0].name, "overcast");
  EXPECT_EQ(setups[1].size(), 2u);
  EXPECT_THROW(parse_lighting_setups_json(R"({"setups": [{"name": "a/b", "lights": []}]})", "s.json"),
               InputError);
  EXPECT_THROW(parse_lighting_setups_json(
                   R"({"setups": [{"name": "a", "lights": []}, {"name": "a", "lights": []}]})", "s.json"),
               InputError);
}

// ---- pleat shade ------------------------------------------------------------------------------------

TEST(ShadeCommand, RelightWritesOneOutputPerSetupAndRejectsBadLights) {
  test::TempDir dir;
  const std::string d = dir.path().string();
  ASSERT_EQ(test::run_pleat("generate curtain -o " + d + "/c.obj --resolution 12 --frames 3").exit_code, 0);
  {
    std::ofstream setups(dir / "setups.json");
    setups << R"({"setups": [{"name": "overcast", "lights": ["cloudy:1,up=0,1,0"]},
                             {"name": "lamp", "lights": ["sky:0.1", "point:0,-1,2,I=4"]}]})";
  }
  const auto relit = test::run_pleat("shade " + d + "/c.obj --cache " + d + "/c.pc2 -o " + d +
                                     "/out/c.glb --relight " + d + "/setups.json --frames 1:3");
  ASSERT_EQ(relit.exit_code, 0) << relit.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "out/c_overcast.glb"));
  EXPECT_TRUE(std::filesystem::exists(dir / "out/c_lamp.glb"));
  EXPECT_FALSE(std::filesystem::exists(dir / "out/c.glb"));

  const auto single = test::run_pleat("shade " + d + "/c.obj --cache " + d + "/c.pc2 -o " + d +
                                      "/one.glb --light sky:0.5 --light 'dir:0,-1,0,E=2' --frames 2");
  ASSERT_EQ(single.exit_code, 0) << single.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "one.glb"));

  const auto bad =
      test::run_pleat("shade " + d + "/c.obj --cache " + d + "/c.pc2 -o " + d + "/bad.glb --light lamp:3");
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.output.find("lamp:3"), std::string::npos) << bad.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "bad.glb"));
}

}  // namespace
}  // namespace pleat
