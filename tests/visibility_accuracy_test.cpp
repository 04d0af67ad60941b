// 3D visibility from cones against closed forms and against Embree ray casting (4096 cosine-weighted rays
// per vertex and side) on the generated folded sequences.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "oracles/test_meshes.hpp"
#include "shading/ray_visibility.hpp"
#include "sim_io/cloth_generators.hpp"
#include "sim_io/load_sequence.hpp"
#include "sim_io/mesh_sequence.hpp"
#include "static_core/internal/fan_cone.hpp"
#include "static_core/internal/frame_assembly.hpp"
#include "static_core/mesh_connectivity.hpp"
#include "static_core/visibility.hpp"
#include "test_support.hpp"

namespace pleat {
namespace {

constexpr double kPi = 3.14159265358979323846;

FrameVisibility cones_of(const test::TestMesh& mesh, int orientations = 6) {
  const SlicingPlan plan = make_diffuse_plan(mesh.topology, mesh.frame, {orientations, 0.0, 0});
  return compute_visibility(mesh.topology, mesh.frame, plan);
}

TEST(VisibilityAccuracy, FlatSheetSeesEverythingOnBothSides) {
  const auto sheet = test::flat_sheet(12, 9);
  const FrameVisibility vis = cones_of(sheet);
  for (Index v = 0; v < sheet.topology.num_vertices; ++v)
    for (Side s : kBothSides) EXPECT_NEAR(vis.measure(s, v).sky_visibility, 1.0, 1e-9) << v;
}

TEST(VisibilityAccuracy, TiltedFlatSheetToo) {
  auto sheet = test::flat_sheet(10, 10);
  test::rigid_transform(sheet, {0.3, -1.1, 0.7}, 0.9, {5, -2, 1});
  const FrameVisibility vis = cones_of(sheet);
  for (Index v = 0; v < sheet.topology.num_vertices; ++v)
    for (Side s : kBothSides) EXPECT_NEAR(vis.measure(s, v).sky_visibility, 1.0, 1e-9) << v;
}

TEST(VisibilityAccuracy, InsideOfAClosedSphereSeesNothing) {
  const auto sphere = test::icosphere(3);  // outward normals: the back side is inside
  const FrameVisibility vis = cones_of(sphere);
  for (Index v = 0; v < sphere.topology.num_vertices; ++v) {
    EXPECT_EQ(vis.measure(Side::Back, v).sky_visibility, 0.0) << v;
    EXPECT_NEAR(vis.measure(Side::Front, v).sky_visibility, 1.0, 5e-3)
        << v;  // polyhedral: the faces dip below the hemisphere
  }
}

TEST(VisibilityAccuracy, BottomOfAVFoldSeesTheLuneBetweenItsArms) {
  // Two long planes meeting along the x axis, opening upwards with half-angle alpha: from the bottom
  // line the visible set is the lune between the planes, A = sin(alpha) (see ray_visibility_test).
  for (double alpha : {kPi / 6, kPi / 4, kPi / 3}) {
    const auto fold = test::v_fold(alpha, 41, 21, 20.0, 10.0);
    const FrameVisibility vis = cones_of(fold);
    const Index bottom = fold.marked_vertex;
    // The bottom's cones come from slice points up to half an edge up the arms (the paper stores each
    // slice point's cone on the nearer mesh vertex): horizontal slices see the lune's tips slightly
    // widened, oblique ones are bounded by the arm's own tangent there, which is interior to the bottom's
    // hemisphere: on the outside of the crease this cuts notches whose size depends on where the planes
    // fall. Measured: inside +0.7% to +1.4%; outside -2% to -7.5% (planes one average edge apart).
    EXPECT_NEAR(vis.measure(Side::Front, bottom).sky_visibility, std::sin(alpha), 0.02) << alpha;
    EXPECT_NEAR(vis.measure(Side::Back, bottom).sky_visibility, 1.0, 0.1) << alpha;
  }
}

struct ErrorStats {
  double mean = 0, p95 = 0, bias = 0;
};

ErrorStats compare_with_rays(const MeshTopology& topology, const Frame& frame) {
  const SlicingPlan plan = make_diffuse_plan(topology, frame, {});
  const FrameVisibility vis = compute_visibility(topology, frame, plan);
  EmbreeScene scene(topology, frame);
  const RayVisibility rays = ray_cast_visibility(scene, topology, frame, vis.normals, {4096, 11, true});
  std::vector<double> errors;
  ErrorStats stats;
  for (int s = 0; s < 2; ++s)
    for (Index v = 0; v < topology.num_vertices; ++v) {
      const double d = vis.measures[s][v].sky_visibility - rays.sky_visibility[s][v];
      errors.push_back(std::abs(d));
      stats.bias += d;
    }
  std::sort(errors.begin(), errors.end());
  for (double e : errors) stats.mean += e;
  stats.mean /= errors.size();
  stats.bias /= errors.size();
  stats.p95 = errors[errors.size() * 95 / 100];
  return stats;
}

TEST(VisibilityAccuracy, ConesAgreeWithRayCastingOnGeneratedCloth) {
  // Bounds: measured on 2026-11-25 at resolution 40 (1,600 vertices: coarser than the benchmark's 3,025),
  // mid-motion frame, the defaults (8 relaxed spread orientations 1/2 edge apart, interpolated-on-fan
  // storage): mean |dA| curtain 0.0250, roll 0.0104, flag 0.0074, sleeve 0.0184; p95 0.138 / 0.032 / 0.026 /
  // 0.064; |bias| <= 0.0053 (3/4 edge apart on the spiral: 0.0075-0.029 and 0.026-0.122; 1 edge apart and
  // nearest-on-fan: 0.009-0.035 and 0.03-0.135; the paper's plan: 0.014-0.037 and 0.05-0.16). The bounds
  // leave about 1.3x for noise and guard against regressions.
  struct Bound {
    ClothKind kind;
    double mean, p95;
  };
  for (const Bound& b : {Bound{ClothKind::Curtain, 0.033, 0.18}, Bound{ClothKind::Roll, 0.014, 0.042},
                         Bound{ClothKind::Flag, 0.01, 0.034}, Bound{ClothKind::Sleeve, 0.024, 0.083}}) {
    const ClothGenerator generator(b.kind, {40, 12, 24.0, 0});
    const ErrorStats e = compare_with_rays(generator.topology(), generator.frame(6));
    std::printf("%-8s mean |A_cone - A_rays| %.4f  p95 %.4f  bias %+.4f\n",
                std::string(cloth_kind_name(b.kind)).c_str(), e.mean, e.p95, e.bias);
    EXPECT_LT(e.mean, b.mean) << cloth_kind_name(b.kind);
    EXPECT_LT(e.p95, b.p95) << cloth_kind_name(b.kind);
    EXPECT_LT(std::abs(e.bias), 0.01) << cloth_kind_name(b.kind);
  }
}

TEST(VisibilityAccuracy, ConesAgreeWithRayCastingOnTheBundledBlenderCloth) {
  // Measured 2026-11-25 with the defaults (8 relaxed spread orientations 1/2 edge apart, interpolated-on-fan
  // storage), 4096 rays: drape frames 20/60/99 mean 0.0143/0.0150/0.0143, p95 0.044/0.046/0.042; pile (last
  // frame) 0.0110/0.040; rucked 0.0197/0.054; layered 0.0108/0.041; |bias| <= 0.0052 — every one within the
  // issue's mean 0.02 and p95 0.07. The bounds leave about 1.25x for noise and guard against regressions.
  // Before (3/4 edge apart on the spiral): drape 0.016-0.017 / 0.049-0.050, pile 0.014/0.050, rucked
  // 0.024/0.069, layered 0.0135/0.054; (1 edge apart, nearest-on-fan): drape 0.018-0.019 / 0.054-0.057, pile
  // 0.018/0.070, rucked 0.029/0.091; the paper's plan (6 axis orientations, nearer-endpoint storage): mean
  // 0.035-0.041 and p95 0.12-0.14.
  struct Case {
    const char* name;
    std::vector<int> frames;  // negative: from the end
    double mean, p95;
  };
  for (const Case& c : {Case{"drape", {20, 60, 99}, 0.019, 0.057}, Case{"pile", {-1}, 0.014, 0.05},
                        Case{"rucked", {-1}, 0.025, 0.068}, Case{"layered", {-1}, 0.014, 0.052}}) {
    const std::string dir = std::string("data/") + c.name + "/" + c.name;
    const MeshSequence cloth =
        load_sequence(test::source_dir() / (dir + ".obj"), test::source_dir() / (dir + ".pc2"));
    for (int f : c.frames) {
      const std::size_t k = f < 0 ? cloth.num_frames() - std::size_t(-f) : std::size_t(f);
      const ErrorStats e = compare_with_rays(cloth.topology(), cloth.frame(k));
      std::printf("%-7s frame %3zu  mean |A_cone - A_rays| %.4f  p95 %.4f  bias %+.4f\n", c.name, k, e.mean,
                  e.p95, e.bias);
      EXPECT_LT(e.mean, c.mean) << c.name << " " << k;
      EXPECT_LT(e.p95, c.p95) << c.name << " " << k;
      EXPECT_LT(std::abs(e.bias), 0.01) << c.name << " " << k;
    }
  }
}

TEST(VisibilityAccuracy, WholeFansAgreeWithRayCastingOnTheRuckedSleeve) {
  // The sleeve's rucks put most of its vertices on sharp fans, and its two cuffs are open fans
  // (static_core/internal/fan_cone.hpp): their cones come from every cut of the fan. Measured 2026-11-28 on
  // its last frame (the cloth alone, the defaults, 4096 rays): mean |dA| over the sharp fans' 3,842 sides
  // 0.0096, p95 0.0325 (with the nearest cut's cone alone, and the ray casting's side test before it was
  // exact, 0.0120 and 0.0396); over the open fans' 192 sides 0.0082, p95 0.0274 (the nearest cut's cone
  // alone: 0.0112, 0.0343). The bounds leave room for noise and fail without the fans' cuts.
  const std::string dir = "data/rucked/rucked";
  const MeshSequence cloth =
      load_sequence(test::source_dir() / (dir + ".obj"), test::source_dir() / (dir + ".pc2"));
  const Frame& frame = cloth.frame(cloth.num_frames() - 1);
  const FrameVisibility vis =
      compute_visibility(cloth.topology(), frame, make_diffuse_plan(cloth.topology(), frame, {}));
  EmbreeScene scene(cloth.topology(), frame);
  const RayVisibility rays =
      ray_cast_visibility(scene, cloth.topology(), frame, vis.normals, {4096, 11, true});
  const MeshConnectivity connectivity(cloth.topology());
  FrameMarks marks;
  mark_whole_fans(cloth.topology(), connectivity, frame, area_weighted_normals(cloth.topology(), frame),
                  marks.whole_fans);
  std::vector<double> sharp, open;
  for (int s = 0; s < 2; ++s)
    for (Index v = 0; v < cloth.topology().num_vertices; ++v) {
      const double error = std::abs(vis.measures[s][v].sky_visibility - rays.sky_visibility[s][v]);
      if (!connectivity.has_closed_fan(v))
        open.push_back(error);
      else if (marks.whole_fans[v])
        sharp.push_back(error);
    }
  ASSERT_GT(sharp.size(), cloth.topology().num_vertices);  // most of the sleeve: both sides of over half
  ASSERT_EQ(open.size(), 2u * 96);                         // both sides of the two cuffs' 48 vertices each
  auto mean_and_p95 = [](std::vector<double>& errors) {
    std::sort(errors.begin(), errors.end());
    double mean = 0;
    for (double e : errors) mean += e;
    return std::pair(mean / double(errors.size()), errors[errors.size() * 95 / 100]);
  };
  const auto [sharp_mean, sharp_p95] = mean_and_p95(sharp);
  const auto [open_mean, open_p95] = mean_and_p95(open);
  std::printf(
      "rucked sharp fans: %zu sides, mean |A_cone - A_rays| %.4f  p95 %.4f; open fans: %zu sides, %.4f "
      "%.4f\n",
      sharp.size(), sharp_mean, sharp_p95, open.size(), open_mean, open_p95);
  EXPECT_LT(sharp_mean, 0.0115);
  EXPECT_LT(sharp_p95, 0.038);
  EXPECT_LT(open_mean, 0.0097);
  EXPECT_LT(open_p95, 0.031);
}

}  // namespace
}  // namespace pleat
