// Path-traced reference radiance (shading/path_trace): exact cases (flat sheet under a sky and a directional
// light, the inside of a closed sphere), bounds at the bottom of a V-fold against the Stewart–Langer model,
// and determinism.
#include "shading/path_trace.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/glm.hpp>
#include <map>
#include <numbers>

#include "oracles/test_meshes.hpp"
#include "static_core/visibility.hpp"

namespace pleat {
namespace {

using Mesh = test::TestMesh;

Mesh flat_sheet(int n, double size) { return test::flat_sheet(n, n, size / (n - 1)); }

/// Unit octahedron subdivided `levels` times and pushed onto the sphere, outward winding.
Mesh sphere(int levels) {
  std::vector<glm::dvec3> p = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  std::vector<Triangle> f = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                             {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<Index, Index>, Index> mid;
    auto midpoint = [&](Index a, Index b) {
      const auto key = std::minmax(a, b);
      if (auto it = mid.find(key); it != mid.end()) return it->second;
      p.push_back(glm::normalize(p[a] + p[b]));
      return mid[key] = static_cast<Index>(p.size() - 1);
    };
    std::vector<Triangle> g;
    for (const Triangle& t : f) {
      const Index a = midpoint(t[0], t[1]), b = midpoint(t[1], t[2]), c = midpoint(t[2], t[0]);
      g.insert(g.end(),
               {Triangle{t[0], a, c}, Triangle{t[1], b, a}, Triangle{t[2], c, b}, Triangle{a, b, c}});
    }
    f = std::move(g);
  }
  Mesh m;
  m.topology.num_vertices = static_cast<Index>(p.size());
  m.topology.triangles = f;
  m.frame.positions = p;
  return m;
}

/// V-fold of half-angle alpha about +y, crease along z (see ray_visibility_test.cpp for the construction).
Mesh v_fold(double alpha, const std::vector<double>& offsets, const std::vector<double>& rows, int& columns) {
  Mesh m;
  const int half = static_cast<int>(offsets.size());
  columns = 2 * half - 1;
  for (double z : rows)
    for (int c = 0; c < columns; ++c) {
      const int k = c - (half - 1);
      const double s = offsets[static_cast<std::size_t>(std::abs(k))];
      m.frame.positions.push_back({(k < 0 ? -1.0 : 1.0) * s * std::sin(alpha), s * std::cos(alpha), z});
    }
  m.topology.num_vertices = static_cast<Index>(m.frame.positions.size());
  auto v = [&](int c, int r) { return static_cast<Index>(r * columns + c); };
  for (int r = 0; r + 1 < static_cast<int>(rows.size()); ++r)
    for (int c = half - 1; c + 1 < columns; ++c) {
      m.topology.triangles.push_back({v(c, r), v(c + 1, r + 1), v(c + 1, r)});
      m.topology.triangles.push_back({v(c, r), v(c, r + 1), v(c + 1, r + 1)});
      const int mc = columns - 1 - c;
      m.topology.triangles.push_back({v(mc, r), v(mc - 1, r), v(mc - 1, r + 1)});
      m.topology.triangles.push_back({v(mc, r), v(mc - 1, r + 1), v(mc, r + 1)});
    }
  return m;
}

PathTracedFrame trace(const Mesh& m, const Lighting& lighting, const PathTraceParams& params) {
  EmbreeScene scene(m.topology, m.frame);
  return path_trace_vertices(scene, m.topology, m.frame, vertex_normals(m.topology, m.frame), lighting,
                             params);
}

TEST(PathTrace, FlatSheetUnderAUniformSkyIsRhoL) {
  const Mesh sheet = flat_sheet(8, 1.0);
  Lighting lighting;
  lighting.lights.push_back(UniformSkyLight{glm::dvec3(1.0, 0.5, 0.25)});
  PathTraceParams params;
  params.paths_per_vertex = 64;
  params.albedo = 0.5;
  const PathTracedFrame r = trace(sheet, lighting, params);
  for (int s = 0; s < 2; ++s)
    for (Index v = 0; v < sheet.topology.num_vertices; ++v)
      EXPECT_EQ(r.radiance[s][v], glm::vec3(0.5f, 0.25f, 0.125f)) << s << " " << v;
}

TEST(PathTrace, FlatSheetUnderADirectionalLightIsRhoEOverPi) {
  const Mesh sheet = flat_sheet(6, 1.0);
  Lighting lighting;
  const glm::dvec3 travel = glm::normalize(glm::dvec3(0.3, 0.0, -1.0));
  lighting.lights.push_back(DirectionalLight{travel, glm::dvec3(2.0)});
  PathTraceParams params;
  params.paths_per_vertex = 16;
  params.albedo = 0.6;
  const PathTracedFrame r = trace(sheet, lighting, params);
  const float expected = static_cast<float>(0.6 / std::numbers::pi * 2.0 * -travel.z);
  for (Index v = 0; v < sheet.topology.num_vertices; ++v) {
    EXPECT_NEAR(r.radiance[0][v].x, expected, 1e-6f);
    EXPECT_EQ(r.radiance[1][v].x, 0.0f);
  }
}

TEST(PathTrace, InsideAClosedSphereIsDark) {
  const Mesh ball = sphere(3);
  Lighting lighting;
  lighting.lights.push_back(UniformSkyLight{glm::dvec3(1.0)});
  lighting.lights.push_back(DirectionalLight{glm::dvec3(0.0, 0.0, -1.0), glm::dvec3(3.0)});
  PathTraceParams params;
  params.paths_per_vertex = 32;
  const PathTracedFrame r = trace(ball, lighting, params);
  for (Index v = 0; v < ball.topology.num_vertices; ++v) {
    ASSERT_EQ(r.radiance[1][v], glm::vec3(0.0f)) << v;
    EXPECT_GE(r.radiance[0][v].x, 0.6f * 0.97f);  // outside: the sky (almost all of it) plus the sun
  }
}

// At the bottom of a V-fold (half-angle α, uniform sky L = 1, albedo ρ), one bounce gives ρA with A = sin α;
// the true radiance adds light reflected by the fold's faces, which are brighter than the bottom, so it lies
// between the Stewart–Langer value ρA / (1 − ρ(1 − A)) (which assumes the faces are as dark as the bottom)
// and ρ (a flat sheet).
TEST(PathTrace, VFoldBottomLiesBetweenStewartLangerAndFlat) {
  int columns = 0;
  const double alpha = 30.0 * std::numbers::pi / 180.0;
  const Mesh fold =
      v_fold(alpha, {0.0, 0.5, 1.0, 3.0, 10.0, 100.0}, {-100.0, -10.0, -1.0, 0.0, 1.0, 10.0, 100.0}, columns);
  Lighting lighting;
  lighting.lights.push_back(UniformSkyLight{glm::dvec3(1.0)});
  PathTraceParams params;
  params.paths_per_vertex = 4096;
  params.albedo = 0.7;
  const PathTracedFrame r = trace(fold, lighting, params);
  const Index bottom = static_cast<Index>(3 * columns + (columns - 1) / 2);
  ASSERT_EQ(fold.frame.positions[bottom], glm::dvec3(0.0));
  const double rho = params.albedo, a = std::sin(alpha);
  const double stewart_langer = rho * a / (1.0 - rho * (1.0 - a));
  const double b = r.radiance[0][bottom].x;
  const double noise = 3.0 * rho * std::sqrt(a * (1 - a) / params.paths_per_vertex);
  EXPECT_GT(b, stewart_langer - noise);
  EXPECT_LT(b, rho);
  EXPECT_EQ(r.radiance[1][bottom].x, static_cast<float>(rho));  // outside of the V: the open half-space
}

TEST(PathTrace, DeterministicForASeed) {
  int columns = 0;
  const Mesh fold = v_fold(0.6, {0.0, 0.5, 1.0}, {-1.0, 0.0, 1.0}, columns);
  Lighting lighting;
  lighting.lights.push_back(HemisphereSkyLight{glm::dvec3(1.0), glm::dvec3(0.0, 1.0, 0.0)});
  lighting.lights.push_back(PointLight{glm::dvec3(0.0, 2.0, 0.5), glm::dvec3(4.0)});
  PathTraceParams params;
  params.paths_per_vertex = 32;
  const PathTracedFrame a = trace(fold, lighting, params);
  params.parallel = false;
  const PathTracedFrame b = trace(fold, lighting, params);
  EXPECT_EQ(a.radiance, b.radiance);
  EXPECT_EQ(a.rays, b.rays);
  params.albedo = 1.0;
  EXPECT_THROW(trace(fold, lighting, params), std::invalid_argument);
}

}  // namespace
}  // namespace pleat
