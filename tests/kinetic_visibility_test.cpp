// The kinetic engine against a full static recompute at every frame (docs/method.md §11): per slice the
// same hull, windows, shortest-path-tree parents and, in regions with holes, sights through sleeves (compared
// as multisets keyed by mesh edges, so numbering does not matter) and the same 2D cones; per vertex the same
// 3D cones and measures to 1e-9. On random coherent motions (every generated kind, random parameters, smooth
// perturbations, random frame steps, planes through vertices at frame times) and on stress cases: a flat
// sheet, a fold closing and reopening, a vertex on a plane at a frame time, events exactly at t = 1,
// simultaneous events; then 1000 frames.
#include "kinetic/kinetic_visibility.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <numeric>
#include <sstream>
#include <tuple>

#include "kinetic/internal/kinetic_inspect.hpp"
#include "kinetic/internal/kinetic_slice.hpp"
#include "oracles/funnel_walk_oracle.hpp"
#include "oracles/test_meshes.hpp"
#include "sim_io/cloth_generators.hpp"
#include "static_core/internal/shortest_path_tree.hpp"
#include "static_core/visibility.hpp"

namespace pleat {
namespace {

constexpr double kTolerance = 1e-9;

/// A slice's structure in terms of mesh edges (slice vertices are numbered per frame, corners per build).
struct SliceSignature {
  std::vector<Index> hull;                                           // mesh edges of hull vertices
  std::vector<std::pair<Index, Index>> windows;                      // (edge at a, edge at b)
  std::vector<std::tuple<Index, Index, int, Index, Index>> parents;  // (window, from_b, corner, parent)
  // regions with holes: (window, corner, first vertices of its paths to a and b) per sleeve it sees through
  std::vector<std::tuple<Index, Index, Index, Index, Index>> sights;
  std::vector<std::tuple<Index, int, std::vector<Wedge>>> cones;  // (edge, side, wedges)
  std::size_t trees_unlike_the_walk =
      0;  // trees that differ from the walk oracle's on the same triangulation
};

SliceSignature signature(const Slice& slice, const SliceTriangulation& st, const SliceCones& cones) {
  SliceSignature s;
  auto edge_of = [&](cgal::VertexHandle v) { return slice.vertices[v->info().slice_vertex].edge; };
  for (Index x = 0; x < slice.vertices.size(); ++x)
    for (Side side : kBothSides) {
      const auto c = cones.cone(x, side);
      s.cones.emplace_back(slice.vertices[x].edge, int(side), std::vector<Wedge>(c.begin(), c.end()));
    }
  std::sort(s.cones.begin(), s.cones.end(), [](const auto& a, const auto& b) {
    return std::tie(std::get<0>(a), std::get<1>(a)) < std::tie(std::get<0>(b), std::get<1>(b));
  });
  if (st.dimension() < 2) return s;
  const cgal::Cdt& cdt = st.cdt();
  auto vc = cdt.incident_vertices(cdt.infinite_vertex()), done = vc;
  do s.hull.push_back(edge_of(vc));
  while (++vc != done);
  std::sort(s.hull.begin(), s.hull.end());
  std::vector<int> parent(st.num_corners(), -1), walked(st.num_corners(), -1);
  FunnelScratch funnel;
  SleeveScratch sleeves;
  std::vector<SleeveSight> sights;
  for (std::size_t r = 0; r < st.num_regions(); ++r) {
    const SliceRegion region = st.region(r);
    for (const SliceWindow& w : region.windows) {
      const auto key =
          std::make_pair(edge_of(st.corner_vertex(w.corner_a)), edge_of(st.corner_vertex(w.corner_b)));
      s.windows.push_back(key);
      if (region.has_holes) {
        sights.clear();
        see_window_through_sleeves(st, w, region.faces.size(), sleeves, sights);
        for (const SleeveSight& sight : sights)
          s.sights.emplace_back(key.first, key.second, edge_of(st.corner_vertex(sight.corner)),
                                edge_of(st.corner_vertex(sight.from_a)),
                                edge_of(st.corner_vertex(sight.from_b)));
        continue;
      }
      for (int from_b = 0; from_b < 2; ++from_b) {
        std::fill(parent.begin(), parent.end(), -1);
        grow_shortest_path_tree(st, w, from_b, parent, funnel);
        std::fill(walked.begin(), walked.end(), -1);
        test::walk_shortest_path_tree(st, w, from_b, walked);
        s.trees_unlike_the_walk += walked != parent;
        for (std::size_t c = 0; c < parent.size(); ++c)
          if (parent[c] >= 0)
            s.parents.emplace_back(key.first, key.second, from_b, edge_of(st.corner_vertex(int(c))),
                                   edge_of(st.corner_vertex(parent[c])));
      }
    }
  }
  std::sort(s.windows.begin(), s.windows.end());
  std::sort(s.parents.begin(), s.parents.end());
  std::sort(s.sights.begin(), s.sights.end());
  return s;
}

/// Empty when kinetic slice p equals the static build of the same plane and frame; else the first difference.
std::string compare_slice(const KineticVisibility& kinetic, std::size_t p, const MeshTopology& topology,
                          const MeshConnectivity& connectivity, const Frame& frame) {
  const SlicingPlane& plane = kinetic.plan().planes[p];
  std::vector<Index> all(topology.triangles.size());
  std::iota(all.begin(), all.end(), Index(0));
  PlaneCones fresh;
  SlicerScratch slicer;
  slice_mesh(topology, connectivity, frame, plane, all, slicer, fresh.slice);
  SliceTriangulation st;
  st.build(fresh.slice);
  PlaneConeScratch scratch;
  FrameMarks marks;
  mark_frame(topology, connectivity, frame, marks);
  if (offer_plane_cones(topology.num_receivers(), kinetic.plan().storage, frame, marks.whole_fans, scratch,
                        fresh))
    compute_plane_cones(st, 0.0, scratch, fresh);
  const Slice& slice = fresh.slice;
  const SliceCones& cones = fresh.cones;
  const kinetic::KineticSlice& ks = kinetic::KineticInspect::slice(kinetic, p);
  const SliceSignature a = signature(slice, st, cones);
  SliceTriangulation kept;
  ks.rederive_triangulation(kept);
  const SliceSignature b = signature(ks.cones().slice, kept, ks.cones().cones);
  std::string why;
  if (!ks.check_invariants(&why)) return "invariants: " + why;
  if (a.trees_unlike_the_walk + b.trees_unlike_the_walk > 0) return "funnel trees unlike the walk oracle's";
  if (a.hull != b.hull) return "hull";
  if (a.windows != b.windows) return "windows";
  if (a.parents != b.parents) return "shortest-path parents";
  if (a.sights != b.sights) return "sights through sleeves in regions with holes";
  if (a.cones.size() != b.cones.size()) return "slice vertices";
  for (std::size_t i = 0; i < a.cones.size(); ++i) {
    const auto& [ea, sa, wa] = a.cones[i];
    const auto& [eb, sb, wb] = b.cones[i];
    if (ea != eb || sa != sb || wa.size() != wb.size()) return "2D cone of edge " + std::to_string(ea);
    for (std::size_t k = 0; k < wa.size(); ++k)
      if (std::abs(wa[k].start - wb[k].start) > kTolerance ||
          std::abs(wa[k].width - wb[k].width) > kTolerance)
        return "2D cone wedge of edge " + std::to_string(ea);
  }
  return {};
}

/// Empty when the frames' 3D cones and measures agree to 1e-9.
std::string compare_frames(const FrameVisibility& k, const FrameVisibility& s) {
  for (int side = 0; side < 2; ++side)
    for (std::size_t v = 0; v < s.measures[side].size(); ++v) {
      std::ostringstream at;
      at << "side " << side << " vertex " << v << ": ";
      if (std::abs(k.measures[side][v].sky_visibility - s.measures[side][v].sky_visibility) > kTolerance)
        return at.str() + "A " + std::to_string(k.measures[side][v].sky_visibility) + " vs " +
               std::to_string(s.measures[side][v].sky_visibility);
      const auto& pk = k.cones[side][v].pieces;
      const auto& ps = s.cones[side][v].pieces;
      if (pk.size() != ps.size()) return at.str() + "number of pieces";
      for (std::size_t i = 0; i < pk.size(); ++i) {
        if (pk[i].size() != ps[i].size()) return at.str() + "piece size";
        for (std::size_t j = 0; j < pk[i].size(); ++j)
          if (glm::length(pk[i][j] - ps[i][j]) > kTolerance) return at.str() + "piece direction";
      }
    }
  return {};
}

/// Runs the kinetic engine over `frames` and compares it with the static engine at every frame (and every
/// slice when `slices`). Returns the first difference; accumulates the kinetic counters into `total`.
std::string run_and_compare(const MeshTopology& topology, const std::vector<Frame>& frames,
                            const SlicingPlan& plan, bool slices, KineticFrameStats* total = nullptr,
                            const KineticParams& params = {false, {}, true}) {
  KineticVisibility kinetic(topology, plan, frames[0], params);
  StaticVisibility reference(topology, plan, {false});
  const MeshConnectivity connectivity(topology);
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const FrameVisibility& k = f == 0 ? kinetic.current() : kinetic.advance(frames[f]);
    if (std::string why = compare_frames(k, reference.compute(frames[f])); !why.empty())
      return "frame " + std::to_string(f) + ": " + why;
    if (slices)
      for (std::size_t p = 0; p < plan.planes.size(); ++p)
        if (std::string why = compare_slice(kinetic, p, topology, connectivity, frames[f]); !why.empty())
          return "frame " + std::to_string(f) + " plane " + std::to_string(p) + ": " + why;
    if (total && f > 0) *total += kinetic.last_stats();
  }
  return {};
}

/// A plan of a few orientations plus planes exactly through chosen vertices at chosen frames.
SlicingPlan plan_for(const MeshTopology& topology, const std::vector<Frame>& frames,
                     int planes_per_orientation, const std::vector<std::pair<std::size_t, Index>>& through) {
  SlicingPlan plan = make_diffuse_plan(topology, frames[0], {6, 0.0, planes_per_orientation});
  for (std::size_t i = 0; i < through.size(); ++i) {
    const int o = static_cast<int>(i % plan.orientations.size());
    const glm::dvec3 n = plan.orientations[o];
    const glm::dvec3& p = frames[through[i].first].positions[through[i].second];
    plan.planes.push_back(make_plane(n, glm::dot(n, p), o));
  }
  return plan;
}

RC_GTEST_PROP(KineticVisibility, EqualsAFullRecomputeAtEveryFrameOnRandomCoherentMotions, ()) {
  const auto kind =
      *rc::gen::element(ClothKind::Curtain, ClothKind::Roll, ClothKind::Flag, ClothKind::Sleeve);
  const int resolution = *rc::gen::inRange(6, 14);
  const int step = *rc::gen::inRange(1, 4);
  const int count = *rc::gen::inRange(8, 20);
  const std::uint64_t seed = *rc::gen::inRange<std::uint64_t>(1, 1000000);
  const double amplitude = *rc::gen::element(0.0, 0.002, 0.01, 0.03);
  const double k = *rc::gen::inRange(1, 8) * 1.0;
  const ClothGenerator cloth(kind, {resolution, count * step, 24.0, seed});
  std::vector<Frame> frames;
  for (int f = 0; f < count * step; f += step) {
    Frame frame = cloth.frame(f);
    for (glm::dvec3& p : frame.positions)  // a smooth travelling perturbation
      p += amplitude *
           glm::dvec3(std::sin(k * p.y + 0.7 * f), std::sin(k * p.z + 1.3 * f), std::sin(k * p.x + 0.4 * f));
    frames.push_back(std::move(frame));
  }
  // Held frames: a frame repeated as it is (a cloth at rest for a while), with its time moving on.
  const int holds = *rc::gen::inRange(0, 3);
  for (int h = 0; h < holds; ++h) {
    const std::size_t at = *rc::gen::inRange<std::size_t>(0, frames.size());
    Frame held = frames[at];
    frames.insert(frames.begin() + std::ptrdiff_t(at) + 1, held);
    for (std::size_t f = 0; f < frames.size(); ++f) frames[f].time = double(f) / 24.0;
  }
  std::vector<std::pair<std::size_t, Index>> through;
  const int extra = *rc::gen::inRange(0, 4);
  through.reserve(std::size_t(extra));
  for (int i = 0; i < extra; ++i)
    through.emplace_back(*rc::gen::inRange<std::size_t>(0, frames.size()),
                         *rc::gen::inRange<Index>(0, cloth.topology().num_vertices));
  const SlicingPlan plan = plan_for(cloth.topology(), frames, *rc::gen::inRange(2, 7), through);
  // The default policy, and one that repairs far more (so every repair path runs often).
  const bool repair_everything = *rc::gen::arbitrary<bool>();
  KineticParams params{false, {}, true};
  if (repair_everything) params.policy = {1.0, 8, false};
  const std::string why = run_and_compare(cloth.topology(), frames, plan, true, nullptr, params);
  if (!why.empty()) RC_FAIL(why);
}

/// The property above must exercise the kinetic paths, not only compare the static engine with itself:
/// coherent motions of every kind, with a policy that repairs far more than the default, give failed
/// certificates repaired by putting vertices back and by edge flips, regular and critical crossings, fan
/// swaps (relabeled slice vertices) beside plain removals and insertions, and more slices repaired than
/// rebuilt (and equal a recompute).
TEST(KineticVisibility, CoherentMotionsExerciseEveryRepair) {
  KineticFrameStats totals;
  for (ClothKind kind : {ClothKind::Curtain, ClothKind::Roll, ClothKind::Flag, ClothKind::Sleeve}) {
    const ClothGenerator cloth(kind, {12, 48, 24.0, 5});
    std::vector<Frame> frames;
    for (std::size_t f = 0; f < 12; ++f) frames.push_back(cloth.frame(f));
    const SlicingPlan plan = plan_for(cloth.topology(), frames, 5, {{3, 40}});
    EXPECT_EQ(run_and_compare(cloth.topology(), frames, plan, true, &totals, {false, {1.0, 8, false}, true}),
              "");
  }
  for (const KineticCounter& c : kKineticCounters) std::cout << c.name << ' ' << totals.*c.field << '\n';
  EXPECT_GT(totals.certificates_failed, 0u);
  EXPECT_GT(totals.reinserted, 0u);
  EXPECT_GT(totals.flipped, 0u);
  EXPECT_GT(totals.relabeled, 0u);
  EXPECT_GT(totals.removed, 0u);
  EXPECT_GT(totals.inserted, 0u);
  EXPECT_GT(totals.side_changes_regular, 0u);
  EXPECT_GT(totals.side_changes_critical, 0u);
  EXPECT_GT(totals.slices_unchanged, 0u);
  EXPECT_GT(totals.slices_repaired, totals.slices_rebuilt);
}

/// The policy tests' motion: the generated flag's first `count` frames, five planes per orientation and one
/// through a vertex.
struct FlagRun {
  ClothGenerator cloth{ClothKind::Flag, {12, 48, 24.0, 5}};
  std::vector<Frame> frames;
  SlicingPlan plan;
  explicit FlagRun(std::size_t count) {
    for (std::size_t f = 0; f < count; ++f) frames.push_back(cloth.frame(f));
    plan = plan_for(cloth.topology(), frames, 5, {{3, 40}});
  }
};

/// A slice the policy rebuilds is rebuilt outright for the next retry_interval - 1 intervals: no certificate
/// is checked and nothing is put back for it then, and the output still equals a recompute.
TEST(KineticVisibility, PolicyRebuildsAreNotRetriedEveryInterval) {
  const FlagRun flag(12);
  auto run = [&](int retry_interval) {
    KineticFrameStats totals;
    // A tight budget: many policy rebuilds (by the edit count alone, not the measured cost: deterministic).
    const KineticParams params{false, {0.05, retry_interval, false, 0}, true};
    EXPECT_EQ(run_and_compare(flag.cloth.topology(), flag.frames, flag.plan, true, &totals, params), "");
    return totals;
  };
  const KineticFrameStats every = run(1), eighth = run(8);
  const auto policy = static_cast<std::size_t>(kinetic::RebuildReason::policy);
  ASSERT_GT(every.rebuilt_because[policy], 0u);
  ASSERT_GT(eighth.rebuilt_because[policy], 0u);
  EXPECT_LT(eighth.certificates, every.certificates);
}

/// A slice whose attempt after a run of policy rebuilds fails again starts a run twice as long (up to the
/// policy's doublings), so over many frames of motion too fast to repair it is attempted less often: fewer
/// certificates checked, as many slices rebuilt, and the output still equals a recompute.
TEST(KineticVisibility, FailedRetriesBackOff) {
  const FlagRun flag(36);
  auto run = [&](int doublings) {
    KineticFrameStats totals;
    // A tight budget and a short retry interval (by the edit count alone: deterministic).
    const KineticParams params{false, {0.05, 2, false, doublings}, true};
    EXPECT_EQ(run_and_compare(flag.cloth.topology(), flag.frames, flag.plan, true, &totals, params), "");
    return totals;
  };
  const KineticFrameStats fixed = run(0), backoff = run(3);
  const auto policy = static_cast<std::size_t>(kinetic::RebuildReason::policy);
  ASSERT_GT(fixed.rebuilt_because[policy], 0u);
  EXPECT_GE(backoff.rebuilt_because[policy], fixed.rebuilt_because[policy]);
  EXPECT_LT(backoff.certificates, fixed.certificates);
}

/// The measured policy (the default) rebuilds slices whose carrying has cost more than their rebuilding, then
/// rebuilds them outright, keeping nothing, until the retry interval: its choices follow the timings, the
/// output still equals a recompute at every frame. On these small slices carrying rarely pays, so slices are
/// rebuilt for their cost: one by one, or the whole interval's by the engine.
TEST(KineticVisibility, MeasuredCostRebuildsKeepTheOutput) {
  const FlagRun flag(24);
  KineticFrameStats totals;
  EXPECT_EQ(run_and_compare(flag.cloth.topology(), flag.frames, flag.plan, true, &totals, {false, {}, true}),
            "");
  EXPECT_GT(totals.rebuilt_because[static_cast<std::size_t>(kinetic::RebuildReason::cost)] +
                totals.rebuilt_because[static_cast<std::size_t>(kinetic::RebuildReason::frame_cost)],
            0u);
  EXPECT_GT(totals.slices_repaired + totals.slices_unchanged, 0u);
}

// The certificate that a kept triangulation is valid at the frame needs the hull's winding: a hexagon's
// triangulation whose points are moved so that its hull goes twice around a triangle keeps every triangle
// positive and every hull corner convex, and only the winding check rejects it.
TEST(KineticVisibility, HullWoundTwiceIsCaught) {
  cgal::Cdt cdt;
  std::vector<cgal::VertexHandle> hull;
  for (int i = 0; i < 6; ++i) {
    const double a = 2.0 * M_PI * i / 6.0;
    hull.push_back(cdt.insert(cgal::Point2(std::cos(a), std::sin(a))));
  }
  const cgal::VertexHandle centre = cdt.insert(cgal::Point2(0.0, 0.0));
  ASSERT_EQ(cdt.degree(centre), 6u);  // a fan of six triangles around the centre
  EXPECT_TRUE(kinetic::hull_winds_once(cdt));
  // Each hull vertex at twice its angle (slightly shrunk so no two coincide): the fan wraps twice.
  for (int i = 0; i < 6; ++i) {
    const double a = 2.0 * 2.0 * M_PI * i / 6.0, r = i < 3 ? 1.0 : 0.9;
    hull[i]->set_point(cgal::Point2(r * std::cos(a), r * std::sin(a)));
  }
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
    ASSERT_EQ(CGAL::orientation(f->vertex(0)->point(), f->vertex(1)->point(), f->vertex(2)->point()),
              CGAL::LEFT_TURN);
  EXPECT_FALSE(kinetic::hull_winds_once(cdt));
}

/// A failed triangle is repaired by a flip that joins two vertices joined already. One chain
/// P -> W -> q -> A -> Z, with q inside the triangle (A, P, W): q has degree 3 (faces (A, P, q), (P, W, q),
/// (W, A, q)), and (A, W, Z), (A, Z, P) lie beyond. At the next frame q lies below A, so (A, P, q) and
/// (W, A, q) fail. Flipping P q (with (P, W, q)) makes (A, P, W) and (A, W, q), positive, but joins A and W a
/// second time; flipping W A of the other (with (A, W, Z)) makes (q, W, Z) and (q, Z, A), positive, and takes
/// the old edge away. Made one after the other, in either order, the two flips leave a valid triangulation:
/// nothing is put back.
TEST(KineticVisibility, FlipsMayJoinVerticesJoinedAlready) {
  // A fan of four triangles around an apex above the plane z = 0, its other vertices below: the slice
  // points are the midpoints of the apex's edges. In the plane (u, w) = (x, y): P (3, 5), W (-4, 0),
  // q (-1, 1), then (0, -1.5), A (0, 0), Z (1, -3).
  const glm::dvec3 apex(0, 2, 1);
  auto below = [&](glm::dvec2 cut) { return glm::dvec3(2 * cut.x - apex.x, 2 * cut.y - apex.y, -1); };
  MeshTopology topology;
  topology.num_vertices = 6;
  topology.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}};
  std::vector<Frame> frames(2);
  for (int f = 0; f < 2; ++f) {
    frames[f].time = f;
    frames[f].positions = {apex,           below({3, 5}),
                           below({-4, 0}), below(f == 0 ? glm::dvec2(-1, 1) : glm::dvec2(0, -1.5)),
                           below({0, 0}),  below({1, -3})};
  }
  SlicingPlan plan;
  plan.orientations = {{0, 0, 1}};
  plan.planes = {make_plane({0, 0, 1}, 0.0, 0)};
  const KineticVisibility probe(topology, plan, frames[0]);
  ASSERT_EQ(kinetic::KineticInspect::slice(probe, 0).cones().slice.vertices.size(), 5u);
  KineticFrameStats totals;
  EXPECT_EQ(run_and_compare(topology, frames, plan, true, &totals, {false, {1.0, 8, false}, true}), "");
  EXPECT_GE(totals.certificates_failed, 2u);
  EXPECT_EQ(totals.flipped, 2u);
  EXPECT_EQ(totals.reinserted, 0u);
  EXPECT_EQ(totals.slices_repaired, 1u);
}

