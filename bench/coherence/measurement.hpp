// What the frame-coherence benchmark measures: one Measurement per sequence x size x temporal resolution,
// holding a MethodRow per method (static, kinetic, Embree at each ray count) and thread count.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "bench/coherence/matched_error.hpp"
#include "kinetic/kinetic_visibility.hpp"

namespace pleat::bench {

inline double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

/// The kinetic engine's counters summed over the timed frames.
struct KineticTotals {
  KineticFrameStats sum;
  int frames = 0;

  void add(const KineticFrameStats& s) {
    sum += s;
    ++frames;
  }
  double per_frame(std::size_t total) const { return frames ? double(total) / frames : NAN; }
};

struct MethodRow {
  std::string method;  ///< "static", "kinetic", "paper", "plan", "embree" (fixed directions), "embree-random"
  int rays = 0;        ///< Embree's rays per vertex and side
  int threads = 1;
  std::string
      config;  ///< how the method was configured (Embree: BVH update, ray call, flags; "plan": its name)
  std::vector<double> ms;      ///< wall time per timed frame (frames 1..N-1)
  std::vector<double> cpu_ms;  ///< process CPU time per timed frame (the one-core cost at 1 thread)
  double ms_first = NAN;       ///< frame 0 (construction / BVH build / warm-up)
  std::vector<SkyValues> sky;  ///< per timed frame, when accuracy is measured
  ErrorStats err;
  double flicker = NAN;
  double peak_mb = NAN, rss_before_mb = NAN;
  bool peak_reset = false;
  double slice_vertices = NAN;  ///< per frame, mean over the timed frames
  std::optional<KineticTotals> kinetic;
  std::string status = "ok";

  double ms_per_frame() const { return median(ms); }
  double cpu_ms_per_frame() const { return median(cpu_ms); }
  bool ok() const { return status == "ok"; }
  bool measured_accuracy() const { return err.count > 0; }
};

struct PeerTrial {
  std::string config;
  double ms = NAN;  ///< median CPU time per frame at Options::sweep_rays, one thread (least of its runs)
};

struct Measurement {
  std::string sequence;
  bool real = false;
  Index vertices = 0;
  std::size_t triangles = 0;
  double upsample = 1;
  int frames = 0;
  std::size_t planes = 0;
  std::vector<MethodRow> rows;
  std::vector<PeerTrial> peer_sweep;  ///< the Embree configurations tried (u = 1), fastest first
  Index reference_stride = 0;         ///< 0: no reference (accuracy not measured at this u)
  double max_static_kinetic = NAN;    ///< max |A_static − A_kinetic| over the frames compared
  /// Static ÷ Embree at round(K*) (mean error), one thread, the two timed in turn in this process: per round
  /// the ratio of their median CPU times per frame (empty: not measured). The other ratios compare times
  /// taken minutes apart, under whatever load the shared machine has at each.
  int alternated_rays = 0;
  std::vector<double> alternated_ratios;

  const MethodRow* row(const std::string& method, int threads = 1, int rays = 0) const {
    for (const auto& r : rows)
      if (r.method == method && r.threads == threads && r.rays == rays) return &r;
    return nullptr;
  }
  /// The static engine's rows on other plans (Options::plans), in the order given.
  std::vector<const MethodRow*> plans() const {
    std::vector<const MethodRow*> p;
    for (const auto& r : rows)
      if (r.method == "plan") p.push_back(&r);
    return p;
  }
  /// Embree's fixed-direction rows at `threads`, by ascending ray count.
  std::vector<const MethodRow*> ladder(int threads) const {
    std::vector<const MethodRow*> l;
    for (const auto& r : rows)
      if (r.method == "embree" && r.threads == threads && r.ok()) l.push_back(&r);
    std::sort(l.begin(), l.end(), [](auto* a, auto* b) { return a->rays < b->rays; });
    return l;
  }
};

}  // namespace pleat::bench
