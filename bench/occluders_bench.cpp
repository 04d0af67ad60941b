// The cloth in its scene (issue: occluders): on every bundled real sequence with the colliders it was
// simulated against (data/README.md), at its last frame, the cones' error against ray-traced truth *of the
// scene* (4096 cosine-weighted rays per vertex and side, occluders and ground included), with the occluders
// given and without them (the cloth alone, as pleat answered before); and what the occluders cost: a static
// frame's CPU time with and without them, alternated, medians, one thread.
//
// Usage: occluders_bench [--rays=4096] [--repeat=7] [--sequences=drape,pile,rucked,layered] [--body=OBJ]
// Prints a markdown table (bench/run_occluders.sh writes it to bench/results/occluders.md).
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <string>
#include <vector>

#include "bench/bench_args.hpp"
#include "shading/embree_scene.hpp"
#include "shading/ray_visibility.hpp"
#include "sim_io/scene.hpp"
#include "static_core/visibility.hpp"

namespace {

using namespace pleat;

struct Errors {
  double mean = 0.0, p95 = 0.0;
};

Errors errors(const FrameVisibility& cones, const std::array<std::vector<double>, 2>& truth) {
  std::vector<double> e;
  for (Side side : kBothSides)
    for (std::size_t v = 0; v < truth[0].size(); ++v)
      e.push_back(std::abs(cones.measure(side, Index(v)).sky_visibility - truth[int(side)][v]));
  Errors out;
  for (double x : e) out.mean += x;
  out.mean /= double(e.size());
  std::sort(e.begin(), e.end());
  out.p95 = e[std::size_t(0.95 * double(e.size() - 1))];
  return out;
}

double cpu_seconds() { return double(std::clock()) / CLOCKS_PER_SEC; }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  int rays = 4096, repeat = 7;
  std::vector<std::string> names = {"drape", "pile", "rucked", "layered"};
  std::string body;
  for (int i = 1; i < argc; ++i) {
    if (const char* v = bench::flag_value(argv[i], "--rays")) rays = std::stoi(v);
    if (const char* v = bench::flag_value(argv[i], "--repeat")) repeat = std::stoi(v);
    if (const char* v = bench::flag_value(argv[i], "--sequences")) names = bench::split(v);
    if (const char* v = bench::flag_value(argv[i], "--body")) body = v;
  }
  const tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  const std::filesystem::path data = std::filesystem::path(PLEAT_BENCH_SOURCE_DIR) / "data";
  std::printf(
      "| sequence | colliders | mean, cloth alone | p95, cloth alone | mean, in its scene | p95, in its "
      "scene |"
      " frame ms, cloth alone | frame ms, in its scene | ratio "
      "|\n|---|---|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const std::string& name : names) {
    const std::filesystem::path dir = data / name;
    const MeshSequence cloth = load_sequence(dir / (name + ".obj"), dir / (name + ".pc2"));
    std::vector<OccluderSpec> occluders;
    std::string described;
    if (std::filesystem::exists(dir / (name + "_colliders.obj"))) {
      OccluderSpec spec{(dir / (name + "_colliders.obj")).string(), {}};
      if (std::filesystem::exists(dir / (name + "_colliders.pc2")))
        spec.cache = (dir / (name + "_colliders.pc2")).string();
      occluders.push_back(spec);
      described = name + "_colliders" + (spec.cache.empty() ? " (static)" : " (animated)");
    }
    if (!body.empty() && name == "rucked") {
      occluders.push_back({body, {}});
      described += " + body";
    }
    std::vector<GroundPlane> grounds;
    if (name != "rucked") {  // the rucked sleeve was simulated without a ground (data/README.md)
      grounds.push_back(parse_ground_plane("y=0"));
      described += described.empty() ? "ground y=0" : ", ground y=0";
    }
    const Scene alone(cloth), scene(cloth, occluders, grounds);
    const std::size_t f = cloth.num_frames() - 1;
    const SlicingPlan plan = make_diffuse_plan(cloth.topology(), cloth.frame(0), {}, &cloth.bounds());
    const Frame cloth_frame = alone.frame(f), scene_frame = scene.frame(f);
    VisibilityParams serial{false};
    const FrameVisibility without = compute_visibility(alone.topology(), cloth_frame, plan, serial);
    const FrameVisibility with = compute_visibility(scene.topology(), scene_frame, plan, serial);
    EmbreeScene embree(scene.topology(), scene_frame);
    RayVisibilityParams params;
    params.rays_per_vertex = rays;
    params.parallel = false;
    const auto truth = ray_cast_sky_visibility(embree, scene.topology(), scene_frame, with.normals, params);
    const Errors before = errors(without, truth), after = errors(with, truth);
    // Cost: the static engine's frame, alternated (cloth alone, then in its scene), CPU seconds.
    StaticVisibility engine_alone(alone.topology(), plan, serial),
        engine_scene(scene.topology(), plan, serial);
    std::vector<double> t_alone, t_scene;
    for (int r = 0; r < repeat; ++r) {
      double t0 = cpu_seconds();
      engine_alone.compute(cloth_frame);
      t_alone.push_back(cpu_seconds() - t0);
      t0 = cpu_seconds();
      engine_scene.compute(scene_frame);
      t_scene.push_back(cpu_seconds() - t0);
    }
    const double a = median(t_alone) * 1e3, s = median(t_scene) * 1e3;
    std::printf("| %s (frame %zu, %u vertices) | %s | %.4f | %.4f | %.4f | %.4f | %.1f | %.1f | %.2f |\n",
                name.c_str(), f, cloth.topology().num_vertices, described.c_str(), before.mean, before.p95,
                after.mean, after.p95, a, s, s / a);
    std::fflush(stdout);
  }
  return 0;
}
