// Micro-benchmarks of the kinetic layer's hot parts on real data (kinetic/internal/kinetic_slice.hpp,
// docs/method.md §11): what one frame certificate, one rebuilt slice vertex, one repaired edit and one
// funnel-tree corner cost, so that the kinetic engine's frame time can be read off its parts.
//
// Input: two consecutive frames k, k+1 of a sequence and the CLI's default plan on frame k
// (make_diffuse_plan). "drape" is the bundled Blender simulation (data/drape/drape.obj + drape.pc2, 3,111
// vertices), samples 40 and 41; "curtain/3025" is ClothGenerator's curtain at resolution 55 (48 frames per
// cycle), frames 12 and 13. Everything the timed loops read is prepared once, outside them.
//
// Benchmarks (one thread, serial; wall time (UseRealTime) and process CPU time; per-item counters are
// seconds per item over wall time, printed with an SI prefix):
//   certificate/at_frame/<seq>        the frame certificate of a kept triangle: CGAL::orientation (EPICK,
//                                     filtered exact) of every finite face of every plane's triangulation at
//                                     frame k, on its slice vertices' frame-k+1 points (matched by mesh edge;
//                                     faces whose vertex vanishes, or is a crossing point of two chains, are
//                                     skipped). Counters: s_per_certificate, failed (not left turns at k+1),
//                                     motion_p10 / _median / _p90: how far the slice vertices that survive
//                                     to k+1 move, in mean chain-edge lengths of their slice at k;
//                                     margin_certified: the certificates a margin would decide without the
//                                     predicate (twice the area at k above 2 d (|ab| + |ac|) + 4 d^2, d the
//                                     largest movement of the three vertices, a opposite the longest side);
//                                     margin_certified_4x with a quarter of d (4x the frame rate, about).
//   slice/rebuild/<seq>               KineticSlice::build of every plane at frame k+1 (the static path:
//                                     slicing, constrained triangulation, regions, cones).
//                                     s_per_slice_vertex.
//   slice/repair/<seq>                KineticSlice::build at frame k (not timed) then advance to k+1 with
//                                     KineticPolicy{100, 8, false} (repair whatever can be repaired), every
//                                     plane.
//                                     Counters: s_per_slice_vertex (frame k+1's), every KineticCounts
//                                     counter, rebuilt_<reason>, s_per_edit (the whole advance over slice
//                                     vertices removed, inserted and put back).
//   slice/advance_default/<seq>       the same with the default KineticPolicy{}.
//   funnel/trees/<seq>                grow_shortest_path_tree from both ends of every window of every region
//                                     without holes, on every plane's triangulation at frame k.
//                                     Counter: s_per_corner_tree (corners of the region per tree).
//
// Flags of ours (before Google Benchmark's own):
//   --pleat_sequences=drape,curtain   which inputs
//   --pleat_data=DIR                  data/ (default: that of the source tree it was built from)
// Run: build/bench/kinetic_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
// Results: bench/results/kinetic_micro.md.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>
#include <deque>
#include <filesystem>
#include <glm/geometric.hpp>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bench/bench_args.hpp"
#include "kinetic/internal/kinetic_slice.hpp"
#include "sim_io/cloth_generators.hpp"
#include "sim_io/load_sequence.hpp"
#include "sim_io/mesh_sequence.hpp"
#include "static_core/internal/shortest_path_tree.hpp"
#include "static_core/internal/slice_triangulation.hpp"
#include "static_core/mesh_slicer.hpp"
#include "static_core/slicing_plan.hpp"

