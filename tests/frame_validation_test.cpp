// Every engine entry validates the cloth it is given (static_core/mesh_validation.hpp): a frame with too few
// or too many positions, a NaN or an infinite coordinate, and a triangle naming a vertex out of range each
// throw InputError naming the entry, the place (frame and vertex, or triangle) and the problem, before any
// position is read. A valid frame still gives the same result, also right after a rejected one.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "kinetic/kinetic_visibility.hpp"
#include "oracles/test_meshes.hpp"
#include "shading/path_trace.hpp"
#include "shading/render.hpp"
#include "shading/shade.hpp"
#include "static_core/adaptive_plan.hpp"
#include "static_core/mesh_validation.hpp"
#include "static_core/slicing_plan.hpp"
#include "static_core/visibility.hpp"
#include "support/input_error.hpp"
#include "test_support.hpp"

namespace pleat {
namespace {

using Mesh = test::TestMesh;

/// A V-fold (cones of every kind: open, blocked, partly blocked), at time 0.5.
Mesh fold() {
  Mesh m = test::v_fold(0.5, 6, 5, 2.0, 1.0);
  m.frame.time = 0.5;
  return m;
}

/// The same fold turned a little and moved: the next frame of a sequence.
Frame next_frame(const Mesh& m) {
  Mesh next = m;
  test::rigid_transform(next, {0.3, 1.0, 0.2}, 0.05, {0.01, 0.0, -0.02});
  next.frame.time = 0.75;
  return next.frame;
}

/// One way to spoil the input, and what the error must say.
struct BadInput {
  std::string name;
  bool spoils_topology = false;  ///< the triangle case; the others spoil the frame
  std::function<void(MeshTopology&, Frame&)> spoil;
  std::string place;  ///< InputError::place()
  std::string words;  ///< must occur in what()
};

std::vector<BadInput> bad_inputs(const Mesh& good) {
  const Index n = good.topology.num_vertices;
  const std::string at = "frame at t=0.5";
  return {
      {"too few positions", false,
       [](MeshTopology&, Frame& f) { f.positions.resize(f.positions.size() / 2); }, at,
       "too few positions: " + std::to_string(n / 2) + " for " + std::to_string(n) + " vertices"},
      {"too many positions", false, [](MeshTopology&, Frame& f) { f.positions.push_back(glm::dvec3(0.0)); },
       at, "too many positions: " + std::to_string(n + 1) + " for " + std::to_string(n) + " vertices"},
      {"a NaN", false, [](MeshTopology&, Frame& f) { f.positions[5].y = std::nan(""); }, at + ", vertex 5",
       "non-finite position ("},
      {"an inf", false,
       [](MeshTopology&, Frame& f) { f.positions[7].z = -std::numeric_limits<double>::infinity(); },
       at + ", vertex 7", "non-finite position ("},
      {"a triangle index out of range", true, [n](MeshTopology& t, Frame&) { t.triangles[3][1] = n + 4; },
       "triangle 3",
       "vertex index " + std::to_string(n + 4) + " out of range (" + std::to_string(n) + " vertices)"},
  };
}

/// Runs `entry` on each bad input it can be given (frame cases if it takes a frame, the triangle case if
/// it takes a topology) and checks the error; then once on the good input, which must not throw.
void expect_validates(const std::string& who, bool takes_topology, bool takes_frame,
                      const std::function<void(const MeshTopology&, const Frame&)>& entry) {
  const Mesh good = fold();
  int checked = 0;
  for (const BadInput& bad : bad_inputs(good)) {
    if (bad.spoils_topology ? !takes_topology : !takes_frame) continue;
    SCOPED_TRACE(who + ", " + bad.name);
    MeshTopology topology = good.topology;
    Frame frame = good.frame;
    bad.spoil(topology, frame);
    try {
      entry(topology, frame);
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), who);
      EXPECT_EQ(e.place(), bad.place);
      EXPECT_NE(std::string(e.what()).find(bad.words), std::string::npos) << e.what();
      const char* value = bad.name == "a NaN" ? "nan" : bad.name == "an inf" ? "-inf" : "";
      EXPECT_NE(std::string(e.what()).find(value), std::string::npos) << e.what();
    }
    ++checked;
  }
  EXPECT_EQ(checked, (takes_topology ? 1 : 0) + (takes_frame ? 4 : 0));
  EXPECT_NO_THROW(entry(good.topology, good.frame)) << who;
}

