// Occluders (sim_io/scene.hpp): the meshes and ground a cloth was simulated against block its sky and
// receive no cones. Closed forms (a sheet over the ground, beside an infinite wall), ray casting of the same
// scene, kinetic = static with a moving occluder, cloth touching and crossing the ground, bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numeric>
#include <string>
#include <vector>

#include "kinetic/kinetic_visibility.hpp"
#include "oracles/test_meshes.hpp"
#include "shading/embree_scene.hpp"
#include "shading/path_trace.hpp"
#include "shading/ray_visibility.hpp"
#include "sim_io/cloth_generators.hpp"
#include "sim_io/obj_format.hpp"
#include "sim_io/scene.hpp"
#include "static_core/internal/frame_assembly.hpp"
#include "static_core/mesh_connectivity.hpp"
#include "static_core/visibility.hpp"
#include "support/input_error.hpp"
#include "test_support.hpp"

namespace pleat {
namespace {

/// A cloth of one frame as a sequence (the scenes are built over sequences).
MeshSequence sequence_of(const test::TestMesh& mesh) {
  return MeshSequence("sheet", mesh.topology, {mesh.frame});
}

/// The first `count` frames of a generated cloth as a sequence.
MeshSequence generated(ClothKind kind, GeneratorParams params, int count) {
  const ClothGenerator generator(kind, params);
  std::vector<Frame> frames;
  for (int f = 0; f < count; ++f) frames.push_back(generator.frame(f));
  return MeshSequence(std::string(cloth_kind_name(kind)), generator.topology(), std::move(frames));
}

/// The cones of frame `f` of the cloth in `scene`, with the plan the CLI makes (lattice over the cloth).
FrameVisibility cones_in(const Scene& scene, const MeshSequence& cloth, std::size_t f = 0) {
  const SlicingPlan plan = make_diffuse_plan(cloth.topology(), cloth.frame(0), {}, &cloth.bounds());
  return compute_visibility(scene.topology(), scene.frame(f), plan);
}

TEST(Occluders, ASheetOverTheGroundSeesTheSkyAboveAndNothingBelow) {
  auto sheet = test::flat_sheet(15, 12, 0.1);
  for (auto& p : sheet.frame.positions) p.z = 0.3;  // 0.3 above the ground z = 0; front (+z) faces up
  const MeshSequence cloth = sequence_of(sheet);
  const Scene alone(cloth), grounded(cloth, std::vector<OccluderSpec>{}, {parse_ground_plane("z=0")});
  EXPECT_EQ(grounded.topology().num_occluder_vertices, 4u);
  EXPECT_EQ(grounded.topology().num_receivers(), cloth.topology().num_vertices);
  const FrameVisibility free = cones_in(alone, cloth), held = cones_in(grounded, cloth);
  ASSERT_EQ(held.measures[0].size(), cloth.topology().num_vertices);  // the ground gets no cone
  for (Index v = 0; v < cloth.topology().num_vertices; ++v) {
    EXPECT_NEAR(free.measure(Side::Back, v).sky_visibility, 1.0, 1e-9) << v;
    EXPECT_NEAR(held.measure(Side::Front, v).sky_visibility, 1.0, 1e-9) << v;
    // An infinite ground: the back's hemisphere meets the sky above the ground in its horizon alone.
    EXPECT_EQ(held.measure(Side::Back, v).sky_visibility, 0.0) << v;
  }
}

TEST(Occluders, AnUprightSheetOverTheGroundSeesHalfItsHemisphereOnEachSide) {
  // The sheet in the plane y = 0, from 0.2 to 1.3 above the ground z = 0: each side's hemisphere is cut in
  // two halves of equal cosine weight by the ground's horizon (the lune between the two great circles).
  auto sheet = test::flat_sheet(12, 12, 0.1);
  for (auto& p : sheet.frame.positions) p = {p.x, 0.0, 0.2 + p.y};
  const MeshSequence cloth = sequence_of(sheet);
  const Scene grounded(cloth, std::vector<OccluderSpec>{}, {parse_ground_plane("z=0")});
  const FrameVisibility held = cones_in(grounded, cloth);
  double worst = 0.0;
  for (Side side : kBothSides)
    for (Index v = 0; v < cloth.topology().num_vertices; ++v)
      worst = std::max(worst, std::abs(held.measure(side, v).sky_visibility - 0.5));
  EXPECT_LT(worst, 0.005);
}

/// A small upright sheet, 0.3 wide, 10 units over the ground z = 0.
MeshSequence upright_sheet_high_over_the_ground() {
  auto sheet = test::flat_sheet(4, 4, 0.1);
  for (auto& p : sheet.frame.positions) p = {p.x, 0.0, 10.0 + p.y};
  return sequence_of(sheet);
}

TEST(Occluders, RayCastingTakesTheGroundAsAnInfinitePlane) {
  // A small upright sheet high over the ground z = 0: the ground's square (50 cloth diagonals to each side)
  // is seen from it under 0.5 rad below the horizon, so rays cast at the square alone would let a band of
  // sky through beyond its edge (A about 0.74 instead of 0.5). The reference takes the plane exactly, as
  // the engines do.
  const MeshSequence cloth = upright_sheet_high_over_the_ground();
  const Scene grounded(cloth, std::vector<OccluderSpec>{}, {parse_ground_plane("z=0")});
  const Frame frame = grounded.frame(0);
  const FrameVisibility vis = cones_in(grounded, cloth);
  EmbreeScene rays(grounded.topology(), frame);
  RayVisibilityParams params;
  params.rays_per_vertex = 1024;
  const auto truth = ray_cast_sky_visibility(rays, grounded.topology(), frame, vis.normals, params);
  for (Side side : kBothSides)
    for (Index v = 0; v < cloth.topology().num_vertices; ++v) {
      EXPECT_NEAR(truth[int(side)][v], 0.5, 0.01) << v;
      EXPECT_NEAR(vis.measure(side, v).sky_visibility, 0.5, 0.005) << v;
    }
}

TEST(Occluders, PathTracingTakesTheGroundAsAnInfinitePlane) {
  // The same sheet under a uniform sky L = 1, every surface grey (albedo rho = 1/2): the ground, lit by the
  // whole sky but for the small sheet, leaves rho L; each side of the upright sheet sees sky over half its
  // cosine-weighted hemisphere and ground over the other half, so B = rho (1 + rho) L / 2 = 0.375. Paths that
  // passed the square's edge into the sky would read about rho (0.74 + 0.26 rho) L = 0.435.
  const MeshSequence cloth = upright_sheet_high_over_the_ground();
  const Scene grounded(cloth, std::vector<OccluderSpec>{}, {parse_ground_plane("z=0")});
  const Frame frame = grounded.frame(0);
  EmbreeScene rays(grounded.topology(), frame);
  Lighting lighting;
  lighting.lights.push_back(UniformSkyLight{glm::dvec3(1.0)});
  PathTraceParams params;
  params.paths_per_vertex = 2048;
  params.albedo = 0.5;
  const PathTracedFrame traced = path_trace_vertices(rays, grounded.topology(), frame,
                                                     cones_in(grounded, cloth).normals, lighting, params);
  double sum = 0.0;
  std::size_t count = 0;
  for (Side side : kBothSides)
    for (Index v = 0; v < cloth.topology().num_vertices; ++v, ++count) sum += traced.radiance[int(side)][v].x;
  EXPECT_NEAR(sum / double(count), 0.375, 0.01);
}

TEST(Occluders, AnInfiniteWallBesideASheetHidesHalfOfEachSide) {
  // A vertical wall x = 1 (two triangles a thousand units wide) beside a sheet over [0, 0.7]^2 at z = 0:
  // every direction with a positive x component meets it, half of each hemisphere's cosine-weighted sky.
  test::TempDir dir;
  MeshTopology wall{.num_vertices = 4, .triangles = {{0, 1, 2}, {0, 2, 3}}};
  write_obj(dir / "wall.obj", wall, {{1, -1000, -1000}, {1, 1000, -1000}, {1, 1000, 1000}, {1, -1000, 1000}});
  const MeshSequence cloth = sequence_of(test::flat_sheet(8, 8, 0.1));
  const Scene scene(cloth, {parse_occluder_spec((dir / "wall.obj").string())}, {});
  const FrameVisibility vis = cones_in(scene, cloth);
  for (Index v = 0; v < cloth.topology().num_vertices; ++v)
    for (Side side : kBothSides) EXPECT_NEAR(vis.measure(side, v).sky_visibility, 0.5, 2e-3) << v;
}

TEST(Occluders, ConesAgreeWithRayCastingOfTheSameScene) {
  // A folded generated cloth over the ground and an animated occluder: the cones against 1024 cosine-
  // weighted rays per vertex and side cast in the scene itself (occluders and ground included).
  test::TempDir dir;
  const MeshSequence cloth = generated(ClothKind::Roll, {18, 3, 24.0, 0}, 3);
  const Bounds& box = cloth.bounds();
  // A block under part of the roll, as an OBJ (static: one frame).
  const glm::dvec3 lo = box.lo - glm::dvec3(0.2), hi = glm::dvec3(box.hi.x, box.lo.y, box.hi.z);
  const test::TestMesh block = test::closed_box(lo, hi);
  write_obj(dir / "block.obj", block.topology, block.frame.positions);
  const std::string ground = "y=" + std::to_string(box.lo.y - 0.05);
  const Scene scene(cloth, {parse_occluder_spec((dir / "block.obj").string())}, {parse_ground_plane(ground)});
  const Frame frame = scene.frame(2);
  const FrameVisibility vis = cones_in(scene, cloth, 2);
  EmbreeScene rays(scene.topology(), frame);
  RayVisibilityParams params;
  params.rays_per_vertex = 1024;
  const auto truth = ray_cast_sky_visibility(rays, scene.topology(), frame, vis.normals, params);
  ASSERT_EQ(truth[0].size(), cloth.topology().num_vertices);
  double error = 0.0;
  for (Side side : kBothSides)
    for (Index v = 0; v < cloth.topology().num_vertices; ++v)
      error += std::abs(vis.measure(side, v).sky_visibility - truth[int(side)][v]);
  error /= 2.0 * cloth.topology().num_vertices;
  EXPECT_LT(error, 0.03) << "mean |A - A_rays| in the scene";
  // Without the occluders the cones answer another question: far from the scene's truth.
  const FrameVisibility alone = cones_in(Scene(cloth), cloth, 2);
  double alone_error = 0.0;
  for (Side side : kBothSides)
    for (Index v = 0; v < cloth.topology().num_vertices; ++v)
      alone_error += std::abs(alone.measure(side, v).sky_visibility - truth[int(side)][v]);
  alone_error /= 2.0 * cloth.topology().num_vertices;
  EXPECT_GT(alone_error, 3.0 * error);
}

TEST(Occluders, KineticEqualsStaticWithAMovingOccluderAndTheGround) {
  test::TempDir dir;
  const MeshSequence cloth = generated(ClothKind::Flag, {12, 10, 24.0, 3}, 10);
  // A tilted quad sweeping through the flag's box, frame by frame (an OBJ sequence).
  const Bounds& box = cloth.bounds();
  const glm::dvec3 c = 0.5 * (box.lo + box.hi), size = box.hi - box.lo;
  MeshTopology quad{.num_vertices = 4, .triangles = {{0, 1, 2}, {0, 2, 3}}};
  for (int f = 0; f < 10; ++f) {
    const double x = box.lo.x + size.x * (0.1 + 0.08 * f);
    char name[64];
    std::snprintf(name, sizeof name, "quad_%02d.obj", f);
    write_obj(dir / name, quad,
              {{x, c.y - size.y, c.z - size.z},
               {x + 0.3 * size.x, c.y + size.y, c.z - size.z},
               {x + 0.3 * size.x, c.y + size.y, c.z + size.z},
               {x, c.y - size.y, c.z + size.z}});
  }
  const Scene scene(cloth, {parse_occluder_spec((dir / "quad_%02d.obj").string())},
                    {parse_ground_plane("y=" + std::to_string(box.lo.y - 0.01))});
  const SlicingPlan plan = make_diffuse_plan(cloth.topology(), cloth.frame(0), {}, &box);
  KineticVisibility kinetic(scene.topology(), plan, scene.frame(0));
  std::size_t crossings = 0;
  for (std::size_t f = 1; f < 10; ++f) {
    const Frame frame = scene.frame(f);
    const FrameVisibility& k = kinetic.advance(frame);
    const FrameVisibility s = compute_visibility(scene.topology(), frame, plan);
    crossings += s.stats.chain_crossings;
    // The quad hides part of the flag's sky in every frame (against the flag alone).
    const FrameVisibility alone = compute_visibility(cloth.topology(), cloth.frame(f), plan);
    double hidden = 0.0;
    for (Index v = 0; v < cloth.topology().num_vertices; ++v)
      hidden = std::max(
          hidden, alone.measure(Side::Front, v).sky_visibility - s.measure(Side::Front, v).sky_visibility);
    EXPECT_GT(hidden, 0.05) << "frame " << f;
    ASSERT_EQ(k.measures[0].size(), cloth.topology().num_vertices);
    for (Side side : kBothSides)
      for (Index v = 0; v < cloth.topology().num_vertices; ++v)
        ASSERT_EQ(k.measure(side, v).sky_visibility, s.measure(side, v).sky_visibility)
            << "frame " << f << " vertex " << v;
  }
  // The quad cuts through the flag, but an occluder is cast as a shadow, never triangulated with the cloth
  // (docs/method.md §3): no chain crossing, no failure.
  EXPECT_EQ(crossings, 0u);
}

TEST(Occluders, PlanesCuttingOnlyOccludersAreNotTriangulated) {
  // A flag and a tall quad beside it, beyond the flag's box: the planes over the box that cut the quad but
  // not the flag offer no cone, so neither engine triangulates them.
  test::TempDir dir;
  const MeshSequence cloth = generated(ClothKind::Flag, {12, 10, 24.0, 3}, 6);
  const Bounds& box = cloth.bounds();
  const glm::dvec3 size = box.hi - box.lo;
  const double x = box.hi.x + 0.05 * size.x;
  write_obj(dir / "wall.obj", MeshTopology{.num_vertices = 4, .triangles = {{0, 1, 2}, {0, 2, 3}}},
            {{x, box.lo.y - size.y, box.lo.z - size.z},
             {x + 0.2 * size.x, box.hi.y + size.y, box.lo.z - size.z},
             {x + 0.2 * size.x, box.hi.y + size.y, box.hi.z + size.z},
             {x, box.lo.y - size.y, box.hi.z + size.z}});
  const Scene scene(cloth, {parse_occluder_spec((dir / "wall.obj").string())}, {});
  const MeshTopology& topology = scene.topology();
  const SlicingPlan plan = make_diffuse_plan(cloth.topology(), cloth.frame(0), {}, &box);
  const MeshConnectivity connectivity(topology);
  std::vector<Index> all(topology.triangles.size());
  std::iota(all.begin(), all.end(), Index(0));
  SlicerScratch slicer;
  PlaneConeScratch scratch;
  FrameMarks marks;
  mark_frame(topology, connectivity, scene.frame(0), marks);
  std::size_t occluders_only = 0;
  for (const SlicingPlane& plane : plan.planes) {
    PlaneCones out;
    slice_mesh(topology, connectivity, scene.frame(0), plane, all, slicer, out.slice);
    const bool receives =
        std::any_of(out.slice.vertices.begin(), out.slice.vertices.end(),
                    [&](const SliceVertex& v) { return v.above < topology.num_receivers(); });
    ASSERT_EQ(offer_plane_cones(topology.num_receivers(), plan.storage, scene.frame(0), marks.whole_fans,
                                scratch, out),
              receives);
    if (receives || out.slice.vertices.empty()) continue;
    ++occluders_only;
    EXPECT_TRUE(out.stored.empty());
    ASSERT_EQ(out.cones.offsets.size(), 2 * out.slice.vertices.size() + 1);
    for (Index v = 0; v < out.slice.vertices.size(); ++v)
      for (Side side : kBothSides) EXPECT_TRUE(out.cones.cone(v, side).empty());
  }
  EXPECT_GT(occluders_only, 0u);  // the case is exercised
  // The kinetic engine slices such planes afresh every frame (never carried) and equals the static one.
  KineticVisibility kinetic(topology, plan, scene.frame(0));
  std::size_t resliced = 0;
  for (std::size_t f = 1; f < 6; ++f) {
    const FrameVisibility& k = kinetic.advance(scene.frame(f));
    resliced +=
        kinetic.last_stats().rebuilt_because[static_cast<std::size_t>(kinetic::RebuildReason::no_cones)];
    const FrameVisibility s = compute_visibility(topology, scene.frame(f), plan);
    for (Side side : kBothSides)
      for (Index v = 0; v < cloth.topology().num_vertices; ++v)
        ASSERT_EQ(k.measure(side, v).sky_visibility, s.measure(side, v).sky_visibility)
            << "frame " << f << " vertex " << v;
    EXPECT_EQ(k.stats.regions, s.stats.regions);
    EXPECT_EQ(k.stats.windows, s.stats.windows);
  }
  EXPECT_GT(resliced, 0u);  // (intervals the engine rebuilds as a whole count as frame_cost)
}

TEST(Occluders, ATopologyMixingClothAndOccludersIsRefused) {
  // The engines slice the cloth's triangles and the occluders' apart (split_faces): a triangle joining the
  // two, or a cloth triangle after an occluder's, is named.
  const Frame frame{0.0, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}}};
  const MeshTopology joined{
      .num_vertices = 6, .triangles = {{0, 1, 2}, {2, 3, 4}}, .num_occluder_vertices = 3};
  const MeshTopology after{
      .num_vertices = 6, .triangles = {{0, 1, 2}, {3, 4, 5}, {0, 2, 1}}, .num_occluder_vertices = 3};
  const SlicingPlan plan =
      make_diffuse_plan(MeshTopology{.num_vertices = 3, .triangles = {{0, 1, 2}}},
                        Frame{0.0, {frame.positions.begin(), frame.positions.begin() + 3}}, {});
  for (const auto& [topology, says] :
       {std::pair{joined, "joins cloth and occluder vertices"}, std::pair{after, "after an occluder's"}}) {
    try {
      compute_visibility(topology, frame, plan);
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("triangle"), std::string::npos) << e.what();
    }
  }
}