/// A sheet in z = 0 turning in its own plane: every slice is collinear (dimension 1).
TEST(KineticVisibility, FlatSheetEveryFrame) {
  test::TestMesh sheet = test::flat_sheet(9, 7, 0.1);
  std::vector<Frame> frames;
  for (int f = 0; f < 6; ++f) {
    test::TestMesh m = sheet;
    test::rigid_transform(m, {0, 0, 1}, 0.05 * f, {0.01 * f, 0.0, 0.0});
    frames.push_back(m.frame);
  }
  const SlicingPlan plan = plan_for(sheet.topology, frames, 4, {{2, 10}, {3, 31}});
  KineticFrameStats totals;
  EXPECT_EQ(run_and_compare(sheet.topology, frames, plan, true, &totals), "");
  EXPECT_GT(totals.rebuilt_because[int(kinetic::RebuildReason::degenerate)], 0u);
}

/// A V-fold whose half-angle closes to almost nothing and reopens; at frames 0 and 6 it is flat open (180°).
TEST(KineticVisibility, AHeldFrameKeepsEverySliceAndCone) {
  // A flag that moves, holds for three frames, and moves on: the held frames change no slice and equal a
  // recompute; the frame after the hold carries from the held one.
  const ClothGenerator cloth(ClothKind::Flag, {12, 10, 24.0, 3});
  std::vector<Frame> frames;
  for (int f = 0; f < 10; ++f) frames.push_back(cloth.frame(f < 4 ? f : f < 7 ? 4 : f - 2));
  for (std::size_t f = 0; f < frames.size(); ++f) frames[f].time = double(f) / 24.0;
  const SlicingPlan plan = make_diffuse_plan(cloth.topology(), frames[0], {});
  KineticVisibility kinetic(cloth.topology(), plan, frames[0]);
  StaticVisibility fresh(cloth.topology(), plan);
  for (std::size_t f = 1; f < frames.size(); ++f) {
    const FrameVisibility& k = kinetic.advance(frames[f]);
    const FrameVisibility& s = fresh.compute(frames[f]);
    for (const Side side : kBothSides)
      for (Index v = 0; v < cloth.topology().num_vertices; ++v)
        ASSERT_EQ(k.measure(side, v).sky_visibility, s.measure(side, v).sky_visibility) << f << " " << v;
    const bool held = f >= 5 && f <= 6;
    EXPECT_EQ(kinetic.last_stats().slices_kept == s.stats.slices && kinetic.last_stats().certificates == 0,
              held)
        << f;
  }
}