namespace pleat {
namespace {

namespace fs = std::filesystem;
using kinetic::KineticPolicy;
using kinetic::KineticScratch;
using kinetic::KineticSlice;

// ---- Options ----

struct Options {
  std::vector<std::string> sequences{"drape", "curtain"};
  fs::path data = fs::path(PLEAT_BENCH_SOURCE_DIR) / "data";
};
Options g_options;

constexpr std::size_t kDrapeFrame = 40;    // samples 40 and 41 of the bundled drape
constexpr int kCurtainResolution = 55;     // 3,025 vertices
constexpr int kCurtainCycle = 48;          // frames per motion cycle
constexpr std::size_t kCurtainFrame = 12;  // a quarter of the cycle: moving fastest

/// Removes our flags from argv (Google Benchmark rejects unknown ones). Returns false on a bad value.
bool parse_options(int& argc, char** argv) {
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    auto value = [&](const char* name) { return bench::flag_value(argv[i], name); };
    if (const char* v = value("--pleat_sequences")) {
      g_options.sequences = bench::split(v);
      for (const auto& s : g_options.sequences)
        if (s != "drape" && s != "curtain") {
          std::fprintf(stderr, "kinetic_bench: unknown sequence '%s' (drape, curtain)\n", s.c_str());
          return false;
        }
    } else if (const char* v = value("--pleat_data")) {
      g_options.data = v;
    } else {
      argv[kept++] = argv[i];
    }
  }
  argc = kept;
  return true;
}

std::string sequence_label(const std::string& name) { return name == "curtain" ? "curtain/3025" : name; }

// ---- Inputs: frames k and k+1, the plan, and every structure the benchmarks read, built once. ----

/// One window of a region without holes: the two trees grown from it, and the region's corner count.
struct TreeTask {
  std::size_t plane = 0;
  const SliceWindow* window = nullptr;
  std::size_t corners = 0;
};

struct Workload {
  MeshTopology topology;
  Frame frame0, frame1;  // k and k+1
  SlicingPlan plan;
  std::unique_ptr<MeshConnectivity> connectivity;
  std::vector<std::vector<Index>> faces0, faces1;   // candidate faces per plane at k and k+1
  std::vector<KineticSlice> at_k;                   // every plane built at frame k (sized once: never moved)
  std::deque<SliceTriangulation> triangulations_k;  // their triangulations with regions (never moved)
  std::size_t slice_vertices0 = 0, slice_vertices1 = 0;
  std::vector<std::array<cgal::Point2, 3>> points1;  // every finite face of frame k, at frame k+1's points
  std::size_t skipped_vanishing = 0;  // faces with a slice vertex whose mesh edge stops crossing at k+1
  std::size_t skipped_crossing = 0;   // faces with a crossing point of two chains (no mesh edge)
  /// Per slice vertex that survives to k+1: how far its point moves, in mean chain-edge lengths of its slice
  /// at frame k (sorted).
  std::vector<double> motion;
  /// Of the faces in points1: those whose area at frame k exceeds what the movement of their vertices to
  /// k+1 could take away (a margin certificate would keep them without evaluating the predicate).
  std::size_t margin_certified = 0;
  std::size_t margin_certified_4x = 0;  ///< the same with a quarter of the movement (4x the frame rate)
  std::vector<TreeTask> trees;          // every window of every region without holes
  std::size_t tree_corners = 0;         // sum over trees of both ends: corners reached
  std::size_t max_corners = 0;

  void load(const std::string& name) {
    if (name == "drape") {
      const MeshSequence seq =
          load_sequence(g_options.data / "drape" / "drape.obj", g_options.data / "drape" / "drape.pc2");
      topology = seq.topology();
      frame0 = seq.frame(kDrapeFrame);
      frame1 = seq.frame(kDrapeFrame + 1);
    } else {
      const ClothGenerator generator(ClothKind::Curtain,
                                     GeneratorParams{kCurtainResolution, kCurtainCycle, 24.0, 0});
      topology = generator.topology();
      frame0 = generator.frame(kCurtainFrame);
      frame1 = generator.frame(kCurtainFrame + 1);
    }
  }

