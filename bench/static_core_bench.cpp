// Speed of the static core (docs/method.md §2–§8, docs/benchmarks.md; issue 3, "Speed"): Google Benchmark
// timings of compute_visibility on generated cloth at 3k, 30k and 300k vertices, one thread and two, with µs
// per slice vertex; micro-benchmarks of its stages on one frame's whole slice set (slicing, constrained
// triangulation, 2D cones, 3D assembly); operator-new counts per slice vertex for each stage; and Embree
// per-vertex ray casting (256 rays per vertex and side, BVH build included) on the same frame and threads as
// a reference.
//
// Every benchmark reports wall-clock time (UseRealTime) and process CPU time of one frame; counters carry the
// slice counts so that bench/run_static_core_bench.sh can derive µs per slice vertex, speed-ups and the stage
// breakdown. Threads: "threads:1" runs the sequential path (params.parallel = false) under a
// tbb::global_control of one thread; "threads:2" runs the TBB path under a control of two.
//
// Flags of ours (before Google Benchmark's own):
//   --pleat_resolutions=55,173,548   grid resolutions (55 -> 3,025 vertices, 173 -> 29,929, 548 -> 300,304)
//   --pleat_kinds=curtain,roll       generated kinds for the frame benchmarks
//   --pleat_large_repetitions=2      repetitions of compute_visibility above resolution 200 (the rest use
//                                    --benchmark_repetitions); Embree and the stages get one there
//   --pleat_stage_resolutions=55,173,548  the curtain frames whose slice sets the stage micro-benchmarks
//                                    use (allocation counts: resolutions up to 200 only)
//   --pleat_embree=1                 0 skips the Embree reference rows
//   --pleat_real=drape,pile,rucked,layered
//                                    the real Blender sequences of data/ for the frame/real rows (their last
//                                    sample, the most folded; "" for none): the pile and layered regression
//                                    benchmarks of the static-core issue (no real sequence above 2x the
//                                    drape's µs per slice vertex; compare the rows' s_per_slice_vertex)
//   --pleat_data=DIR                 data/ (default: that of the source tree it was built from)
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <glm/geometric.hpp>
#include <map>
#include <memory>
#include <new>
#include <queue>
#include <sstream>
#include <string>
#include <vector>

#include "bench/bench_args.hpp"
#include "shading/embree_scene.hpp"
#include "shading/ray_visibility.hpp"
#include "sim_io/cloth_generators.hpp"
#include "sim_io/load_sequence.hpp"
#include "sim_io/mesh_sequence.hpp"
#include "static_core/cone_assembly.hpp"
#include "static_core/internal/slice_cones.hpp"
#include "static_core/internal/slice_triangulation.hpp"
#include "static_core/mesh_slicer.hpp"
#include "static_core/slicing_plan.hpp"
#include "static_core/visibility.hpp"

// ---- Allocation counting: every operator new of the process, counted only while g_counting is set. ----
namespace {
std::atomic<bool> g_counting{false};
std::atomic<std::uint64_t> g_allocations{0};

void* counted_allocation(std::size_t size, std::size_t alignment) {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (size == 0) size = 1;
  void* p = alignment > alignof(std::max_align_t)
                ? std::aligned_alloc(alignment, (size + alignment - 1) / alignment * alignment)
                : std::malloc(size);
  if (!p) throw std::bad_alloc();
  return p;
}
}  // namespace

void* operator new(std::size_t size) { return counted_allocation(size, 0); }
void* operator new[](std::size_t size) { return counted_allocation(size, 0); }
void* operator new(std::size_t size, std::align_val_t a) { return counted_allocation(size, std::size_t(a)); }
void* operator new[](std::size_t size, std::align_val_t a) {
  return counted_allocation(size, std::size_t(a));
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return counted_allocation(size, 0);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return counted_allocation(size, 0);
  } catch (...) {
    return nullptr;
  }
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }

