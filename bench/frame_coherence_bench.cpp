// The frame-coherence benchmark: pleat's cone engines against each other and against ray casting at its best.
//
// For each cloth sequence x size x temporal resolution u, on the same frames (bench/coherence/sequences.hpp):
//   static   StaticVisibility::compute, a full recompute of every frame;
//   kinetic  KineticVisibility::advance (constructed on the first frame), which keeps every slice alive;
// both in a watched child process, frame by frame in turn (bench/coherence/cone_worker.hpp), at one thread
// for every u and, at u = 1, also at each thread count of --threads. At u = 1 only (Embree's cost and
// accuracy do not depend on u):
//   embree   Embree per-vertex ray casting (bench/coherence/peer.hpp) in its fastest measured configuration,
//            over a ladder of ray counts per vertex and side, with fixed directions, at each thread count;
//   embree-random  the same at --random-rays rays with new directions every frame (the flicker a naive loop
//   has); reference      --reference-rays rays on every timed frame (untimed), for error and flicker of every
//   method;
// and the matched-error comparison (bench/coherence/matched_error.hpp): K*, Embree's time at K*, and
// pleat ÷ Embree(K*) for both engines, by mean and by 95th-percentile error; then, once K* is known, the
// static engine and Embree at round(K*) rays timed in turn in this process, three rounds at one thread (the
// ladder's times are taken minutes after the engine's, under whatever load the shared machine then has).
// Static and kinetic must agree to 1e-9 on every frame where accuracy is measured, and so must a --plans row
// naming the default plan (or the paper's) and the static (paper) row.
// Outputs (bench/coherence/report.hpp): DIR/frame_coherence.csv, DIR/frame_coherence.md and
// DIR/frame_coherence_headline.md (bench/run_frame_coherence.sh puts the latter into docs/benchmarks.md);
// with --plans, the markdown's "Plans" tables and a "frame_coherence: plan ..." line per plan row on stdout
// (bench/run_error_cost.sh).
//
// Flags (all optional):
//   --quick                  curtain 3025, u = 1 and 2, 3 frames, rays 8,16,64, reference 512 (the test
//   suite's run)
//   --out DIR                output directory (default bench/results)
//   --sequences a,b,...      default: every real sequence in data/ (drape first), then
//   curtain,roll,flag,sleeve
//   --sizes n,...            vertex counts of generated kinds: 3025, 29929, 300304 (default 3025,29929)
//   --upsample u,...         default 0.5,1,2,4,8
//   --frames N               frames per measurement (default 8; the first is not timed)
//   --large-frames N         frames per measurement above 10,000 vertices (default 4; 0: --frames)
//   --large-upsample u,...   temporal resolutions above 10,000 vertices (default: --upsample)
//   --rays K,...             Embree's ladder, ascending (default 8,12,16,24,32,48,64,96,128,256,1024)
//   --threads T,...          thread counts at u = 1 (default 1,2; every u runs at the first)
//   --sweep-rays K           rays of the peer-configuration sweep (default 32)
//   --random-rays K          rays of the new-directions-each-frame row (default 16; 0: none)
//   --reference-rays K       default 4096
//   --reference-sample N     the reference estimates every k-th vertex, k = ceil(vertices / N) (default 4000)
//   --data DIR               the repository's data/ (default: the data/ of the source tree it was built from)
//   --cloth-alone            real sequences without their colliders (default: in the scene they were
//                            simulated in, data/README.md; every method, the reference included, sees it)
//   --kinetic-timeout S      seconds without progress before the cone engines' process is declared hung
//   --plans o:s:storage,...  at u = 1 and the first thread count, a "plan" row per plan: the static engine on
//                            o orientations s average edges apart with that storage rule (plan_setting.hpp;
//                            e.g. 12:0.5:aimed-on-fan), on the same frames and reference as the other rows,
//                            with its own K* and pleat ÷ Embree(K*) (default: none)
//   --vertex-errors          also write, per measurement at u = 1, every value the reference estimates:
//                            frame_coherence_errors_<sequence>_<vertices>.csv in --out (frame, vertex, side,
//                            position, the static engine's A and the reference's), for
//                            bench/plot_vertex_errors.py: where the error is, not only how large
// Exit status 1 and "frame_coherence: FAILED: ..." lines when any method failed or static and kinetic differ.
// Plain executable: no Google Benchmark main.
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "bench/bench_args.hpp"
#include "bench/coherence/cone_worker.hpp"
#include "bench/coherence/memory_window.hpp"
#include "bench/coherence/options.hpp"
#include "bench/coherence/peer.hpp"
#include "bench/coherence/report.hpp"
#include "bench/coherence/sequences.hpp"
#include "bench/coherence/stopwatch.hpp"
#include "sim_io/cloth_generators.hpp"
#include "static_core/slicing_plan.hpp"

