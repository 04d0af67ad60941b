// Micro-benchmarks of the kinetic layer's hot parts on real data (kinetic/kinetic_slice.hpp, DESIGN.md §3):
// what one certificate, one static predicate, one rebuilt slice vertex, one repaired event or edit and one
// funnel-tree corner cost, so that the kinetic engine's frame time can be read off its parts.
//
// Input: two consecutive frames k, k+1 of a sequence and the CLI's default plan on frame k
// (make_diffuse_plan: 6 orientations, spacing = average edge length). "drape" is the bundled Blender
// simulation (data/drape/drape.obj + drape.pc2, 3,111 vertices), samples 40 and 41; "curtain/3025" is
// ClothGenerator's curtain at resolution 55 (48 frames per cycle), frames 12 and 13. Everything the timed
// loops read is prepared once, outside them.
//
// Benchmarks (one thread, serial; wall time (UseRealTime) and process CPU time; per-item counters are
// seconds per item over wall time, printed with an SI prefix):
//   certificate/filter/<seq>          certainly_positive on every finite face of every plane's triangulation
//                                     at frame k, its slice vertices moving from their frame-k to their
//                                     frame-k+1 points (matched by mesh edge; faces whose vertex vanishes, or
//                                     is a crossing point of two chains, are skipped); one FPU-rounding guard
//                                     per pass. Counters: s_per_certificate, undecided_fraction,
//                                     skipped_vanishing, skipped_crossing.
//   certificate/filter_guarded/<seq>  the same with one guard per certificate, as the engine's certify does.
//   certificate/exact/<seq>           the undecided ones: orientation_polynomial, sign_after and
//                                     first_root_after at t = 0 (all in rational arithmetic). Counter:
//                                     s_per_certificate.
//   certificate/lazy/<seq>            the undecided ones as KineticSlice's certify decides them at t = 0:
//                                     orientation_certificate, exact Bernstein signs (Mpzf), certain_sign_at,
//                                     first_root_after on the interval enclosure, the rational polynomial
//                                     only where intervals cannot decide. Counters: s_per_certificate, and
//                                     how many each stage decided (by_signs, by_intervals, by_exact).
//   predicate/orientation/<seq>       CGAL::orientation (EPICK, filtered exact) on the same triples at frame
//                                     k+1: what a static recompute pays per predicate. Counter:
//                                     s_per_predicate.
//   slice/rebuild/<seq>               KineticSlice::build of every plane at frame k+1 (the static path:
//                                     slicing, constrained triangulation, regions, cones).
//                                     s_per_slice_vertex.
//   slice/repair/<seq>                KineticSlice::build at frame k (not timed) then advance to k+1 with
//                                     KineticPolicy{100, 100} (repair whatever can be repaired), every plane.
//                                     Counters: s_per_slice_vertex (frame k+1's), events, edits, rebuilt
//                                     (slices rebuilt anyway, and rebuilt_<reason>), s_per_event_or_edit
//                                     (the whole advance over events + edits).
//   slice/advance_default/<seq>       the same with the default KineticPolicy{}.
//   funnel/trees/<seq>                grow_shortest_path_tree from both ends of every window of every region
//                                     without holes, on every plane's triangulation at frame k.
//                                     Counter: s_per_corner_tree (corners of the region per tree).
// The cost of the local edits alone (slice/edit) is not separable from advance() without touching the
// kinetic sources: not measured.
//
// Flags of ours (before Google Benchmark's own):
//   --pleat_sequences=drape,curtain   which inputs
//   --pleat_data=DIR                  the repository's data/ (default: found from this source file's path)
// Run: build/bench/kinetic_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
// Results: bench/results/kinetic_micro.md.
#include <CGAL/FPU.h>
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bench/bench_args.hpp"
#include "kinetic/kinetic_slice.hpp"
#include "kinetic/moving_orientation.hpp"
#include "kinetic/root_isolation.hpp"
#include "sim_io/cloth_generators.hpp"
#include "sim_io/mesh_sequence.hpp"
#include "static_core/mesh_slicer.hpp"
#include "static_core/shortest_path_tree.hpp"
#include "static_core/slice_triangulation.hpp"
#include "static_core/slicing_plan.hpp"

