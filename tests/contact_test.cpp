// Cloth in contact with its colliders (docs/method.md §6.2): a sheet resting on, just above, just inside and
// straddling a ground plane, a box top and a sphere has the values of the same sheet lifted onto the surface
// (rays cast in the scene); a ground mesh (open) and a ground plane on the other side of the axis the same;
// deeper penetration is counted, never inverted; kinetic = static in contact.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "kinetic/kinetic_visibility.hpp"
#include "oracles/test_meshes.hpp"
#include "shading/embree_scene.hpp"
#include "shading/ray_visibility.hpp"
#include "sim_io/load_sequence.hpp"
#include "sim_io/obj_format.hpp"
#include "sim_io/scene.hpp"
#include "static_core/visibility.hpp"
#include "test_support.hpp"

namespace pleat {
namespace {

enum class Surface { Ground, GroundMesh, Box, Sphere };
const char* name_of(Surface s) {
  switch (s) {
    case Surface::Ground:
      return "ground plane";
    case Surface::GroundMesh:
      return "ground mesh";
    case Surface::Box:
      return "box top";
    case Surface::Sphere:
      return "sphere";
  }
  return "";
}

/// The occluder of `surface` (none for the ground plane), its top at z = 0 under the sheet [0, 1]^2.
MeshSequence occluder_of(Surface surface) {
  MeshTopology topology;
  std::vector<glm::dvec3> positions;
  if (surface == Surface::GroundMesh) {  // two triangles facing up (+z), 20 wide: a plane mesh
    topology = {4, {{0, 1, 2}, {0, 2, 3}}};
    positions = {{-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0}};
  } else if (surface == Surface::Box) {  // [-1, 2]^2 x [-1, 0], outward winding
    test::TestMesh box = test::closed_box({-1, -1, -1}, {2, 2, 0});
    topology = box.topology;
    positions = box.frame.positions;
  } else {  // a sphere of radius 2 whose top vertex is at (0.5, 0.5, 0)
    test::TestMesh sphere = test::icosphere(4);
    glm::dvec3 top(0.0, 0.0, -1e300);
    for (const glm::dvec3& p : sphere.frame.positions)
      if (p.z > top.z) top = p;
    // Turn the top vertex onto +z, then scale and move it to (0.5, 0.5, 0).
    const glm::dvec3 axis = glm::cross(top, glm::dvec3(0, 0, 1));
    if (glm::length(axis) > 0)
      test::rigid_transform(sphere, glm::normalize(axis), std::acos(std::clamp(top.z, -1.0, 1.0)), {});
    for (glm::dvec3& p : sphere.frame.positions) p = 2.0 * p + glm::dvec3(0.5, 0.5, -2.0);
    topology = sphere.topology;
    positions = sphere.frame.positions;
  }
  return MeshSequence(name_of(surface), topology, {Frame{0.0, positions}});
}

/// The 11 x 11 sheet over [0, 1]^2 (front up), at height `lift` over the surface's top plus `tilt` x (x -
/// 1/2) (a sheet straddling it).
MeshSequence sheet(double lift, double tilt = 0.0) {
  test::TestMesh mesh = test::flat_sheet(11, 11, 0.1);
  for (glm::dvec3& p : mesh.frame.positions) p.z = lift + tilt * (p.x - 0.5);
  return MeshSequence("sheet", mesh.topology, {mesh.frame});
}

Scene scene_of(const MeshSequence& cloth, Surface surface, std::optional<double> tolerance = std::nullopt) {
  if (surface == Surface::Ground)
    return Scene::with_loaded(cloth, {}, {parse_ground_plane("z=0")}, tolerance);
  return Scene::with_loaded(cloth, {{name_of(surface), occluder_of(surface)}}, {}, tolerance);
}

FrameVisibility cones_in(const Scene& scene, const MeshSequence& cloth) {
  const SlicingPlan plan = make_diffuse_plan(cloth.topology(), cloth.frame(0), {}, &cloth.bounds());
  return compute_visibility(scene.topology(), scene.frame(0), plan);
}

/// The sheet lifted onto the surface: a hair above it (1e-4, beyond the rays' relative start 1e-6 of the
/// scene's diameter, so that no ray starts inside).
constexpr double kLifted = 1e-4;

/// The reference: 4096 rays per vertex and side cast in the scene of the sheet lifted onto the surface.
std::array<std::vector<double>, 2> lifted_truth(Surface surface) {
  const MeshSequence cloth = sheet(kLifted);
  const Scene scene = scene_of(cloth, surface);
  const Frame frame = scene.frame(0);
  EmbreeScene rays(scene.topology(), frame);
  RayVisibilityParams params;
  params.rays_per_vertex = 4096;
  return ray_cast_sky_visibility(rays, scene.topology(), frame, cones_in(scene, cloth).normals, params);
}

struct Placement {
  const char* name;
  double lift, tilt;
};
constexpr Placement kPlacements[] = {{"resting on", 0.0, 0.0},
                                     {"1 mm above", 1e-3, 0.0},
                                     {"1 mm into", -1e-3, 0.0},
                                     {"straddling", 0.0, 2e-3}};

TEST(Contact, ASheetOnTheGroundABoxOrASphereHasTheValuesOfTheSheetLiftedOntoIt) {
  for (const Surface surface : {Surface::Ground, Surface::GroundMesh, Surface::Box, Surface::Sphere}) {
    const auto truth = lifted_truth(surface);
    const MeshSequence on = sheet(kLifted);
    const FrameVisibility lifted = cones_in(scene_of(on, surface), on);
    for (const Placement& at : kPlacements) {
      const MeshSequence cloth = sheet(at.lift, at.tilt);
      const FrameVisibility vis = cones_in(scene_of(cloth, surface), cloth);
      double sum = 0.0, worst = 0.0, worst_lifted = 0.0;
      std::size_t count = 0;
      for (const Side side : kBothSides)
        for (Index v = 0; v < cloth.topology().num_vertices; ++v) {
          const double error = std::abs(vis.measure(side, v).sky_visibility - truth[int(side)][v]);
          sum += error;
          worst = std::max(worst, error);
          worst_lifted =
              std::max(worst_lifted, std::abs(lifted.measure(side, v).sky_visibility - truth[int(side)][v]));
          ++count;
        }
      EXPECT_LT(sum / double(count), 0.02) << at.name << " the " << name_of(surface) << ": mean error";
      // Every vertex within 0.02 of the truth, or, on the sphere, no farther from it than the engine's worst
      // on the lifted sheet (the thin gap under the sheet round the contact is the engine's hardest case) and
      // 0.02.
      EXPECT_LT(worst, surface == Surface::Sphere ? worst_lifted + 0.02 : 0.02)
          << at.name << " the " << name_of(surface) << ": worst vertex";
      // Lying on a plane, flat: the front sees the whole sky, the back none of it.
      if (surface != Surface::Sphere)
        for (Index v = 0; v < cloth.topology().num_vertices; ++v) {
          EXPECT_GT(vis.measure(Side::Front, v).sky_visibility, 0.98) << at.name << " " << name_of(surface);
          EXPECT_LT(vis.measure(Side::Back, v).sky_visibility, 0.02) << at.name << " " << name_of(surface);
        }
      EXPECT_EQ(vis.stats.penetrating_vertices, 0u) << at.name << " the " << name_of(surface);
    }
  }
}

TEST(Contact, AGroundPlaneWithItsSolidAboveIsACeiling) {
  // "-z=0.001": the solid above z = 0.001; the sheet just under it and 1 mm into it: its back (-z) sees the
  // sky and its front none, as under a ceiling.
  for (const double lift : {-0.5, 2e-3}) {
    const MeshSequence below = sheet(lift);
    const FrameVisibility vis =
        cones_in(Scene::with_loaded(below, {}, {parse_ground_plane("-z=0.001")}), below);
    for (Index v = 0; v < below.topology().num_vertices; ++v) {
      EXPECT_NEAR(vis.measure(Side::Back, v).sky_visibility, 1.0, 1e-9) << v;
      EXPECT_NEAR(vis.measure(Side::Front, v).sky_visibility, 0.0, 1e-9) << v;
    }
  }
}

TEST(Contact, PenetrationDeeperThanTheToleranceIsCountedNotInverted) {
  // The sheet's mean edge is 0.114: the default tolerance is 0.057. Sunk 0.2 into the ground, the box or the
  // sphere's top (a cap of radius 0.87 around the contact), its vertices are counted and keep the values of
  // a sheet lying on the surface.
  for (const Surface surface : {Surface::Ground, Surface::Box, Surface::Sphere}) {
    const MeshSequence cloth = sheet(-0.2);
    const Scene scene = scene_of(cloth, surface);
    const double tolerance = 0.5 * average_edge_length(cloth.topology(), cloth.frame(0));
    EXPECT_DOUBLE_EQ(scene.topology().contact_tolerance, tolerance);
    const FrameVisibility vis = cones_in(scene, cloth);
    std::size_t expected = 0;
    for (const glm::dvec3& p : cloth.frame(0).positions) {
      const double depth =
          surface == Surface::Sphere ? 2.0 - glm::length(p - glm::dvec3(0.5, 0.5, -2.0)) : 0.2;
      expected += depth > tolerance + 2e-3;  // the icosphere lies up to 2e-3 inside the sphere
    }
    if (surface == Surface::Sphere)
      EXPECT_NEAR(double(vis.stats.penetrating_vertices), double(expected), 8.0) << name_of(surface);
    else
      EXPECT_EQ(vis.stats.penetrating_vertices, expected) << name_of(surface);
    EXPECT_NEAR(vis.stats.deepest_penetration, 0.2, 3e-3) << name_of(surface);
    if (surface == Surface::Sphere) continue;
    for (Index v = 0; v < cloth.topology().num_vertices; ++v) {
      EXPECT_GT(vis.measure(Side::Front, v).sky_visibility, 0.98) << name_of(surface) << " " << v;
      EXPECT_LT(vis.measure(Side::Back, v).sky_visibility, 0.02) << name_of(surface) << " " << v;
    }
  }
  // A tolerance of 0.3 takes the same sheet as resting: nothing is reported.
  const MeshSequence cloth = sheet(-0.2);
  EXPECT_EQ(cones_in(scene_of(cloth, Surface::Box, 0.3), cloth).stats.penetrating_vertices, 0u);
}

TEST(Contact, BehindAnOpenSurfaceFartherThanTheToleranceIsBehindIt) {
  // 0.3 under the ground mesh (tolerance 0.057): the sheet is under a roof, its front sees the mesh's
  // underside (A about 0), its back the open space below.
  const MeshSequence cloth = sheet(-0.3);
  const FrameVisibility vis = cones_in(scene_of(cloth, Surface::GroundMesh), cloth);
  for (Index v = 0; v < cloth.topology().num_vertices; ++v) {
    EXPECT_LT(vis.measure(Side::Front, v).sky_visibility, 0.05) << v;
    EXPECT_GT(vis.measure(Side::Back, v).sky_visibility, 0.95) << v;
  }
}

TEST(Contact, AToleranceThatIsNotAFiniteDistanceIsRefused) {
  const MeshSequence cloth = sheet(0.0);
  for (const double bad : {-1.0, double(NAN), double(INFINITY)})
    EXPECT_THROW(scene_of(cloth, Surface::Box, bad), std::exception) << bad;
}

TEST(Contact, KineticEqualsStaticAsASheetSinksThroughABoxTop) {
  // The sheet moves from 2 mm above the box top to 2 mm into it and back, tilting: every frame of the
  // kinetic engine equals the static recompute.
  std::vector<Frame> frames;
  for (int f = 0; f < 5; ++f) {
    const double lift = 2e-3 * std::cos(f * 1.3), tilt = 1e-3 * std::sin(f * 0.9);
    frames.push_back(sheet(lift, tilt).frame(0));
    frames.back().time = f / 24.0;
  }
  const MeshSequence cloth("sheet", sheet(0.0).topology(), frames);
  const Scene scene = scene_of(cloth, Surface::Box);
  const SlicingPlan plan = make_diffuse_plan(cloth.topology(), cloth.frame(0), {}, &cloth.bounds());
  KineticVisibility kinetic(scene.topology(), plan, scene.frame(0));
  StaticVisibility fresh(scene.topology(), plan);
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const Frame frame = scene.frame(f);
    const FrameVisibility& k = f == 0 ? kinetic.current() : kinetic.advance(frame);
    const FrameVisibility& s = fresh.compute(frame);
    for (const Side side : kBothSides)
      for (Index v = 0; v < cloth.topology().num_vertices; ++v)
        ASSERT_EQ(k.measure(side, v).sky_visibility, s.measure(side, v).sky_visibility) << f << " " << v;
  }
}

/// The bundled drape's frame `f` (its table and the ground y = 0) with the table moved up by `raise`.
FrameVisibility drape_with_table_raised(const MeshSequence& cloth, std::size_t f, double raise,
                                        const std::string& ground = "y=0") {
  const std::string data = std::string(PLEAT_SOURCE_DIR) + "/data/drape/";
  MeshSequence table = load_sequence(data + "drape_colliders.obj", data + "drape_colliders.pc2");
  Frame at = table.frame(f);
  for (glm::dvec3& p : at.positions) p.y += raise;
  const MeshSequence raised("table", table.topology(), {at});
  const Scene scene = Scene::with_loaded(cloth, {{"table", raised}}, {parse_ground_plane(ground)});
  const SlicingPlan plan = make_diffuse_plan(cloth.topology(), cloth.frame(0), {}, &cloth.bounds());
  return compute_visibility(scene.topology(), scene.frame(f), plan);
}

TEST(Contact, TheDrapeWithItsTableRaisedIntoTheClothKeepsItsValues) {
  // Frame 60 of the bundled drape: the cloth lies on the table top (y = 0.75) at the collision distance.
  // Raised to 0.2 mm above the highest cloth vertex on it, the table holds every one of them: their values
  // stay those of the cloth resting on it.
  const std::string data = std::string(PLEAT_SOURCE_DIR) + "/data/drape/";
  const MeshSequence cloth = load_sequence(data + "drape.obj", data + "drape.pc2");
  const std::size_t f = 60;
  const Frame frame = cloth.frame(f);
  std::vector<Index> on_top;
  double highest = 0.0;
  glm::dvec2 axis(0.0);  // the table's, from its vertices
  {
    const std::string colliders = data + "drape_colliders";
    const Frame table = load_sequence(colliders + ".obj", colliders + ".pc2").frame(f);
    for (const glm::dvec3& p : table.positions) axis += glm::dvec2(p.x, p.z) / double(table.positions.size());
  }
  for (Index v = 0; v < cloth.topology().num_vertices; ++v) {
    const glm::dvec3& p = frame.positions[v];
    if (p.y > 0.745 && p.y < 0.8 && glm::distance(glm::dvec2(p.x, p.z), axis) < 0.48) {
      on_top.push_back(v);
      highest = std::max(highest, p.y);
    }
  }
  ASSERT_GT(on_top.size(), 200u);
  const FrameVisibility resting = drape_with_table_raised(cloth, f, 0.0);
  const FrameVisibility raised = drape_with_table_raised(cloth, f, highest + 2e-4 - 0.75);
  double worst = 0.0;
  for (const Index v : on_top)
    for (const Side side : kBothSides)
      worst = std::max(
          worst, std::abs(raised.measure(side, v).sky_visibility - resting.measure(side, v).sky_visibility));
  EXPECT_LT(worst, 0.02);
  EXPECT_EQ(resting.stats.penetrating_vertices, 0u);
  // The ground 0.5 mm above the drape's lowest vertices: they lie under it, and keep their values.
  double lowest = 1e300;
  for (const glm::dvec3& p : frame.positions) lowest = std::min(lowest, p.y);
  const FrameVisibility flooded =
      drape_with_table_raised(cloth, f, 0.0, "y=" + std::to_string(lowest + 5e-4));
  double ground_worst = 0.0;
  for (Index v = 0; v < cloth.topology().num_vertices; ++v)
    if (frame.positions[v].y < lowest + 5e-4)
      for (const Side side : kBothSides)
        ground_worst = std::max(ground_worst, std::abs(flooded.measure(side, v).sky_visibility -
                                                       resting.measure(side, v).sky_visibility));
  EXPECT_LT(ground_worst, 0.02);
}

/// A flat 11 x 11 sheet at y = 0 over [0, 1] x [-1, 0] (front +y) and a closed box [-1, 2] x [-1, top] x
/// [-2, 2] under it, as OBJs.
void write_sheet_and_box(const test::TempDir& dir, double top) {
  test::TestMesh mesh = test::flat_sheet(11, 11, 0.1);
  for (glm::dvec3& p : mesh.frame.positions) p = {p.x, 0.0, -p.y};  // in y = 0, front up (+y)
  write_obj(dir / "sheet.obj", mesh.topology, mesh.frame.positions);
  const test::TestMesh box = test::closed_box({-1, -1, -2}, {2, top, 2});
  write_obj(dir / "box.obj", box.topology, box.frame.positions);
}

/// The CSV's (front, back) per row.
std::vector<std::array<double, 2>> read_values(const std::filesystem::path& csv) {
  std::istringstream in(test::slurp(csv));
  std::string line;
  std::getline(in, line);
  std::vector<std::array<double, 2>> values;
  while (std::getline(in, line)) {
    std::array<double, 2> ab{};
    std::sscanf(line.c_str(), "%*d,%*d,%lf,%lf", &ab[0], &ab[1]);
    values.push_back(ab);
  }
  return values;
}

TEST(Contact, TheCommandLineNeverInvertsASheetOnTheGroundOrABox) {
  // The cases as a user meets them: a sheet 1 mm under the ground, 1 mm above, into and at a box's top.
  test::TempDir dir;
  const std::string sheet = (dir / "sheet.obj").string(), out = (dir / "a.csv").string();
  for (const double top : {-1e-3, 1e-3, 0.0}) {
    write_sheet_and_box(dir, top);
    for (const std::string scene :
         {"--ground y=" + std::to_string(-top), "--occluder " + (dir / "box.obj").string()}) {
      const test::CommandResult r =
          test::run_pleat("visibility " + sheet + " " + scene + " -o " + out + " -q");
      ASSERT_EQ(r.exit_code, 0) << r.output;
      for (const auto& [front, back] : read_values(out)) {
        EXPECT_GT(front, 0.98) << scene << " top " << top;
        EXPECT_LT(back, 0.02) << scene << " top " << top;
      }
    }
  }
}

TEST(Contact, SunkVerticesAreReportedAndTheToleranceIsAnOption) {
  test::TempDir dir;
  write_sheet_and_box(dir, 0.3);  // the sheet 0.3 inside the box: deeper than the default tolerance (0.057)
  const std::string base = "visibility " + (dir / "sheet.obj").string() + " --occluder " +
                           (dir / "box.obj").string() + " -o " + (dir / "a.csv").string() + " --stats " +
                           (dir / "s.json").string();
  test::CommandResult r = test::run_pleat(base);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("warning: cloth lies deeper than the contact tolerance"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("first: frame 0, 121 vertices"), std::string::npos) << r.output;
  const auto stats = nlohmann::json::parse(test::slurp(dir / "s.json"));
  EXPECT_EQ(stats["frames"][0]["penetrating_vertices"], 121);
  EXPECT_NEAR(stats["frames"][0]["deepest_penetration"].get<double>(), 0.3, 1e-9);
  for (const auto& [front, back] : read_values(dir / "a.csv")) {  // taken as lying on the top
    EXPECT_GT(front, 0.98);
    EXPECT_LT(back, 0.02);
  }
  // A tolerance beyond the depth: no warning, nothing counted.
  r = test::run_pleat(base + " --contact-tolerance 0.5");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("warning"), std::string::npos) << r.output;
  EXPECT_EQ(nlohmann::json::parse(test::slurp(dir / "s.json"))["frames"][0]["penetrating_vertices"], 0);
  // Not a distance: refused naming the option.
  for (const std::string bad : {"-1", "nan", "inf"}) {
    r = test::run_pleat(base + " --contact-tolerance " + bad);
    EXPECT_EQ(r.exit_code, 2) << bad << r.output;
    EXPECT_NE(r.output.find("--contact-tolerance"), std::string::npos) << r.output;
  }
}

}  // namespace
}  // namespace pleat