void expect_same(const FrameVisibility& a, const FrameVisibility& b, double tolerance) {
  for (int s = 0; s < 2; ++s) {
    ASSERT_EQ(a.measures[s].size(), b.measures[s].size());
    for (std::size_t v = 0; v < a.measures[s].size(); ++v)
      EXPECT_NEAR(a.measures[s][v].sky_visibility, b.measures[s][v].sky_visibility, tolerance)
          << "side " << s << " vertex " << v;
  }
}

TEST(MeshValidation, MessagesNameTheEntryThePlaceAndTheProblem) {
  const Mesh good = fold();
  const Index n = good.topology.num_vertices;
  Frame frame = good.frame;
  frame.positions.pop_back();
  try {
    validate_frame(good.topology, frame, "compute_visibility");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "compute_visibility:frame at t=0.5: too few positions: " +
                                         std::to_string(n - 1) + " for " + std::to_string(n) + " vertices");
  }
  frame = good.frame;
  frame.positions[2] = {1.0, std::numeric_limits<double>::infinity(), 0.25};
  try {
    validate_frame(good.topology, frame, "KineticVisibility::advance");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "KineticVisibility::advance:frame at t=0.5, vertex 2: non-finite position (1, inf, 0.25)");
  }
  MeshTopology topology = good.topology;
  topology.triangles.back()[2] = n;
  try {
    validate_topology(topology, "StaticVisibility");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "StaticVisibility:triangle " +
                                         std::to_string(topology.triangles.size() - 1) + ": vertex index " +
                                         std::to_string(n) + " out of range (" + std::to_string(n) +
                                         " vertices)");
  }
  // The first offender is named; an empty cloth is valid.
  frame = good.frame;
  frame.positions[9].x = std::nan("");
  frame.positions[4].z = std::nan("");
  try {
    validate_frame(good.topology, frame, "x");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.place(), "frame at t=0.5, vertex 4");
  }
  EXPECT_NO_THROW(validate_mesh(MeshTopology{}, Frame{}, "x"));
  EXPECT_NO_THROW(validate_mesh(good.topology, good.frame, "x"));
}

// ---- static_core ------------------------------------------------------------------------------------

TEST(FrameValidation, ComputeVisibility) {
  const Mesh good = fold();
  const SlicingPlan plan = make_diffuse_plan(good.topology, good.frame, {});
  expect_validates("compute_visibility", true, true,
                   [&](const MeshTopology& t, const Frame& f) { compute_visibility(t, f, plan, {false}); });
  FrameVisibility reused;
  expect_validates("compute_visibility", true, true, [&](const MeshTopology& t, const Frame& f) {
    compute_visibility(t, f, plan, {false}, reused);
  });
}

TEST(FrameValidation, StaticVisibilityConstructorAndCompute) {
  const Mesh good = fold();
  const SlicingPlan plan = make_diffuse_plan(good.topology, good.frame, {});
  expect_validates("StaticVisibility", true, false,
                   [&](const MeshTopology& t, const Frame&) { StaticVisibility engine(t, plan, {false}); });
  StaticVisibility engine(good.topology, plan, {false});
  expect_validates("StaticVisibility::compute", false, true,
                   [&](const MeshTopology&, const Frame& f) { engine.compute(f); });
  // After the rejected frames the engine still computes a full frame.
  const Frame next = next_frame(good);
  expect_same(engine.compute(next), compute_visibility(good.topology, next, plan, {false}), 0.0);
}