namespace pleat {
namespace {

namespace fs = std::filesystem;
using kinetic::KineticPolicy;
using kinetic::KineticScratch;
using kinetic::KineticSlice;
using kinetic::MovingPoint;
using kinetic::RootTime;
using kinetic::SliceEventCounts;

// ---- Options ----

struct Options {
  std::vector<std::string> sequences{"drape", "curtain"};
  fs::path data = fs::path(__FILE__).parent_path().parent_path() / "data";
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

/// Three slice vertices of a finite face at frame k, moving to their frame-k+1 points.
using Triple = std::array<MovingPoint, 3>;

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
  std::unique_ptr<MeshEdges> edges;
  std::vector<std::vector<Index>> faces0, faces1;  // candidate faces per plane at k and k+1
  std::vector<KineticSlice> at_k;                  // every plane built at frame k (sized once: never moved)
  std::size_t slice_vertices0 = 0, slice_vertices1 = 0;
  std::vector<Triple> triples;        // every finite face of frame k whose slice vertices survive
  std::size_t skipped_vanishing = 0;  // faces with a slice vertex whose mesh edge stops crossing at k+1
  std::size_t skipped_crossing = 0;   // faces with a crossing point of two chains (no mesh edge)
  std::vector<Triple> undecided;      // the triples the interval filter cannot decide
  std::vector<std::array<cgal::Point2, 3>> points1;  // the triples at frame k+1
  std::vector<TreeTask> trees;                       // every window of every region without holes
  std::size_t tree_corners = 0;                      // sum over trees of both ends: corners reached
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
    edges = std::make_unique<MeshEdges>(topology);
    faces0 = candidate_faces_per_plane(topology, frame0, plan);
    faces1 = candidate_faces_per_plane(topology, frame1, plan);
    const std::size_t planes = plan.planes.size();
    at_k.resize(planes);
    KineticScratch scratch;
    SlicerScratch slicer;
    Slice next;
    std::vector<std::int32_t> next_of_edge(edges->endpoints.size(), -1);
    for (std::size_t p = 0; p < planes; ++p) {
      at_k[p].build(topology, *edges, frame0, plan.planes[p], plan.storage, faces0[p], scratch);
      const Slice& slice = at_k[p].cones().slice;
      slice_mesh(topology, *edges, frame1, plan.planes[p], faces1[p], slicer, next);
      slice_vertices0 += slice.vertices.size();
      slice_vertices1 += next.vertices.size();
      for (Index y = 0; y < next.vertices.size(); ++y) next_of_edge[next.vertices[y].edge] = std::int32_t(y);

      // Certificates: the triangle orientations of frame k's triangulation over the interval.
      const SliceTriangulation& tri = at_k[p].triangulation();
      const cgal::Cdt& cdt = tri.cdt();
      if (tri.dimension() == 2)
        for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
          Triple t;
          bool crossing = false, vanishing = false;
          for (int i = 0; i < 3; ++i) {
            const int x = f->vertex(i)->info().slice_vertex;
            const std::int32_t y = x < 0 ? -1 : next_of_edge[slice.vertices[x].edge];
            if (x < 0)
              crossing = true;
            else if (y < 0)
              vanishing = true;
            else
              t[i] = {cgal::to_glm(f->vertex(i)->point()), next.vertices[y].point};
          }
          if (crossing || vanishing) {
            ++(crossing ? skipped_crossing : skipped_vanishing);
            continue;
          }
          triples.push_back(t);
          points1.push_back({cgal::to_point(t[0].to), cgal::to_point(t[1].to), cgal::to_point(t[2].to)});
        }
      for (const SliceVertex& v : next.vertices) next_of_edge[v.edge] = -1;