TEST(KineticVisibility, FoldClosingAndReopening) {
  std::vector<Frame> frames;
  MeshTopology topology;
  for (double alpha : {1.5707963267948966, 1.0, 0.5, 0.15, 0.04, 0.15, 0.5, 1.0, 1.5707963267948966}) {
    test::TestMesh m = test::v_fold(alpha, 9, 6, 1.0, 0.6);
    test::rigid_transform(m, {1, 2, 3}, 0.3, {0, 0, 0});
    topology = m.topology;
    frames.push_back(m.frame);
  }
  const SlicingPlan plan = plan_for(topology, frames, 6, {{4, 20}});
  EXPECT_EQ(run_and_compare(topology, frames, plan, true), "");
}

/// Planes through vertices at frame times (the vertex is on the plane at the end of one interval and the
/// start of the next), three slice points collinear exactly at a frame (a flat frame inside a moving
/// sequence), and a mirror-symmetric motion whose failures come in symmetric pairs.
TEST(KineticVisibility, DegenerateFrameTimesAndSimultaneousEvents) {
  const ClothGenerator cloth(ClothKind::Curtain, {10, 8, 24.0, 0});  // nominal curtain: mirror symmetric
  std::vector<Frame> frames;
  for (std::size_t f = 0; f < 8; ++f) frames.push_back(cloth.frame(f));
  // Frame 4 flattened onto its best plane z = mean: every slice collinear exactly there.
  double mean_z = 0;
  for (const glm::dvec3& p : frames[4].positions) mean_z += p.z;
  mean_z /= double(frames[4].positions.size());
  for (glm::dvec3& p : frames[4].positions) p.z = mean_z;
  std::vector<std::pair<std::size_t, Index>> through;
  for (std::size_t f = 0; f < frames.size(); ++f) through.emplace_back(f, Index(7 * f + 3));
  const SlicingPlan plan = plan_for(cloth.topology(), frames, 5, through);
  EXPECT_EQ(run_and_compare(cloth.topology(), frames, plan, true), "");
}

