// Embree ray casting as the benchmark's peer: its configuration sweep, its timed runs and the reference.
#include "bench/coherence/peer.hpp"

#include <tbb/global_control.h>

#include <algorithm>
#include <memory>

#include "bench/coherence/memory_window.hpp"
#include "bench/coherence/stopwatch.hpp"
#include "shading/ray_visibility.hpp"
#include "static_core/visibility.hpp"

namespace pleat::bench {

namespace {

constexpr std::uint64_t kMethodSeed = 7;
constexpr std::uint64_t kReferenceSeed = 0x5eed4096;

SkyValues sky_of(const std::array<std::vector<double>, 2>& r) {
  SkyValues a(r[0]);
  a.insert(a.end(), r[1].begin(), r[1].end());
  return a;
}

}  // namespace

std::string describe(const EmbreeSceneParams& p) {
  std::string s = p.mode == EmbreeSceneParams::BuildMode::Refit ? "refit" : "rebuild";
  s += std::string(" + ") + ray_call_name(p.ray_call);
  if (p.coherent) s += " + coherent";
  s += p.robust ? " + robust" : " + non-robust";
  return s;
}

MethodRow run_embree(const MeshTopology& topology, const std::vector<Frame>& frames,
                     const EmbreeSceneParams& config, int rays, bool random_directions, int threads,
                     bool keep_sky) {
  MethodRow row;
  row.method = random_directions ? "embree-random" : "embree";
  row.rays = rays;
  row.threads = threads;
  row.config = describe(config);
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
  row.peak_reset = start_memory_window(row.rss_before_mb);
  try {
    RayVisibilityParams params;
    params.rays_per_vertex = rays;
    std::unique_ptr<EmbreeScene> scene;
    for (std::size_t k = 0; k < frames.size(); ++k) {
      params.seed = random_directions ? kMethodSeed + k : kMethodSeed;
      const Stopwatch watch;
      if (!scene) scene = std::make_unique<EmbreeScene>(topology, frames[k], config);
      auto normals = vertex_normals(topology, frames[k]);
      normals.resize(topology.num_receivers());  // rays from the cloth only: occluders block
      auto a = ray_cast_sky_visibility(*scene, topology, frames[k], normals, params);
      if (k == 0) {
        row.ms_first = watch.wall_ms();
        continue;
      }
      row.ms.push_back(watch.wall_ms());
      row.cpu_ms.push_back(watch.process_cpu_ms());
      if (keep_sky) row.sky.push_back(sky_of(a));
    }
  } catch (const std::exception& e) {
    row.status = std::string("error: ") + e.what();
  }
  row.peak_mb = status_mb("VmHWM");
  return row;
}

EmbreeSceneParams fastest_peer(const MeshTopology& topology, const std::vector<Frame>& frames, int rays,
                               std::vector<PeerTrial>& trials) {
  trials.clear();
  EmbreeSceneParams best;
  double best_ms = INFINITY;
  auto attempt = [&](const EmbreeSceneParams& p) {
    const MethodRow r = run_embree(topology, frames, p, rays, false, 1, false);
    if (!r.ok()) return;
    trials.push_back({describe(p), r.ms_per_frame()});
    if (r.ms_per_frame() < best_ms) best_ms = r.ms_per_frame(), best = p;
  };
  using C = EmbreeSceneParams::RayCall;
  for (C call : {C::Stream, C::Packet4, C::Packet8, C::Packet16, C::Single}) {
    EmbreeSceneParams p;
    p.ray_call = call;
    attempt(p);
  }
  for (auto change :
       {+[](EmbreeSceneParams& p) { p.coherent = true; }, +[](EmbreeSceneParams& p) { p.robust = false; },
        +[](EmbreeSceneParams& p) { p.mode = EmbreeSceneParams::BuildMode::Rebuild; }}) {
    EmbreeSceneParams p = best;
    change(p);
    attempt(p);
  }
  std::stable_sort(trials.begin(), trials.end(),
                   [](const PeerTrial& a, const PeerTrial& b) { return a.ms < b.ms; });
  return best;
}

std::vector<SkyValues> reference_sky(const MeshTopology& topology, const std::vector<Frame>& frames, int rays,
                                     Index stride) {
  std::vector<SkyValues> out;
  RayVisibilityParams params;
  params.rays_per_vertex = rays;
  params.seed = kReferenceSeed;
  params.vertex_stride = stride;
  std::unique_ptr<EmbreeScene> scene;
  for (std::size_t k = 1; k < frames.size(); ++k) {
    if (!scene) scene = std::make_unique<EmbreeScene>(topology, frames[k]);
    auto normals = vertex_normals(topology, frames[k]);
    normals.resize(topology.num_receivers());  // rays from the cloth only: occluders block
    out.push_back(sky_of(ray_cast_sky_visibility(*scene, topology, frames[k], normals, params)));
  }
  return out;
}

}  // namespace pleat::bench
