// The cloth in its scene (issue: occluders): on every bundled real sequence with the colliders it was
// simulated against (data/README.md), at its last frame, the cones' error against ray-traced truth *of the
// scene* (4096 cosine-weighted rays per vertex and side, occluders and ground included), with the occluders
// given and without them (the cloth alone, as pleat answered before); and what the occluders cost: a frame's
// CPU time with and without them, each engine, over the last frames, alternated, medians, one thread.
//
// Usage: occluders_bench [--rays=4096] [--repeat=10] [--sequences=drape,pile,rucked,layered] [--body=OBJ]
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
#include "kinetic/kinetic_visibility.hpp"
#include "shading/embree_scene.hpp"
#include "shading/ray_visibility.hpp"
#include "sim_io/load_sequence.hpp"
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
  int rays = 4096, repeat = 10;
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
      " static ms: alone / in scene (ratio) | kinetic ms: alone / in scene (ratio) |\n"
      "|---|---|---:|---:|---:|---:|---:|---:|\n");
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
    // Cost: a frame of each engine over the last `repeat` frames, cloth alone and in its scene alternated
    // frame by frame (CPU seconds; the kinetic engines built on the frame before, not counted).
    const std::size_t from = f + 1 - std::min<std::size_t>(std::size_t(repeat), f);
    StaticVisibility static_alone(alone.topology(), plan, serial),
        static_scene(scene.topology(), plan, serial);
    KineticParams kinetic_params;
    kinetic_params.parallel = false;
    KineticVisibility kinetic_alone(alone.topology(), plan, alone.frame(from - 1), kinetic_params);
    KineticVisibility kinetic_scene(scene.topology(), plan, scene.frame(from - 1), kinetic_params);
    std::vector<double> t[4];
    for (std::size_t g = from; g <= f; ++g) {
      const Frame a = alone.frame(g), b = scene.frame(g);
      double t0 = cpu_seconds();
      static_alone.compute(a);
      t[0].push_back(cpu_seconds() - t0);
      t0 = cpu_seconds();
      static_scene.compute(b);
      t[1].push_back(cpu_seconds() - t0);
      t0 = cpu_seconds();
      kinetic_alone.advance(a);
      t[2].push_back(cpu_seconds() - t0);
      t0 = cpu_seconds();
      kinetic_scene.advance(b);
      t[3].push_back(cpu_seconds() - t0);
    }
    double ms[4];
    for (int k = 0; k < 4; ++k) ms[k] = median(t[k]) * 1e3;
    std::printf(
        "| %s (frame %zu, %u vertices) | %s | %.4f | %.4f | %.4f | %.4f | %.1f / %.1f (%.2f) | %.1f / %.1f "
        "(%.2f) |\n",
        name.c_str(), f, cloth.topology().num_vertices, described.c_str(), before.mean, before.p95,
        after.mean, after.p95, ms[0], ms[1], ms[1] / ms[0], ms[2], ms[3], ms[3] / ms[2]);
    std::fflush(stdout);
  }
  return 0;
}