/// 1000 frames: the kept structures do not drift from a full recompute (checked at every frame).
TEST(KineticVisibility, ThousandFramesWithoutDrift) {
  const ClothGenerator cloth(ClothKind::Flag, {9, 1000, 24.0, 17});
  std::vector<Frame> frames;
  for (std::size_t f = 0; f < 1000; ++f) frames.push_back(cloth.frame(f));
  const SlicingPlan plan = plan_for(cloth.topology(), frames, 4, {});
  KineticFrameStats totals;
  // The policy by edit counts alone: the measured one may rebuild these small slices rather than carry them.
  EXPECT_EQ(run_and_compare(cloth.topology(), frames, plan, false, &totals, {false, {0.5, 8, false}, false}),
            "");
  EXPECT_GT(totals.slices_repaired + totals.slices_unchanged, totals.slices_rebuilt);
}

/// The measured policy's whole intervals (KineticPolicy::measured_cost): the engine rebuilds every slice the
/// motion reaches in some intervals (the second one always: the first sample of a rebuild's cost), the output
/// stays the recompute's, and without the measured policy no interval is rebuilt whole.
TEST(KineticVisibility, WholeIntervalRebuildsKeepTheOutput) {
  const ClothGenerator cloth(ClothKind::Flag, {12, 40, 24.0, 5});
  std::vector<Frame> frames;
  for (std::size_t f = 0; f < 40; ++f) frames.push_back(cloth.frame(f));
  const SlicingPlan plan = plan_for(cloth.topology(), frames, 6, {});
  const auto whole = static_cast<std::size_t>(kinetic::RebuildReason::frame_cost);
  for (const bool measured : {true, false}) {
    KineticParams params{false, {}, true};
    params.policy.measured_cost = measured;
    KineticVisibility engine(cloth.topology(), plan, frames[0], params);
    std::size_t whole_intervals = 0;
    for (std::size_t f = 1; f < frames.size(); ++f) {
      const FrameVisibility& kinetic = engine.advance(frames[f]);
      const KineticFrameStats& stats = engine.last_stats();
      // Every slice the motion reaches, or none (the flag's pole does not move: slices along it are kept).
      const std::size_t reached = plan.planes.size() - stats.slices_kept;
      if (stats.rebuilt_because[whole] > 0) {
        EXPECT_EQ(stats.rebuilt_because[whole], reached) << "frame " << f;
        ++whole_intervals;
      }
      if (measured && f == 2) {
        EXPECT_EQ(stats.rebuilt_because[whole], reached);
      }
      const FrameVisibility fresh = compute_visibility(cloth.topology(), frames[f], plan);
      for (int side = 0; side < 2; ++side)
        for (std::size_t v = 0; v < fresh.measures[side].size(); ++v)
          ASSERT_EQ(kinetic.measures[side][v].sky_visibility, fresh.measures[side][v].sky_visibility)
              << "frame " << f << " vertex " << v;
    }
    if (measured)
      EXPECT_GE(whole_intervals, 2u);  // the first sample, and at least every 16th interval after it
    else
      EXPECT_EQ(whole_intervals, 0u);
  }
}