      // Funnel trees: every window of every region without holes.
      std::vector<std::size_t> region_corners(tri.regions().size(), 0);
      for (std::size_t c = 0; c < tri.num_corners(); ++c)
        if (tri.corner_region(int(c)) >= 0) ++region_corners[tri.corner_region(int(c))];
      max_corners = std::max(max_corners, tri.num_corners());
      for (std::size_t r = 0; r < tri.regions().size(); ++r) {
        const SliceRegion& region = tri.regions()[r];
        if (region.has_holes) continue;
        for (const SliceWindow& w : region.windows) {
          trees.push_back({p, &w, region_corners[r]});
          tree_corners += 2 * region_corners[r];
        }
      }
    }
    {
      CGAL::Protect_FPU_rounding<true> rounding;
      for (const Triple& t : triples)
        if (!kinetic::certainly_positive(t[0], t[1], t[2])) undecided.push_back(t);
    }
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

void filter_benchmark(benchmark::State& state, std::string name, bool guard_per_certificate) {
  const Workload& w = workload(name);
  std::size_t positive = 0;
  for (auto _ : state) {
    positive = 0;
    if (guard_per_certificate) {
      for (const Triple& t : w.triples) {
        CGAL::Protect_FPU_rounding<true> rounding;
        positive += kinetic::certainly_positive(t[0], t[1], t[2]);
      }
    } else {
      CGAL::Protect_FPU_rounding<true> rounding;
      for (const Triple& t : w.triples) positive += kinetic::certainly_positive(t[0], t[1], t[2]);
    }
    benchmark::DoNotOptimize(positive);
  }
  state.counters["certificates"] = double(w.triples.size());
  state.counters["skipped_vanishing"] = double(w.skipped_vanishing);
  state.counters["skipped_crossing"] = double(w.skipped_crossing);
  state.counters["undecided_fraction"] = double(w.triples.size() - positive) / double(w.triples.size());
  state.counters["s_per_certificate"] = per_item(double(w.triples.size()));
}

void exact_benchmark(benchmark::State& state, std::string name) {
  const Workload& w = workload(name);
  if (w.undecided.empty()) {
    state.SkipWithError("no undecided certificate");
    return;
  }
  const RootTime t0 = RootTime::zero();
  std::size_t roots = 0, negative = 0;
  for (auto _ : state) {
    roots = negative = 0;
    for (const Triple& t : w.undecided) {
      const kinetic::ExactPolynomial poly = kinetic::orientation_polynomial(t[0], t[1], t[2]);
      negative += kinetic::sign_after(poly, t0) < 0;
      roots += kinetic::first_root_after(poly, t0).has_value();
    }
    benchmark::DoNotOptimize(roots);
  }
  state.counters["certificates"] = double(w.undecided.size());
  state.counters["with_root"] = double(roots);
  state.counters["negative_after_0"] = double(negative);
  state.counters["s_per_certificate"] = per_item(double(w.undecided.size()));
}

/// How KineticSlice's certify decides an undecided triangle certificate at t = 0 (kinetic::first_failure):
/// which stage settled it (0: exact Bernstein signs, 1: intervals, 2: rational arithmetic).
int decide_lazily(const Triple& t, const RootTime& t0) {
  const kinetic::CertificateFailure failure = kinetic::first_failure(t, t0, true);
  benchmark::DoNotOptimize(failure.time);
  switch (failure.decided_by) {
    case kinetic::CertificateFailure::DecidedBy::filter:
    case kinetic::CertificateFailure::DecidedBy::exact_signs:
      return 0;
    case kinetic::CertificateFailure::DecidedBy::intervals:
      return 1;
    case kinetic::CertificateFailure::DecidedBy::rationals:
      return 2;
  }
  return 2;
}

void lazy_benchmark(benchmark::State& state, std::string name) {
  const Workload& w = workload(name);
  if (w.undecided.empty()) {
    state.SkipWithError("no undecided certificate");
    return;
  }
  const RootTime t0 = RootTime::zero();
  std::array<std::size_t, 3> by{};
  for (auto _ : state) {
    by = {};
    for (const Triple& t : w.undecided) ++by[decide_lazily(t, t0)];
    benchmark::DoNotOptimize(by.data());
  }
  state.counters["certificates"] = double(w.undecided.size());
  state.counters["by_signs"] = double(by[0]);
  state.counters["by_intervals"] = double(by[1]);
  state.counters["by_exact"] = double(by[2]);
  state.counters["s_per_certificate"] = per_item(double(w.undecided.size()));
}

void orientation_benchmark(benchmark::State& state, std::string name) {
  const Workload& w = workload(name);
  std::size_t left = 0;
  for (auto _ : state) {
    left = 0;
    for (const auto& p : w.points1) left += CGAL::orientation(p[0], p[1], p[2]) == CGAL::LEFT_TURN;
    benchmark::DoNotOptimize(left);
  }
  state.counters["predicates"] = double(w.points1.size());
  state.counters["not_left_at_k1"] = double(w.points1.size() - left);
  state.counters["s_per_predicate"] = per_item(double(w.points1.size()));
}

void rebuild_benchmark(benchmark::State& state, std::string name) {
  const Workload& w = workload(name);
  std::vector<KineticSlice> slices(w.plan.planes.size());
  KineticScratch scratch;
  auto build_all = [&] {
    for (std::size_t p = 0; p < slices.size(); ++p)
      slices[p].build(w.topology, *w.edges, w.frame1, w.plan.planes[p], w.plan.storage, w.faces1[p], scratch);
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
  SliceEventCounts total;
  std::size_t rebuilt = 0;
  std::array<std::size_t, static_cast<std::size_t>(kinetic::RebuildReason::count)> because{};
  auto build_all = [&] {
    for (std::size_t p = 0; p < slices.size(); ++p)
      slices[p].build(w.topology, *w.edges, w.frame0, w.plan.planes[p], w.plan.storage, w.faces0[p], scratch);
  };
  auto advance_all = [&] {
    total = {};
    rebuilt = 0;
    because = {};
    for (std::size_t p = 0; p < slices.size(); ++p) {
      const SliceEventCounts c =
          slices[p].advance(w.topology, *w.edges, w.frame1, w.plan.planes[p], w.faces1[p], policy, scratch);
      total += c;
      rebuilt += c.rebuild != kinetic::RebuildReason::none;
      ++because[static_cast<std::size_t>(c.rebuild)];
    }
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
  const double events = double(total.events()), edits = double(total.removed + total.inserted);
  state.counters["slices"] = double(slices.size());
  state.counters["slice_vertices"] = double(w.slice_vertices1);
  state.counters["certificates"] = double(total.certificates);
  state.counters["exact_certificates"] = double(total.exact_certificates);
  state.counters["flips"] = double(total.flips);
  state.counters["hull"] = double(total.hull_enter + total.hull_leave);
  state.counters["touches"] = double(total.touches);
  state.counters["events"] = events;
  state.counters["edits"] = edits;
  state.counters["rebuilt"] = double(rebuilt);
  for (std::size_t r = 1; r < because.size(); ++r)  // by reason, where any
    if (because[r] > 0)
      state.counters[std::string("rebuilt_") + kinetic::rebuild_reason_name(kinetic::RebuildReason(r))] =
          double(because[r]);
  state.counters["s_per_slice_vertex"] = per_item(double(w.slice_vertices1));
  if (events + edits > 0) state.counters["s_per_event_or_edit"] = per_item(events + edits);
}

void funnel_benchmark(benchmark::State& state, std::string name) {
  const Workload& w = workload(name);
  std::vector<int> parent(w.max_corners, -1);
  std::vector<FunnelTask> stack;
  stack.reserve(1024);
  for (auto _ : state) {
    for (const TreeTask& t : w.trees) {
      const SliceTriangulation& tri = w.at_k[t.plane].triangulation();
      grow_shortest_path_tree(tri, *t.window, false, parent, stack);
      grow_shortest_path_tree(tri, *t.window, true, parent, stack);
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
    add("certificate/filter/" + label, filter_benchmark, s, false);
    add("certificate/filter_guarded/" + label, filter_benchmark, s, true);
    add("certificate/exact/" + label, exact_benchmark, s);
    add("certificate/lazy/" + label, lazy_benchmark, s);
    add("predicate/orientation/" + label, orientation_benchmark, s);
    add("slice/rebuild/" + label, rebuild_benchmark, s);
    add("slice/repair/" + label, advance_benchmark, s, KineticPolicy{100, 100});
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