  explicit Workload(const std::string& name) {
    load(name);
    plan = make_diffuse_plan(topology, frame0, DiffusePlanParams{});  // the CLI's defaults
    connectivity = std::make_unique<MeshConnectivity>(topology);
    faces0 = candidate_faces_per_plane(topology, frame0, plan);
    faces1 = candidate_faces_per_plane(topology, frame1, plan);
    const std::size_t planes = plan.planes.size();
    at_k.resize(planes);
    KineticScratch scratch;
    SlicerScratch slicer;
    Slice next;
    std::vector<std::int32_t> next_of_edge(connectivity->num_edges(), -1);
    for (std::size_t p = 0; p < planes; ++p) {
      at_k[p].build(topology, *connectivity, frame0, plan.planes[p], plan.storage,
                    split_faces(topology, faces0[p]), {}, scratch);
      const Slice& slice = at_k[p].cones().slice;
      slice_mesh(topology, *connectivity, frame1, plan.planes[p], faces1[p], slicer, next);
      slice_vertices0 += slice.vertices.size();
      slice_vertices1 += next.vertices.size();
      for (Index y = 0; y < next.vertices.size(); ++y) next_of_edge[next.vertices[y].edge] = std::int32_t(y);
      double edge_length = 0.0;
      for (const SliceEdge& e : slice.edges)
        edge_length += glm::length(slice.vertices[e.to].point - slice.vertices[e.from].point);
      edge_length /= double(std::max<std::size_t>(slice.edges.size(), 1));
      for (const SliceVertex& v : slice.vertices)
        if (const std::int32_t y = next_of_edge[v.edge]; y >= 0 && edge_length > 0.0)
          motion.push_back(glm::length(next.vertices[y].point - v.point) / edge_length);

      // Frame certificates: the triangles of frame k's triangulation on frame k+1's points.
      const SliceTriangulation& tri = triangulations_k.emplace_back();
      at_k[p].rederive_triangulation(triangulations_k.back());
      const cgal::Cdt& cdt = tri.cdt();
      if (tri.dimension() == 2)
        for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
          std::array<cgal::Point2, 3> t;
          bool crossing = false, vanishing = false;
          for (int i = 0; i < 3; ++i) {
            const int x = f->vertex(i)->info().slice_vertex;
            const std::int32_t y = x < 0 ? -1 : next_of_edge[slice.vertices[x].edge];
            if (x < 0)
              crossing = true;
            else if (y < 0)
              vanishing = true;
            else
              t[i] = cgal::to_point(next.vertices[y].point);
          }
          if (crossing || vanishing) {
            ++(crossing ? skipped_crossing : skipped_vanishing);
            continue;
          }
          points1.push_back(t);
          // Could a margin certify it without the predicate? Twice its area at frame k against the most it
          // can change when each vertex moves at most delta: 2 delta (|ab| + |ac|) + 4 delta^2, at the vertex
          // a opposite the longest edge.
          std::array<glm::dvec2, 3> q;
          double delta = 0.0;
          for (int i = 0; i < 3; ++i) {
            q[i] = cgal::to_glm(f->vertex(i)->point());
            delta = std::max(delta, glm::length(cgal::to_glm(t[i]) - q[i]));
          }
          const double twice_area =
              std::abs((q[1].x - q[0].x) * (q[2].y - q[0].y) - (q[1].y - q[0].y) * (q[2].x - q[0].x));
          const std::array<double, 3> side{glm::length(q[2] - q[1]), glm::length(q[0] - q[2]),
                                           glm::length(q[1] - q[0])};  // side i opposite vertex i
          const double longest = std::max({side[0], side[1], side[2]});
          const double shorter_two = side[0] + side[1] + side[2] - longest;
          margin_certified += twice_area > 2.0 * delta * shorter_two + 4.0 * delta * delta;
          const double quarter = delta / 4;  // at 4x the frame rate, about
          margin_certified_4x += twice_area > 2.0 * quarter * shorter_two + 4.0 * quarter * quarter;
        }
      for (const SliceVertex& v : next.vertices) next_of_edge[v.edge] = -1;

      // Funnel trees: every window of every region without holes.
      std::vector<std::size_t> region_corners(tri.num_regions(), 0);
      for (std::size_t c = 0; c < tri.num_corners(); ++c)
        if (tri.corner_region(int(c)) >= 0) ++region_corners[tri.corner_region(int(c))];
      max_corners = std::max(max_corners, tri.num_corners());
      for (std::size_t r = 0; r < tri.num_regions(); ++r) {
        const SliceRegion region = tri.region(r);
        if (region.has_holes) continue;
        for (const SliceWindow& w : region.windows) {
          trees.push_back({p, &w, region_corners[r]});
          tree_corners += 2 * region_corners[r];
        }
      }
    }
    std::sort(motion.begin(), motion.end());
  }
};

const Workload& workload(const std::string& name) {
  static std::map<std::string, std::unique_ptr<Workload>> cache;
  auto& slot = cache[name];
  if (!slot) slot = std::make_unique<Workload>(name);
  return *slot;
}