/// Parallel and serial kinetic runs agree bit for bit (slices are independent).
TEST(KineticVisibility, ParallelEqualsSerial) {
  const ClothGenerator cloth(ClothKind::Sleeve, {14, 6, 24.0, 3});
  const SlicingPlan plan = make_diffuse_plan(cloth.topology(), cloth.frame(0), {});
  // The policy by edit counts alone: the measured one's choices (and so the counters) follow the timings.
  const kinetic::KineticPolicy by_edits{0.5, 8, false};
  KineticVisibility serial(cloth.topology(), plan, cloth.frame(0), {false, by_edits, false});
  KineticVisibility parallel(cloth.topology(), plan, cloth.frame(0), {true, by_edits, false});
  for (std::size_t f = 1; f < 6; ++f) {
    const FrameVisibility& a = serial.advance(cloth.frame(f));
    const FrameVisibility& b = parallel.advance(cloth.frame(f));
    for (int side = 0; side < 2; ++side)
      for (std::size_t v = 0; v < a.measures[side].size(); ++v)
        ASSERT_EQ(a.measures[side][v].sky_visibility, b.measures[side][v].sky_visibility);
    EXPECT_EQ(serial.last_stats().reinserted, parallel.last_stats().reinserted);
  }
}

}  // namespace
}  // namespace pleat