TEST(Occluders, ClothLyingOnOrThroughTheGroundIsFine) {
  for (const double height : {0.0, -0.02, 1e-12}) {  // touching, penetrating, a hair above
    auto sheet = test::flat_sheet(10, 10, 0.1);
    for (std::size_t v = 0; v < sheet.frame.positions.size(); ++v)
      sheet.frame.positions[v].z =
          height + (v % 3 == 0 ? 0.05 : 0.0);  // some above the ground, some at height
    const MeshSequence cloth = sequence_of(sheet);
    const Scene scene(cloth, std::vector<OccluderSpec>{}, {parse_ground_plane("z=0")});
    const FrameVisibility vis = cones_in(scene, cloth);
    for (Side side : kBothSides)
      for (Index v = 0; v < cloth.topology().num_vertices; ++v) {
        const double a = vis.measure(side, v).sky_visibility;
        EXPECT_TRUE(a >= 0.0 && a <= 1.0) << height << " " << v;
      }
    // The ground is applied as a plane, not sliced: a cloth through it makes no chain crossing.
    EXPECT_EQ(vis.stats.chain_crossings, 0u) << height;
  }
}

TEST(Occluders, BadOccludersNameTheFile) {
  test::TempDir dir;
  const MeshSequence cloth = generated(ClothKind::Curtain, {6, 3, 24.0, 0}, 3);
  auto fails_naming = [&](const std::string& spec, const std::string& file, const std::string& what) {
    try {
      Scene(cloth, {parse_occluder_spec(spec)}, {});
      ADD_FAILURE() << "accepted " << spec;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  fails_naming((dir / "missing.obj").string(), "missing.obj", "");
  std::ofstream(dir / "nan.obj") << "v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n";
  fails_naming((dir / "nan.obj").string(), "nan.obj", "");
  // Two frames of an occluder against three of the cloth.
  MeshTopology tri{.num_vertices = 3, .triangles = {{0, 1, 2}}};
  write_obj(dir / "t_0.obj", tri, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  write_obj(dir / "t_1.obj", tri, {{0, 0, 1}, {1, 0, 1}, {0, 1, 1}});
  fails_naming((dir / "t_%d.obj").string(), "t_%d.obj", "in 2 frames, the cloth frames 0 to 2 in 3");
  EXPECT_THROW(parse_occluder_spec(""), std::invalid_argument);
  EXPECT_THROW(parse_occluder_spec("a.obj,cache="), std::invalid_argument);
  EXPECT_EQ(parse_occluder_spec("a.obj,cache=b.pc2").cache, "b.pc2");
  EXPECT_THROW(parse_ground_plane("w=0"), std::invalid_argument);
  EXPECT_THROW(parse_ground_plane("y=zero"), std::invalid_argument);
  EXPECT_THROW(parse_ground_plane("y=inf"), std::invalid_argument);
  EXPECT_EQ(parse_ground_plane("z=-1.5").axis, 2);
  EXPECT_EQ(parse_ground_plane("z=-1.5").height, -1.5);
}

}  // namespace
}  // namespace pleat