namespace pleat {
namespace {

// ---- Options ----

struct Options {
  std::vector<int> resolutions{55, 173, 548};
  std::vector<ClothKind> kinds{ClothKind::Curtain, ClothKind::Roll};
  int large_repetitions = 2;
  std::vector<int> stage_resolutions{55, 173, 548};
  bool embree = true;
  std::vector<std::string> real{"drape", "pile", "rucked", "layered"};
  std::string data = std::string(PLEAT_BENCH_SOURCE_DIR) + "/data";
};
Options g_options;

constexpr int kFrames = 48;
constexpr std::size_t kFrameIndex =
    12;  // a quarter of the cycle: between rest and deepest folds, moving fastest
constexpr int kRays = 256;
constexpr int kLargeResolution = 200;  // above this, fixed iterations and fewer repetitions

using bench::split;

/// Removes our flags from argv (Google Benchmark rejects unknown ones). Returns false on a bad value.
bool parse_options(int& argc, char** argv) {
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    auto value = [&](const char* name) { return bench::flag_value(argv[i], name); };
    if (const char* v = value("--pleat_resolutions")) {
      g_options.resolutions.clear();
      for (const auto& s : split(v)) g_options.resolutions.push_back(std::stoi(s));
    } else if (const char* v = value("--pleat_kinds")) {
      g_options.kinds.clear();
      for (const auto& s : split(v)) {
        const auto kind = parse_cloth_kind(s);
        if (!kind) {
          std::fprintf(stderr, "static_core_bench: unknown cloth kind '%s'\n", s.c_str());
          return false;
        }
        g_options.kinds.push_back(*kind);
      }
    } else if (const char* v = value("--pleat_large_repetitions")) {
      g_options.large_repetitions = std::stoi(v);
    } else if (const char* v = value("--pleat_stage_resolutions")) {
      g_options.stage_resolutions.clear();
      for (const auto& s : split(v)) g_options.stage_resolutions.push_back(std::stoi(s));
    } else if (const char* v = value("--pleat_embree")) {
      g_options.embree = std::stoi(v) != 0;
    } else if (const char* v = value("--pleat_real")) {
      g_options.real = split(v);
    } else if (const char* v = value("--pleat_data")) {
      g_options.data = v;
    } else {
      argv[kept++] = argv[i];
    }
  }
  argc = kept;
  return true;
}

// ---- Inputs: one mid-motion frame of a generated cloth and its diffuse plan, built once and cached. ----

struct Input {
  ClothGenerator generator;
  Frame frame;
  SlicingPlan plan;
  Input(ClothKind kind, int resolution)
      : generator(kind, GeneratorParams{resolution, kFrames, 24.0, 0}),
        frame(generator.frame(kFrameIndex)),
        plan(make_diffuse_plan(generator.topology(), frame, DiffusePlanParams{})) {}
  const MeshTopology& topology() const { return generator.topology(); }
};

const Input& input(ClothKind kind, int resolution) {
  static std::map<std::pair<int, int>, std::unique_ptr<Input>> cache;
  auto& slot = cache[{static_cast<int>(kind), resolution}];
  if (!slot) slot = std::make_unique<Input>(kind, resolution);
  return *slot;
}

/// One frame's whole slice set with every stage's output kept, so that each stage can be timed alone on
/// the previous stage's results. The per-vertex 2D cones follow compute_visibility's rules (nearest slice
/// vertex per plane and side; vertices without one in an orientation copy their nearest neighbour's).
struct SliceSet {
  const Input* in = nullptr;
  std::unique_ptr<MeshConnectivity> connectivity;
  std::vector<glm::dvec3> normals;
  std::vector<std::vector<Index>> faces;
  std::vector<Slice> slices;
  std::deque<SliceTriangulation> triangulations;  // never moved (not copyable)
  std::vector<SliceCones> cones;
  std::vector<std::vector<PlanarCone>> planar;  // [side * n + v]
  std::size_t slice_vertices = 0;