namespace pleat::bench {
namespace {

namespace fs = std::filesystem;

constexpr Index kLargeVertices = 10000;
constexpr double kEqualTolerance = 1e-9;
constexpr int kAlternatedRounds = 3;  ///< rounds of the static engine and Embree(K*) timed in turn

/// max |a − b| over every frame and value; infinite when the shapes differ.
double max_difference(const std::vector<SkyValues>& a, const std::vector<SkyValues>& b) {
  if (a.size() != b.size()) return INFINITY;
  double worst = 0;
  for (std::size_t f = 0; f < a.size(); ++f) {
    if (a[f].size() != b[f].size()) return INFINITY;
    for (std::size_t i = 0; i < a[f].size(); ++i) worst = std::max(worst, std::abs(a[f][i] - b[f][i]));
  }
  return worst;
}

struct Run {
  const Options& options;
  std::vector<std::string> failures;

  void progress(const Measurement& m, const std::string& text) const {
    std::fprintf(stderr, "[frame_coherence] %s %u u=%g: %s\n", m.sequence.c_str(), m.vertices, m.upsample,
                 text.c_str());
  }
  void fail(const Measurement& m, const std::string& what) {
    failures.push_back(format("%s %u u=%g: ", m.sequence.c_str(), m.vertices, m.upsample) + what);
    progress(m, "FAILED: " + what);
  }

  /// Static and kinetic at `threads`, in the child process (the static engine alone here if it fails).
  void cone_engines(Measurement& m, const Sequence& seq, const SlicingPlan& plan,
                    const std::vector<Frame>& frames, int threads, bool keep_sky) {
    auto child = run_cone_engines_in_child(seq.name, seq.size, m.vertices, m.upsample, m.frames, threads,
                                           keep_sky, options);
    MethodRow s, k;
    if (auto* rows = std::get_if<std::vector<MethodRow>>(&child)) {
      s = std::move((*rows)[0]);
      k = std::move((*rows)[1]);
      for (std::size_t i = 2; i < rows->size(); ++i) {  // the paper's plan and --plans
        MethodRow& row = (*rows)[i];
        if (!row.ok())
          fail(m, row.method + (row.config.empty() ? "" : " " + row.config) + ": " + row.status);
        else if (row.method == "plan")
          progress(m, format("plan %s: %.1f CPU ms/frame", row.config.c_str(), row.cpu_ms_per_frame()));
        m.rows.push_back(std::move(row));
      }
    } else {
      const std::string why = std::get<std::string>(child);
      progress(m, "the cone engines' process failed (" + why + "); the static engine runs alone");
      k.method = "kinetic";
      k.threads = threads;
      k.status = why;
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
      s = run_static(seq.topology, plan, frames, keep_sky);
      s.threads = threads;
    }
    if (!s.ok()) fail(m, "static: " + s.status);
    if (!k.ok()) fail(m, "kinetic: " + k.status);
    progress(m, format("%d thread(s): static %.1f ms/frame, kinetic %.1f ms/frame (construction %.1f)",
                       threads, s.ms_per_frame(), k.ms_per_frame(), k.ms_first));
    m.rows.push_back(std::move(s));
    m.rows.push_back(std::move(k));
  }