/// Seconds per item: iteration time / items (printed with an SI prefix).
benchmark::Counter per_item(double items) {
  return benchmark::Counter(items,
                            benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// ---- Benchmarks ----

void certificate_benchmark(benchmark::State& state, std::string name) {
  const Workload& w = workload(name);
  std::size_t left = 0;
  for (auto _ : state) {
    left = 0;
    for (const auto& p : w.points1) left += CGAL::orientation(p[0], p[1], p[2]) == CGAL::LEFT_TURN;
    benchmark::DoNotOptimize(left);
  }
  state.counters["certificates"] = double(w.points1.size());
  state.counters["skipped_vanishing"] = double(w.skipped_vanishing);
  state.counters["skipped_crossing"] = double(w.skipped_crossing);
  state.counters["failed"] = double(w.points1.size() - left);
  auto motion_quantile = [&](double q) {
    return w.motion.empty() ? 0.0 : w.motion[std::size_t(q * double(w.motion.size() - 1))];
  };
  state.counters["margin_certified"] = double(w.margin_certified);
  state.counters["margin_certified_4x"] = double(w.margin_certified_4x);
  state.counters["motion_median"] = motion_quantile(0.5);
  state.counters["motion_p10"] = motion_quantile(0.1);
  state.counters["motion_p90"] = motion_quantile(0.9);
  state.counters["s_per_certificate"] = per_item(double(w.points1.size()));
}

void rebuild_benchmark(benchmark::State& state, std::string name) {
  const Workload& w = workload(name);
  std::vector<KineticSlice> slices(w.plan.planes.size());
  KineticScratch scratch;
  auto build_all = [&] {
    for (std::size_t p = 0; p < slices.size(); ++p)
      slices[p].build(w.topology, *w.connectivity, w.frame1, w.plan.planes[p], w.plan.storage,
                      split_faces(w.topology, w.faces1[p]), {}, scratch);
  };
  build_all();  // warm the slices' and the scratch's memory, as the engine's are after its first frame
  for (auto _ : state) {
    build_all();
    benchmark::DoNotOptimize(slices.back().cones().cones.wedges.data());
  }
  state.counters["slices"] = double(slices.size());
  state.counters["slice_vertices"] = double(w.slice_vertices1);
  state.counters["s_per_slice_vertex"] = per_item(double(w.slice_vertices1));
}

void advance_benchmark(benchmark::State& state, std::string name, KineticPolicy policy) {
  const Workload& w = workload(name);
  std::vector<KineticSlice> slices(w.plan.planes.size());
  KineticScratch scratch;
  KineticCounts total;
  auto build_all = [&] {
    for (std::size_t p = 0; p < slices.size(); ++p)
      slices[p].build(w.topology, *w.connectivity, w.frame0, w.plan.planes[p], w.plan.storage,
                      split_faces(w.topology, w.faces0[p]), {}, scratch);
  };
  auto advance_all = [&] {
    total = {};
    for (std::size_t p = 0; p < slices.size(); ++p)
      total += slices[p].advance(w.topology, *w.connectivity, w.frame1, w.plan.planes[p],
                                 split_faces(w.topology, w.faces1[p]), {}, policy, scratch);
  };
  build_all();
  advance_all();  // warm
  for (auto _ : state) {
    state.PauseTiming();
    build_all();
    state.ResumeTiming();
    advance_all();
    benchmark::DoNotOptimize(slices.back().cones().cones.wedges.data());
  }
  const double edits = double(total.removed + total.inserted + total.reinserted);
  state.counters["slices"] = double(slices.size());
  state.counters["slice_vertices"] = double(w.slice_vertices1);
  for (const KineticCounter& c : kKineticCounters) state.counters[c.name] = double(total.*c.field);
  for (std::size_t r = 1; r < total.rebuilt_because.size(); ++r)  // by reason, where any
    if (total.rebuilt_because[r] > 0)
      state.counters[std::string("rebuilt_") + kinetic::rebuild_reason_name(kinetic::RebuildReason(r))] =
          double(total.rebuilt_because[r]);
  state.counters["s_per_slice_vertex"] = per_item(double(w.slice_vertices1));
  if (edits > 0) state.counters["s_per_edit"] = per_item(edits);
}

void funnel_benchmark(benchmark::State& state, std::string name) {
  const Workload& w = workload(name);
  std::vector<int> parent(w.max_corners, -1);
  FunnelScratch funnel;
  for (auto _ : state) {
    for (const TreeTask& t : w.trees) {
      const SliceTriangulation& tri = w.triangulations_k[t.plane];
      grow_shortest_path_tree(tri, *t.window, false, parent, funnel);
      grow_shortest_path_tree(tri, *t.window, true, parent, funnel);
    }
    benchmark::DoNotOptimize(parent.data());
  }
  state.counters["trees"] = double(2 * w.trees.size());
  state.counters["corner_trees"] = double(w.tree_corners);
  state.counters["s_per_corner_tree"] = per_item(double(w.tree_corners));
}

void register_benchmarks() {
  auto add = [](const std::string& bench_name, auto&& fn, auto... args) {
    benchmark::RegisterBenchmark(bench_name.c_str(), fn, args...)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        ->MeasureProcessCPUTime();
  };
  for (const std::string& s : g_options.sequences) {
    const std::string label = sequence_label(s);
    add("certificate/at_frame/" + label, certificate_benchmark, s);
    add("slice/rebuild/" + label, rebuild_benchmark, s);
    add("slice/repair/" + label, advance_benchmark, s, KineticPolicy{100, 8, false});
    add("slice/advance_default/" + label, advance_benchmark, s, KineticPolicy{});
    add("funnel/trees/" + label, funnel_benchmark, s);
  }
}

}  // namespace
}  // namespace pleat

int main(int argc, char** argv) {
  if (!pleat::parse_options(argc, argv)) return 2;
  // One thread: nothing here is parallel, and no TBB worker may run beside the timed loops.
  tbb::global_control control(tbb::global_control::max_allowed_parallelism, 1);
  pleat::register_benchmarks();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 2;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