  explicit SliceSet(const Input& input) : in(&input) {
    const MeshTopology& topology = input.topology();
    const std::size_t n = topology.num_vertices, planes = input.plan.planes.size();
    connectivity = std::make_unique<MeshConnectivity>(topology);
    normals = vertex_normals(topology, input.frame);
    faces = candidate_faces_per_plane(topology, input.frame, input.plan);
    slices.resize(planes);
    triangulations.resize(planes);
    cones.resize(planes);
    SlicerScratch slicer;
    SliceConeScratch scratch;
    for (std::size_t p = 0; p < planes; ++p) {
      slice_mesh(topology, *connectivity, input.frame, input.plan.planes[p], faces[p], slicer, slices[p]);
      triangulations[p].build(slices[p]);
      compute_slice_cones(slices[p], triangulations[p], scratch, cones[p]);
      slice_vertices += slices[p].vertices.size();
    }
    // Store: per plane, side and mesh vertex, the nearest slice vertex (ties: the lower index).
    const std::size_t orientations = input.plan.orientations.size();
    std::vector<std::vector<std::pair<Index, Index>>> stored(2 * orientations * n);  // (plane, slice vertex)
    std::vector<std::int64_t> best(n, -1);
    std::vector<double> best_distance(n);
    for (Index p = 0; p < planes; ++p) {
      const Slice& slice = slices[p];
      std::vector<Index> touched;
      for (Index x = 0; x < slice.vertices.size(); ++x) {
        const SliceVertex& sv = slice.vertices[x];
        if (best[sv.nearer] >= 0 && best_distance[sv.nearer] <= sv.distance) continue;
        if (best[sv.nearer] < 0) touched.push_back(sv.nearer);
        best[sv.nearer] = x;
        best_distance[sv.nearer] = sv.distance;
      }
      const int o = input.plan.planes[p].orientation;
      for (Index v : touched) {
        for (int side = 0; side < 2; ++side)
          stored[(side * orientations + o) * n + v].emplace_back(p, static_cast<Index>(best[v]));
        best[v] = -1;
      }
    }
    // Fill: multi-source Dijkstra along mesh edges per orientation and side.
    std::vector<double> dist(n);
    std::vector<Index> source(n);
    for (std::size_t level = 0; level < 2 * orientations; ++level) {
      auto* refs = &stored[level * n];
      using Item = std::pair<double, Index>;
      std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
      for (Index v = 0; v < n; ++v) {
        dist[v] = refs[v].empty() ? INFINITY : 0.0;
        source[v] = v;
        if (!refs[v].empty()) queue.emplace(0.0, v);
      }
      while (!queue.empty()) {
        const auto [d, v] = queue.top();
        queue.pop();
        if (d > dist[v]) continue;
        for (Index u : connectivity->neighbours(v)) {
          const double du = d + glm::distance(input.frame.positions[u], input.frame.positions[v]);
          if (du < dist[u] || (du == dist[u] && source[v] < source[u])) {
            dist[u] = du;
            source[u] = source[v];
            queue.emplace(du, u);
          }
        }
      }
      for (Index v = 0; v < n; ++v)
        if (refs[v].empty() && std::isfinite(dist[v])) refs[v] = refs[source[v]];
    }
    planar.resize(2 * n);
    for (int side = 0; side < 2; ++side)
      for (std::size_t o = 0; o < orientations; ++o)
        for (Index v = 0; v < n; ++v)
          for (const auto& [p, x] : stored[(side * orientations + o) * n + v])
            planar[side * n + v].push_back(
                {&input.plan.planes[p], cones[p].cone(x, static_cast<Side>(side))});
  }
};

const SliceSet& slice_set(int resolution) {
  static std::map<int, std::unique_ptr<SliceSet>> cache;
  auto& slot = cache[resolution];
  if (!slot) slot = std::make_unique<SliceSet>(input(ClothKind::Curtain, resolution));
  return *slot;
}

// ---- The stages of one frame, each over the whole slice set, single thread. ----

enum class Stage { Setup, Slicing, Triangulation, Cones2d, Assembly3d };
constexpr const char* stage_name(Stage s) {
  switch (s) {
    case Stage::Setup:
      return "setup";
    case Stage::Slicing:
      return "slicing";
    case Stage::Triangulation:
      return "triangulation";
    case Stage::Cones2d:
      return "cones_2d";
    case Stage::Assembly3d:
      return "assembly_3d";
  }
  return "";
}

/// Scratch reused across iterations (as a TBB worker's Workspace is reused across slices).
struct StageScratch {
  SlicerScratch slicer;
  Slice slice;
  SliceTriangulation triangulation;
  SliceConeScratch cones;
  SliceCones cones_out;
  ConeAssemblyScratch assembly;
  std::vector<VisibilityCone> assembled;  // [side * n + v], reused as compute_visibility reuses its result
};

/// Runs one stage once over the whole frame; returns a value to keep the optimiser honest.
double run_stage(Stage stage, const SliceSet& set, StageScratch& s) {
  const Input& in = *set.in;
  const MeshTopology& topology = in.topology();
  double sink = 0.0;
  switch (stage) {
    case Stage::Setup: {  // what compute_visibility does once per frame before the slices
      const auto normals = vertex_normals(topology, in.frame);
      const MeshConnectivity connectivity(topology);
      const auto faces = candidate_faces_per_plane(topology, in.frame, in.plan);
      sink = normals[0].x + double(connectivity.num_edges()) + double(faces[0].size());
      break;
    }
    case Stage::Slicing:
      for (std::size_t p = 0; p < in.plan.planes.size(); ++p) {
        slice_mesh(topology, *set.connectivity, in.frame, in.plan.planes[p], set.faces[p], s.slicer, s.slice);
        sink += double(s.slice.vertices.size());
      }
      break;
    case Stage::Triangulation:
      for (std::size_t p = 0; p < set.slices.size(); ++p) {
        s.triangulation.build(set.slices[p]);
        sink += double(s.triangulation.num_corners());
      }
      break;
    case Stage::Cones2d:
      for (std::size_t p = 0; p < set.slices.size(); ++p) {
        compute_slice_cones(set.slices[p], set.triangulations[p], s.cones, s.cones_out);
        sink += double(s.cones_out.wedges.size());
      }
      break;
    case Stage::Assembly3d: {
      const std::size_t n = topology.num_vertices;
      s.assembled.resize(2 * n);
      for (int side = 0; side < 2; ++side)
        for (std::size_t v = 0; v < n; ++v) {
          const glm::dvec3 side_normal = side_sign(static_cast<Side>(side)) * set.normals[v];
          VisibilityCone& cone = s.assembled[side * n + v];
          assemble_cone(set.planar[side * n + v], side_normal, s.assembly, cone);
          sink += measure_cone(cone, side_normal).sky_visibility;
        }
      break;
    }
  }
  return sink;
}

/// Allocations (operator new calls) of one call of `work`, counted from this thread and any TBB worker.
template <class Work>
std::uint64_t count_allocations(Work&& work) {
  g_allocations.store(0);
  g_counting.store(true);
  work();
  g_counting.store(false);
  return g_allocations.load();
}

void set_slice_counters(benchmark::State& state, const VisibilityStats& stats) {
  state.counters["slices"] = double(stats.slices);
  state.counters["slice_vertices"] = double(stats.slice_vertices);
  // Seconds per slice vertex (the script prints µs): iteration time / slice vertices.
  state.counters["s_per_slice_vertex"] =
      benchmark::Counter(double(stats.slice_vertices),
                         benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["regions_with_holes"] = double(stats.regions_with_holes);
  state.counters["windows"] = double(stats.windows);
  double filled = 0.0;
  for (double f : stats.filled_fraction) filled += f;
  state.counters["filled_fraction"] =
      stats.filled_fraction.empty() ? 0.0 : filled / double(stats.filled_fraction.size());
}

// ---- Benchmarks ----

/// compute_visibility on one frame: threads 1 (sequential path) or 2 (TBB over slices and vertices). The
/// result is reused from one iteration to the next, as a frame loop reuses it (the first call, outside the
/// timing, grows it).
void frame_benchmark(benchmark::State& state, ClothKind kind, int resolution, int threads) {
  const Input& in = input(kind, resolution);
  tbb::global_control control(tbb::global_control::max_allowed_parallelism, threads);
  const VisibilityParams params{threads > 1};
  FrameVisibility result;
  compute_visibility(in.topology(), in.frame, in.plan, params, result);
  for (auto _ : state) {
    compute_visibility(in.topology(), in.frame, in.plan, params, result);
    benchmark::DoNotOptimize(result.measures[0].data());
  }
  state.counters["vertices"] = double(in.topology().num_vertices);
  set_slice_counters(state, result.stats);
}

/// A real Blender sequence's last (most folded) sample with the default plan made on it.
struct RealInput {
  MeshSequence sequence;
  Frame frame;
  SlicingPlan plan;
  explicit RealInput(const std::string& name)
      : sequence(load_sequence(g_options.data + "/" + name + "/" + name + ".obj",
                               g_options.data + "/" + name + "/" + name + ".pc2")),
        frame(sequence.frame(sequence.num_frames() - 1)),
        plan(make_diffuse_plan(sequence.topology(), frame, DiffusePlanParams{})) {}
};

void real_frame_benchmark(benchmark::State& state, std::string name) {
  static std::map<std::string, std::unique_ptr<RealInput>> cache;
  auto& in = cache[name];
  if (!in) in = std::make_unique<RealInput>(name);
  tbb::global_control control(tbb::global_control::max_allowed_parallelism, 1);
  FrameVisibility result;
  compute_visibility(in->sequence.topology(), in->frame, in->plan, {false}, result);
  for (auto _ : state) {
    compute_visibility(in->sequence.topology(), in->frame, in->plan, {false}, result);
    benchmark::DoNotOptimize(result.measures[0].data());
  }
  state.counters["vertices"] = double(in->sequence.topology().num_vertices);
  set_slice_counters(state, result.stats);
}

/// Embree per-vertex ray casting of the same frame: normals, BVH build, 256 rays per vertex and side.
void embree_benchmark(benchmark::State& state, ClothKind kind, int resolution, int threads) {
  const Input& in = input(kind, resolution);
  tbb::global_control control(tbb::global_control::max_allowed_parallelism, threads);
  RayVisibilityParams params;
  params.rays_per_vertex = kRays;
  params.parallel = threads > 1;
  std::uint64_t rays = 0;
  for (auto _ : state) {
    const auto normals = vertex_normals(in.topology(), in.frame);
    EmbreeScene scene(in.topology(), in.frame);
    const RayVisibility result = ray_cast_visibility(scene, in.topology(), in.frame, normals, params);
    benchmark::DoNotOptimize(result.sky_visibility[0].data());
    rays = result.rays_cast;
  }
  state.counters["vertices"] = double(in.topology().num_vertices);
  state.counters["rays_cast"] = double(rays);
  state.counters["rays_per_s"] =
      benchmark::Counter(double(rays), benchmark::Counter::kIsIterationInvariantRate);
}

/// One stage over a curtain frame's whole slice set, one thread.
void stage_benchmark(benchmark::State& state, Stage stage, int resolution) {
  const SliceSet& set = slice_set(resolution);
  tbb::global_control control(tbb::global_control::max_allowed_parallelism, 1);
  StageScratch scratch;
  run_stage(stage, set, scratch);  // warm the scratch, as a worker's is after its first slice
  for (auto _ : state) benchmark::DoNotOptimize(run_stage(stage, set, scratch));
  state.counters["slices"] = double(set.slices.size());
  state.counters["slice_vertices"] = double(set.slice_vertices);
  state.counters["s_per_slice_vertex"] =
      benchmark::Counter(double(set.slice_vertices),
                         benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

/// Allocations per slice vertex: each stage (warm scratch) and the whole compute_visibility, one thread.
void allocation_benchmark(benchmark::State& state, int resolution) {
  const SliceSet& set = slice_set(resolution);
  tbb::global_control control(tbb::global_control::max_allowed_parallelism, 1);
  StageScratch scratch;
  for (auto _ : state) {
    for (Stage stage :
         {Stage::Setup, Stage::Slicing, Stage::Triangulation, Stage::Cones2d, Stage::Assembly3d}) {
      run_stage(stage, set, scratch);  // warm
      const std::uint64_t count = count_allocations([&] { run_stage(stage, set, scratch); });
      state.counters[std::string("allocs_per_sv_") + stage_name(stage)] =
          double(count) / double(set.slice_vertices);
    }
    // The whole frame into a reused result (the second of two calls), and one-shot into a fresh one.
    const Input& in = *set.in;
    FrameVisibility result;
    compute_visibility(in.topology(), in.frame, in.plan, {false}, result);
    std::uint64_t count =
        count_allocations([&] { compute_visibility(in.topology(), in.frame, in.plan, {false}, result); });
    state.counters["allocs_per_sv_frame"] = double(count) / double(set.slice_vertices);
    count = count_allocations([&] {
      benchmark::DoNotOptimize(
          compute_visibility(in.topology(), in.frame, in.plan, {false}).measures[0].data());
    });
    state.counters["allocs_per_sv_frame_one_shot"] = double(count) / double(set.slice_vertices);
  }
  state.counters["slice_vertices"] = double(set.slice_vertices);
}

std::string size_label(int resolution) { return std::to_string(cloth_vertex_count(resolution)); }

void register_benchmarks() {
  for (const std::string& name : g_options.real)
    benchmark::RegisterBenchmark(("frame/real/" + name + "/threads:1").c_str(), real_frame_benchmark, name)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        ->MeasureProcessCPUTime();
  for (ClothKind kind : g_options.kinds)
    for (int resolution : g_options.resolutions) {
      const bool large = resolution > kLargeResolution;
      for (int threads : {1, 2}) {
        const std::string suffix = std::string(cloth_kind_name(kind)) + "/" + size_label(resolution) +
                                   "/threads:" + std::to_string(threads);
        auto* frame = benchmark::RegisterBenchmark(("frame/" + suffix).c_str(), frame_benchmark, kind,
                                                   resolution, threads);
        frame->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();
        if (large) frame->Iterations(1)->Repetitions(g_options.large_repetitions);
        if (!g_options.embree) continue;
        auto* rays = benchmark::RegisterBenchmark(("embree_256/" + suffix).c_str(), embree_benchmark, kind,
                                                  resolution, threads);
        rays->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();
        if (large) rays->Iterations(1)->Repetitions(1);
      }
    }
  for (int resolution : g_options.stage_resolutions) {
    const std::string suffix = "/curtain/" + size_label(resolution) + "/threads:1";
    for (Stage stage :
         {Stage::Setup, Stage::Slicing, Stage::Triangulation, Stage::Cones2d, Stage::Assembly3d}) {
      auto* b = benchmark::RegisterBenchmark((std::string("stage/") + stage_name(stage) + suffix).c_str(),
                                             stage_benchmark, stage, resolution);
      b->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();
      if (resolution > kLargeResolution) b->Iterations(1)->Repetitions(1);
    }
    if (resolution <= kLargeResolution)
      benchmark::RegisterBenchmark(("allocations" + suffix).c_str(), allocation_benchmark, resolution)
          ->Iterations(1)
          ->Repetitions(1);
  }
}

}  // namespace
}  // namespace pleat

int main(int argc, char** argv) {
  if (!pleat::parse_options(argc, argv)) return 2;
  pleat::register_benchmarks();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 2;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