  /// Embree: the configuration sweep, the ladder at every thread count, the new-directions row. Returns the
  /// configuration chosen.
  EmbreeSceneParams peer(Measurement& m, const MeshTopology& topology, const std::vector<Frame>& frames) {
    const EmbreeSceneParams best = fastest_peer(topology, frames, options.sweep_rays, m.peer_sweep);
    if (m.peer_sweep.empty()) {
      fail(m, "no Embree configuration ran");
      return best;
    }
    progress(m, "Embree configuration: " + describe(best) +
                    format(" (%.1f CPU ms at %d rays; %zu tried)", m.peer_sweep.front().ms,
                           options.sweep_rays, m.peer_sweep.size()));
    for (int threads : options.threads)
      for (int rays : options.rays) {
        MethodRow row = run_embree(topology, frames, best, rays, false, threads, threads == 1);
        if (!row.ok()) fail(m, format("embree %d rays, %d threads: ", rays, threads) + row.status);
        progress(m, format("Embree %d rays, %d thread(s): %.1f ms/frame", rays, threads, row.ms_per_frame()));
        m.rows.push_back(std::move(row));
      }
    if (options.random_rays > 0) {
      MethodRow row = run_embree(topology, frames, best, options.random_rays, true, 1, true);
      if (!row.ok()) fail(m, "embree-random: " + row.status);
      m.rows.push_back(std::move(row));
    }
    return best;
  }

  /// Once K* is known: the static engine and Embree at round(K*) rays, one thread, timed in turn
  /// (kAlternatedRounds rounds of each on the same frames), so that both see the same load.
  void alternate(Measurement& m, const MeshTopology& topology, const SlicingPlan& plan,
                 const std::vector<Frame>& frames, const EmbreeSceneParams& best) {
    MatchedRays k;
    if (!matched_embree(m, 1, false, k, true) || k.bound != MatchedRays::Bound::Inside) return;
    m.alternated_rays = static_cast<int>(std::lround(k.rays));
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    for (int round = 0; round < kAlternatedRounds; ++round) {
      const MethodRow s = run_static(topology, plan, frames, false);
      const MethodRow e = run_embree(topology, frames, best, m.alternated_rays, false, 1, false);
      if (!s.ok() || !e.ok()) {
        fail(m, "alternated: " + (s.ok() ? e.status : s.status));
        m.alternated_ratios.clear();
        return;
      }
      m.alternated_ratios.push_back(s.cpu_ms_per_frame() / e.cpu_ms_per_frame());
    }
    const auto [lo, hi] = std::minmax_element(m.alternated_ratios.begin(), m.alternated_ratios.end());
    progress(m, format("static ÷ Embree(%d rays), alternated: %.2f (%.2f–%.2f over %d rounds)",
                       m.alternated_rays, median(m.alternated_ratios), *lo, *hi, kAlternatedRounds));
  }

  /// Every value the reference estimated, with the static engine's (--vertex-errors). sky[f] and reference[f]
  /// are frames[f + 1]'s (frame 0 is not timed); values are the fronts, then the backs.
  void write_vertex_errors(Measurement& m, const std::vector<Frame>& frames,
                           const std::vector<SkyValues>& sky, const std::vector<SkyValues>& reference) {
    std::string name = "frame_coherence_errors_";
    name.append(m.sequence).append("_").append(std::to_string(m.vertices)).append(".csv");
    const fs::path path = options.out / name;
    std::ofstream out(path);
    out << "frame,vertex,side,x,y,z,static,reference\n";
    char line[256];
    for (std::size_t f = 0; f < reference.size(); ++f)
      for (std::size_t i = 0; i < reference[f].size(); ++i) {
        if (!std::isfinite(reference[f][i])) continue;
        const std::size_t vertex = i % m.vertices;
        const glm::dvec3& p = frames[f + 1].positions[vertex];
        std::snprintf(line, sizeof line, "%zu,%zu,%s,%.7g,%.7g,%.7g,%.9g,%.9g\n", f + 1, vertex,
                      i < m.vertices ? "front" : "back", p.x, p.y, p.z, sky[f][i], reference[f][i]);
        out << line;
      }
    out.close();
    if (!out)
      fail(m, "cannot write " + path.string());
    else
      progress(m, "wrote " + path.string());
  }

