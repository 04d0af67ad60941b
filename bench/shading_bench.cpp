// Speed of the shading pass (docs/method.md §10; issue 4, "Speed"): Google Benchmark timings of shade_frame
// per light type — uniform sky, cloudy sky, directional, point, area, environment map — on one frame of the
// generated curtain at 3k and 300k vertices, one thread and two, against the time to compute that frame's
// cones (compute_visibility) in the same process. The cones are computed once per resolution, outside
// every timed loop: a new light costs only the shading pass (the paper's point; Stewart 1999 reports
// 1.5 s for the hemispheric sky on 2,964 points at 300 MHz; the target is < 1 ms for 3k + sky).
//
// Rows: shade/<light>/<vertices>/threads:<k> and cones/<vertices>/threads:<k>, wall-clock ms per frame
// (UseRealTime); with --benchmark_repetitions=N the median row is the one to quote. Threads: "threads:1"
// runs the sequential path (params.parallel = false) under a tbb::global_control of one thread; "threads:2"
// runs the TBB path under a control of two. Counters: cone edges per vertex and side (mean), vertices.
//
// Flags of ours (before Google Benchmark's own):
//   --pleat_resolutions=55,548   curtain grid resolutions (55 -> 3,025 vertices, 548 -> 300,304)
//   --pleat_frame=20             the frame of the 60-frame curtain to shade
//   --pleat_cones=1              0 skips the compute_visibility rows
//   --pleat_large_repetitions=3  repetitions of the rows above 200 of resolution (the rest: --benchmark_*)
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <glm/geometric.hpp>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "bench/bench_args.hpp"
#include "shading/environment_map.hpp"
#include "shading/lights.hpp"
#include "shading/shade.hpp"
#include "sim_io/cloth_generators.hpp"
#include "static_core/slicing_plan.hpp"
#include "static_core/visibility.hpp"

namespace {

using namespace pleat;

std::vector<int> g_resolutions = {55, 548};
int g_frame = 20;
bool g_cones = true;
int g_large_repetitions = 3;

struct Prepared {
  MeshTopology topology;
  Frame frame;
  SlicingPlan plan;
  FrameVisibility visibility;
  double mean_edges = 0.0;  // cone edges per vertex and side
};

/// One generated curtain frame and its cones per resolution, made on first use (outside timed loops).
const Prepared& prepared(int resolution) {
  static std::map<int, std::unique_ptr<Prepared>> cache;
  auto& slot = cache[resolution];
  if (!slot) {
    GeneratorParams params;
    params.resolution = resolution;
    params.frames = 60;
    const ClothGenerator generator(ClothKind::Curtain, params);
    slot = std::make_unique<Prepared>();
    slot->topology = generator.topology();
    slot->frame = generator.frame(static_cast<std::size_t>(g_frame) % generator.num_frames());
    slot->plan = make_diffuse_plan(slot->topology, slot->frame, {});
    slot->visibility = compute_visibility(slot->topology, slot->frame, slot->plan);
    std::size_t edges = 0;
    for (int s = 0; s < 2; ++s)
      for (const VisibilityCone& cone : slot->visibility.cones[s])
        for (const SphericalPolygon& piece : cone.pieces) edges += piece.size();
    slot->mean_edges = double(edges) / (2.0 * double(slot->topology.num_vertices));
  }
  return *slot;
}

/// An in-memory sky-like environment (no file needed): a blue-to-white gradient about +y with a warm sun
/// patch, 512 x 256 texels (the size a user would load with maxres=512).
EnvironmentMap synthetic_environment() {
  const int w = 512, h = 256;
  std::vector<glm::vec3> texels(static_cast<std::size_t>(w) * h);
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) {
      const float elevation = 1.0f - 2.0f * (r + 0.5f) / h;  // +1 at the top row
      glm::vec3 colour = elevation > 0
                             ? glm::mix(glm::vec3(0.9f, 0.95f, 1.0f), glm::vec3(0.3f, 0.5f, 1.0f), elevation)
                             : glm::vec3(0.25f, 0.22f, 0.2f);
      if (std::abs(c - w / 4) < 8 && std::abs(r - h / 4) < 8) colour = glm::vec3(40.0f, 36.0f, 30.0f);
      texels[static_cast<std::size_t>(r) * w + c] = colour;
    }
  return EnvironmentMap(w, h, std::move(texels), {{0.0, 1.0, 0.0}, 0.0});
}