TEST(FrameValidation, SlicingPlansNormalsAndEdgeLength) {
  expect_validates("make_diffuse_plan", true, true,
                   [](const MeshTopology& t, const Frame& f) { make_diffuse_plan(t, f, {}); });
  // Every vertex allowed to miss a cone: no planes, only the validation (with the default 5%, the median
  // split does not terminate on this fold: a known issue outside this test's subject).
  expect_validates("make_adaptive_plan", true, true, [](const MeshTopology& t, const Frame& f) {
    make_adaptive_plan(t, f, {6, 1.0});
  });
  expect_validates("make_point_light_plan", true, true, [](const MeshTopology& t, const Frame& f) {
    make_point_light_plan(t, f, {0.0, 0.0, 3.0});
  });
  expect_validates("make_area_light_plan", true, true, [](const MeshTopology& t, const Frame& f) {
    make_area_light_plan(t, f, {{-1.0, -1.0, 3.0}, {1.0, -1.0, 3.0}, {1.0, 1.0, 3.0}, {-1.0, 1.0, 3.0}});
  });
  expect_validates("vertex_normals", true, true,
                   [](const MeshTopology& t, const Frame& f) { vertex_normals(t, f); });
  expect_validates("average_edge_length", true, true,
                   [](const MeshTopology& t, const Frame& f) { average_edge_length(t, f); });
}

// ---- kinetic ----------------------------------------------------------------------------------------

TEST(FrameValidation, KineticVisibilityConstructorAndAdvance) {
  const Mesh good = fold();
  const SlicingPlan plan = make_diffuse_plan(good.topology, good.frame, {});
  KineticParams params;
  params.parallel = false;
  params.check_invariants = true;
  expect_validates("KineticVisibility", true, true, [&](const MeshTopology& t, const Frame& f) {
    KineticVisibility engine(t, plan, f, params);
  });
  KineticVisibility engine(good.topology, plan, good.frame, params);
  // A rejected frame leaves the engine at its last frame; the good frame of expect_validates is that frame.
  expect_validates("KineticVisibility::advance", false, true,
                   [&](const MeshTopology&, const Frame& f) { engine.advance(f); });
  const Frame next = next_frame(good);
  expect_same(engine.advance(next), compute_visibility(good.topology, next, plan, {false}), 1e-9);
}

// ---- shading and rendering --------------------------------------------------------------------------

TEST(FrameValidation, ShadeFrame) {
  const Mesh good = fold();
  const FrameVisibility visibility = compute_visibility(
      good.topology, good.frame, make_diffuse_plan(good.topology, good.frame, {}), {false});
  Lighting lighting;
  add_light_spec(lighting, "sky:1");
  add_light_spec(lighting, "point:0,0.5,2,I=3");
  // Shading reads no triangle: only the frame is checked (the triangle case is not run).
  expect_validates("shade_frame", false, true,
                   [&](const MeshTopology& t, const Frame& f) { shade_frame(t, f, visibility, lighting); });
  ShadedFrame reused;
  expect_validates("shade_frame", false, true, [&](const MeshTopology& t, const Frame& f) {
    shade_frame(t, f, visibility, lighting, {}, reused);
  });
}

TEST(FrameValidation, RenderEntries) {
  const Mesh good = fold();
  const std::vector<glm::vec3> colours(good.topology.num_vertices, glm::vec3(0.5f));
  const Camera camera = auto_frame(good.frame);
  expect_validates("render_image", true, true, [&](const MeshTopology& t, const Frame& f) {
    render_image(t, f, colours, colours, camera, 16, 12);
  });
  const EmbreeScene scene(good.topology, good.frame);
  expect_validates("render_image", false, true, [&](const MeshTopology&, const Frame& f) {
    render_image(scene, f, colours, colours, camera, 16, 12);
  });
  const test::TempDir dir;
  expect_validates("render_image", true, true, [&](const MeshTopology& t, const Frame& f) {
    render_png(dir / "fold.png", t, f, colours, colours, camera, 16, 12);
  });
  expect_validates("render_turntable", true, true, [&](const MeshTopology& t, const Frame& f) {
    render_turntable(dir.path(), "fold", t, f, colours, colours, camera, 2, 16, 12);
  });
}

TEST(FrameValidation, PathTrace) {
  const Mesh good = fold();
  EmbreeScene scene(good.topology, good.frame);
  const std::vector<glm::dvec3> normals = vertex_normals(good.topology, good.frame);
  Lighting lighting;
  add_light_spec(lighting, "sky:1");
  PathTraceParams params;
  params.paths_per_vertex = 4;
  expect_validates("path_trace_vertices", true, true, [&](const MeshTopology& t, const Frame& f) {
    path_trace_vertices(scene, t, f, normals, lighting, params);
  });
}

}  // namespace
}  // namespace pleat