  /// Error and flicker of every row that kept its sky values; static and kinetic compared.
  void accuracy(Measurement& m, const MeshTopology& topology, const std::vector<Frame>& frames) {
    m.reference_stride =
        std::max<Index>(1, (m.vertices + options.reference_sample - 1) / options.reference_sample);
    std::vector<SkyValues> reference;
    try {
      const Stopwatch watch;
      reference = reference_sky(topology, frames, options.reference_rays, m.reference_stride);
      progress(m, format("reference (%d rays, every %u-th vertex, %zu frames): %.0f ms",
                         options.reference_rays, m.reference_stride, reference.size(), watch.wall_ms()));
    } catch (const std::exception& e) {
      fail(m, std::string("reference: ") + e.what());
      m.reference_stride = 0;
      return;
    }
    for (MethodRow& row : m.rows) {
      if (row.sky.size() != reference.size()) continue;
      row.err = error_stats(row.sky, reference);
      row.flicker = flicker(row.sky, reference);
    }
    const MethodRow* s = m.row("static");
    if (options.vertex_errors && s && s->ok() && s->sky.size() == reference.size())
      write_vertex_errors(m, frames, s->sky, reference);
    const MethodRow* k = m.row("kinetic");
    if (s && k && s->ok() && k->ok()) {
      const double worst = max_difference(s->sky, k->sky);
      m.max_static_kinetic = worst;
      if (!(worst <= kEqualTolerance)) fail(m, format("max |A_static - A_kinetic| = %.3g > 1e-9", worst));
    }
    // A plan that is the default or the paper's repeats that row's engine on the same frames: same values.
    const std::string default_name = setting_name(Setting{});
    const std::string paper_name = setting_name(setting(6, 1.0, ConeStorage::NearerEndpoint));
    for (const MethodRow* p : m.plans()) {
      const MethodRow* same = p->config == default_name ? s
                              : p->config == paper_name ? m.row("paper")
                                                        : nullptr;
      if (!same || !same->ok() || !p->ok()) continue;
      const double d = max_difference(p->sky, same->sky);
      if (!(d <= kEqualTolerance))
        fail(m,
             format("plan %s differs from the %s row by %.3g", p->config.c_str(), same->method.c_str(), d));
    }
    if (s && s->measured_accuracy())
      progress(m,
               format("cone error mean %.4f, p95 %.4f, flicker %.4f", s->err.mean, s->err.p95, s->flicker));
    for (MethodRow& row : m.rows) row.sky = {};  // not needed any more
  }