/// The light setups, in the curtain's frame (Y up, the cloth spans x in [-1, 1], y in [-2.4, 0], faces +-z).
std::vector<std::pair<std::string, Lighting>> light_setups() {
  std::vector<std::pair<std::string, Lighting>> out;
  auto spec = [&](const std::string& name, const std::string& text) {
    Lighting lighting;
    add_light_spec(lighting, text);
    out.emplace_back(name, std::move(lighting));
  };
  spec("sky", "sky:1");
  spec("cloudy", "cloudy:1,up=0,1,0");
  spec("directional", "dir:0.3,-0.5,-1,E=3");
  spec("point", "point:0.3,-0.8,1.2,I=3");
  spec("area", "area:-0.5,-1.5,2;0.5,-1.5,2;0.5,-0.5,2;-0.5,-0.5,2,L=4");
  Lighting env;
  EnvironmentLight light;
  light.map = synthetic_environment();
  light.file = "synthetic";
  env.lights.push_back(std::move(light));
  out.emplace_back("env", std::move(env));
  return out;
}

void bm_shade(benchmark::State& state, int resolution, const Lighting* lighting, int threads) {
  const Prepared& p = prepared(resolution);
  tbb::global_control control(tbb::global_control::max_allowed_parallelism, threads);
  ShadeParams params;
  params.parallel = threads > 1;
  ShadedFrame out;
  for (auto _ : state) {
    shade_frame(p.topology, p.frame, p.visibility, *lighting, params, out);
    benchmark::DoNotOptimize(out.radiance[0].data());
    benchmark::ClobberMemory();
  }
  state.counters["vertices"] = double(p.topology.num_vertices);
  state.counters["edges_per_cone"] = p.mean_edges;
}

void bm_cones(benchmark::State& state, int resolution, int threads) {
  const Prepared& p = prepared(resolution);
  tbb::global_control control(tbb::global_control::max_allowed_parallelism, threads);
  VisibilityParams params;
  params.parallel = threads > 1;
  for (auto _ : state) {
    FrameVisibility visibility = compute_visibility(p.topology, p.frame, p.plan, params);
    benchmark::DoNotOptimize(visibility.cones[0].data());
  }
  state.counters["vertices"] = double(p.topology.num_vertices);
  state.counters["edges_per_cone"] = p.mean_edges;
}

std::vector<int> parse_list(const char* text) {
  std::vector<int> out;
  std::stringstream s(text);
  for (std::string item; std::getline(s, item, ',');) out.push_back(std::atoi(item.c_str()));
  return out;
}

/// Consumes our --pleat_* flags, leaving Google Benchmark's.
void parse_own_flags(int& argc, char** argv) {
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    const char* a = argv[i];
    auto value = [&](const char* name) { return bench::flag_value(a, name); };
    if (const char* v = value("--pleat_resolutions"))
      g_resolutions = parse_list(v);
    else if (const char* v = value("--pleat_frame"))
      g_frame = std::atoi(v);
    else if (const char* v = value("--pleat_cones"))
      g_cones = std::atoi(v) != 0;
    else if (const char* v = value("--pleat_large_repetitions"))
      g_large_repetitions = std::atoi(v);
    else
      argv[kept++] = argv[i];
  }
  argc = kept;
}

}  // namespace

int main(int argc, char** argv) {
  parse_own_flags(argc, argv);
  static const std::vector<std::pair<std::string, Lighting>> setups = light_setups();
  for (int resolution : g_resolutions) {
    const std::string vertices = std::to_string(cloth_vertex_count(resolution));
    const bool large = resolution > 200;
    for (int threads : {1, 2}) {
      for (const auto& [name, lighting] : setups) {
        auto* b = benchmark::RegisterBenchmark(
            ("shade/" + name + "/" + vertices + "/threads:" + std::to_string(threads)).c_str(), bm_shade,
            resolution, &lighting, threads);
        b->UseRealTime()->Unit(benchmark::kMillisecond);
        if (large) b->Repetitions(g_large_repetitions)->Iterations(1);
      }
      if (g_cones) {
        auto* b = benchmark::RegisterBenchmark(
            ("cones/" + vertices + "/threads:" + std::to_string(threads)).c_str(), bm_cones, resolution,
            threads);
        b->UseRealTime()->Unit(benchmark::kMillisecond);
        if (large) b->Repetitions(g_large_repetitions)->Iterations(1);
      }
    }
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