  Measurement measure(const Sequence& seq, double u, int frame_count) {
    Measurement m;
    m.sequence = seq.name;
    m.real = seq.real;
    m.vertices = seq.cloth.num_vertices;  // per cloth vertex: the occluders receive nothing
    m.triangles = seq.cloth.triangles.size();
    m.upsample = u;
    m.frames = frame_count;
    const std::vector<Frame> frames = make_frames(seq, u, frame_count);
    const SlicingPlan plan = default_plan(seq, frames[0]);
    m.planes = plan.planes.size();
    progress(m, format("%d frames, %zu planes%s", frame_count, plan.planes.size(),
                       seq.scene.empty() ? "" : (", in its scene: " + seq.scene).c_str()));
    const bool native = u == 1;
    cone_engines(m, seq, plan, frames, options.threads.front(), native);
    if (!native) return m;
    for (std::size_t t = 1; t < options.threads.size(); ++t)
      cone_engines(m, seq, plan, frames, options.threads[t], false);
    const EmbreeSceneParams best = peer(m, seq.topology, frames);
    accuracy(m, seq.topology, frames);
    if (!m.peer_sweep.empty()) alternate(m, seq.topology, plan, frames, best);
    return m;
  }
};

int run(int argc, char** argv) {
  const Options options = parse_options(argc, argv);
  if (!options.worker_result.empty()) return run_cone_worker(options);
  const Stopwatch run_watch;
  const SourceState source = read_source_state();
  fs::create_directories(options.out);
  const fs::path csv_path = options.out / "frame_coherence.csv";
  const fs::path csv_tmp = csv_path.string() + ".partial";
  std::ofstream csv(csv_tmp);
  if (!csv) {
    std::fprintf(stderr, "frame_coherence_bench: cannot write %s\n", csv_tmp.c_str());
    return 2;
  }
  write_csv_header(csv);
  double rss0 = 0;
  const bool memory_reset = start_memory_window(rss0);
  Run r{options, {}};
  std::vector<Measurement> all;
  for (const std::string& name : options.sequences) {
    const bool real = is_real_sequence(name, options.data) && !parse_cloth_kind(name);
    for (Index size : real ? std::vector<Index>{0} : options.sizes) {
      std::optional<Sequence> seq;
      try {
        seq = make_sequence(name, size, options.data, !options.cloth_alone);
      } catch (const std::exception& e) {
        std::fprintf(stderr, "[frame_coherence] %s %u: cannot make the sequence: %s\n", name.c_str(), size,
                     e.what());
        r.failures.push_back(format("%s %u: %s", name.c_str(), size, e.what()));
        continue;
      }
      const bool large = seq->topology.num_vertices > kLargeVertices;
      const int frames = large && options.large_frames ? options.large_frames : options.frames;
      for (double u : large && !options.large_upsample.empty() ? options.large_upsample : options.upsample) {
        try {
          all.push_back(r.measure(*seq, u, frames));
          write_csv_rows(csv, all.back());
        } catch (const std::exception& e) {
          std::fprintf(stderr, "[frame_coherence] %s %u u=%g: FAILED: %s\n", name.c_str(),
                       seq->topology.num_vertices, u, e.what());
          r.failures.push_back(
              format("%s %u u=%g: %s", name.c_str(), seq->topology.num_vertices, u, e.what()));
        }
        std::fprintf(stderr, "[frame_coherence] elapsed %.0f s\n", run_watch.wall_ms() / 1000.0);
      }
    }
  }
  csv.close();
  fs::rename(csv_tmp, csv_path);
  const double total = run_watch.wall_ms() / 1000.0;
  write_markdown(options.out / "frame_coherence.md", options, source, all, total, memory_reset, r.failures);
  {
    std::ofstream headline(options.out / "frame_coherence_headline.md");
    headline << headline_tables(options, all);
  }
  std::printf("frame_coherence: wrote %s and %s (%zu measurements, %.0f s)\n", csv_path.c_str(),
              (options.out / "frame_coherence.md").c_str(), all.size(), total);
  for (const Measurement& m : all)
    for (const MethodRow* p : m.plans())
      if (p->measured_accuracy())
        std::printf("frame_coherence: plan %s on %s %u: CPU %.1f ms/frame, error mean %.4f p95 %.4f\n",
                    p->config.c_str(), m.sequence.c_str(), m.vertices, p->cpu_ms_per_frame(), p->err.mean,
                    p->err.p95);
  for (const auto& f : r.failures) std::printf("frame_coherence: FAILED: %s\n", f.c_str());
  return r.failures.empty() ? 0 : 1;
}

}  // namespace
}  // namespace pleat::bench

int main(int argc, char** argv) {
  return pleat::bench::run_main("frame_coherence_bench", pleat::bench::run, argc, argv);
}
