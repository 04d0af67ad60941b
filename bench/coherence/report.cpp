// CSV, markdown and headline tables of the frame-coherence benchmark.
#include "bench/coherence/report.hpp"

#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <map>
#include <sstream>

#include "bench/bench_args.hpp"
#include "bench/coherence/plan_setting.hpp"

namespace pleat::bench {

namespace fs = std::filesystem;

namespace {

std::string num(double x, const char* fmt = "%.6g") {
  return std::isfinite(x) ? format(fmt, x) : std::string();
}
std::string cell(double x, const char* fmt) { return std::isfinite(x) ? format(fmt, x) : std::string("–"); }
std::string u_label(double u) { return format("%g", u); }

std::string shell_output(const std::string& command) {
  std::string text;
  if (FILE* pipe = popen(command.c_str(), "r")) {
    char buffer[256];
    while (std::fgets(buffer, sizeof buffer, pipe)) text += buffer;
    pclose(pipe);
  }
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  return text;
}

std::string machine() {
  return shell_output("nproc") + " cores (" +
         shell_output("grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'") + ", shared)";
}

std::string csv_quote(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::vector<std::string> rebuild_reason_columns() {
  std::vector<std::string> names;
  for (int r = 1; r < static_cast<int>(kinetic::RebuildReason::count); ++r)
    names.push_back(std::string("rebuilt_") +
                    kinetic::rebuild_reason_name(static_cast<kinetic::RebuildReason>(r)));
  return names;
}

/// CPU µs per element at one thread (the one-core cost), or NaN.
double us_per(const MethodRow* r, double elements) {
  if (!r || !r->ok() || r->threads != 1 || !(elements > 0)) return NAN;
  return 1000.0 * r->cpu_ms_per_frame() / elements;
}

/// Measurements keyed by (sequence, vertices), in the order of the run.
std::vector<std::pair<std::string, Index>> sequence_keys(const std::vector<Measurement>& all) {
  std::vector<std::pair<std::string, Index>> keys;
  for (const auto& m : all)
    if (std::find(keys.begin(), keys.end(), std::make_pair(m.sequence, m.vertices)) == keys.end())
      keys.emplace_back(m.sequence, m.vertices);
  return keys;
}

const Measurement* find(const std::vector<Measurement>& all, const std::string& seq, Index vertices,
                        double u) {
  for (const auto& m : all)
    if (m.sequence == seq && m.vertices == vertices && m.upsample == u) return &m;
  return nullptr;
}

/// "K*" and "pleat ÷ Embree(K*)" cells, with the bound's direction when K* is off the ladder.
std::string rays_cell(const MatchedRays& k) {
  switch (k.bound) {
    case MatchedRays::Bound::Below:
      return format("< %.0f", k.rays);
    case MatchedRays::Bound::Above:
      return format("> %.0f", k.rays);
    default:
      return format("%.1f", k.rays);
  }
}
std::string ratio_cell(double pleat_ms, const MatchedRays& k) {
  if (!(pleat_ms > 0)) return "–";
  const double r = pleat_ms / k.ms;
  switch (k.bound) {
    case MatchedRays::Bound::Below:
      return format("> %.2f", r);  // Embree(K*) < Embree(K_1)
    case MatchedRays::Bound::Above:
      return format("< %.2f", r);
    default:
      return format("%.2f", r);
  }
}

double ms_of(const MethodRow* r) { return r && r->ok() ? r->ms_per_frame() : NAN; }
/// CPU ms per frame: at one thread, the one-core cost, far less sensitive than wall time to other jobs.
double cpu_of(const MethodRow* r) { return r && r->ok() ? r->cpu_ms_per_frame() : NAN; }

/// Per u = 1 measurement with "plan" rows: each plan's cost and error, whether it is on the Pareto front of
/// the plans measured (no other plan both cheaper in CPU and no less accurate), and its ratio to Embree at
/// matched error, cheapest plan first.
std::string plan_tables(const std::vector<Measurement>& all) {
  std::ostringstream out;
  const std::string default_name = setting_name(Setting{});
  const std::string paper_name = setting_name(setting(6, 1.0, ConeStorage::NearerEndpoint));
  out << "Each plan is orientations:spacing in average edge lengths:storage rule (6 orientations: the "
         "paper's "
         "axis-aligned set; others spread over the hemisphere); **"
      << default_name << "** is pleat's default (its row repeats the static engine's), **" << paper_name
      << "** the paper's plan. One thread, u = 1, median process CPU ms per frame; error against the same "
         "reference as every other row. **front**: on the Pareto front of the plans measured here, by mean "
         "or 95th-percentile error (no other plan both cheaper and at most as far off). "
         "**÷ Embree(K\\*)**: the plan's CPU time over Embree's at the ray count matching its error (< 1: "
         "the plan is faster at equal accuracy).\n\n";
  for (const auto& m : all) {
    auto plans = m.plans();
    if (m.upsample != 1 || plans.empty()) continue;
    std::sort(plans.begin(), plans.end(), [](auto* a, auto* b) { return cpu_of(a) < cpu_of(b); });
    auto on_front = [&](const MethodRow* r, bool p95) {
      if (!r->measured_accuracy() || !r->ok()) return false;
      const double e = p95 ? r->err.p95 : r->err.mean, c = cpu_of(r);
      for (const MethodRow* o : plans) {
        if (o == r || !o->measured_accuracy() || !o->ok()) continue;
        const double oe = p95 ? o->err.p95 : o->err.mean, oc = cpu_of(o);
        if (oc <= c && oe <= e && (oc < c || oe < e)) return false;
      }
      return true;
    };
    out << "**" << m.sequence << "**, " << m.vertices << " vertices, " << m.frames << " frames:\n\n"
        << "| plan | slice vertices | CPU ms / frame | err mean | err p95 | flicker | front | K* (mean) | "
           "÷ Embree(K*) | K* (p95) | ÷ Embree(K* p95) |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const MethodRow* r : plans) {
      MatchedRays k, kp;
      const bool have = matched_embree(m, *r, 1, false, k, true);
      const bool have_p = matched_embree(m, *r, 1, true, kp, true);
      const bool front_mean = on_front(r, false), front_p95 = on_front(r, true);
      const std::string front = front_mean && front_p95 ? "mean, p95"
                                : front_mean            ? "mean"
                                : front_p95             ? "p95"
                                                        : "";
      out << "| " << r->config
          << (r->config == default_name ? " (default)"
              : r->config == paper_name ? " (paper)"
                                        : "")
          << " | " << cell(r->slice_vertices, "%.0f") << " | " << cell(cpu_of(r), "%.1f") << " | "
          << (r->measured_accuracy() ? format("%.4f | %.4f", r->err.mean, r->err.p95) : "– | –") << " | "
          << cell(r->flicker, "%.4f") << " | " << front << " | " << (have ? rays_cell(k) : "–") << " | "
          << (have ? ratio_cell(cpu_of(r), k) : "–") << " | " << (have_p ? rays_cell(kp) : "–") << " | "
          << (have_p ? ratio_cell(cpu_of(r), kp) : "–") << " |";
      if (!r->ok()) out << ' ' << r->status;
      out << '\n';
    }
    out << '\n';
  }
  return out.str();
}

}  // namespace

SourceState read_source_state() {
  const fs::path root = fs::path(PLEAT_BENCH_SOURCE_DIR);
  const std::string git = "git -C '" + root.string() + "' ";
  SourceState s;
  s.commit = shell_output(git + "rev-parse --short HEAD 2>/dev/null");
  s.dirty = shell_output(git + "diff HEAD --name-only 2>/dev/null | paste -sd, - | sed 's/,/, /g'");
  s.dirty_hash = shell_output(git + "diff HEAD 2>/dev/null | sha256sum | cut -c1-12");
  if (s.commit.empty()) s.commit = "unknown";
  return s;
}

bool matched_embree(const Measurement& m, int threads, bool p95, MatchedRays& out, bool cpu) {
  const MethodRow* s = m.row("static");
  return s && matched_embree(m, *s, threads, p95, out, cpu);
}

bool matched_embree(const Measurement& m, const MethodRow& target, int threads, bool p95, MatchedRays& out,
                    bool cpu) {
  if (!target.measured_accuracy()) return false;
  std::vector<Rung> ladder;
  for (const MethodRow* timed : m.ladder(threads)) {
    const MethodRow* accuracy = m.row("embree", 1, timed->rays);
    if (!accuracy || !accuracy->measured_accuracy()) continue;
    const double e = p95 ? accuracy->err.p95 : accuracy->err.mean;
    const double ms = cpu ? timed->cpu_ms_per_frame() : timed->ms_per_frame();
    if (!(e > 0) || !(ms > 0)) continue;
    ladder.push_back({double(timed->rays), ms, e, accuracy->flicker});
  }
  if (ladder.empty()) return false;
  out = matched_rays(ladder, p95 ? target.err.p95 : target.err.mean);
  return true;
}

void write_csv_header(std::ostream& out) {
  out << "sequence,source,vertices,triangles,planes,upsample,frames,method,rays,threads,config,ms_per_frame,"
         "cpu_ms_per_frame,ms_first_frame,ms_min,ms_max,us_per_slice_vertex_cpu,us_per_mesh_vertex_cpu,mean_"
         "err,"
         "p95_err,flicker,max_static_kinetic_diff,slice_vertices,peak_rss_mb,rss_before_mb,peak_increase_mb,"
         "peak_reset";
  for (const KineticCounter& c : kKineticCounters) out << ',' << c.name;
  for (const auto& name : rebuild_reason_columns()) out << ',' << name;
  out << ",status\n";
}

void write_csv_rows(std::ostream& out, const Measurement& m) {
  const MethodRow* static_row = m.row("static");
  const double slice_vertices = static_row ? static_row->slice_vertices : NAN;
  for (const MethodRow& r : m.rows) {
    double lo = NAN, hi = NAN;
    if (!r.ms.empty()) {
      lo = *std::min_element(r.ms.begin(), r.ms.end());
      hi = *std::max_element(r.ms.begin(), r.ms.end());
    }
    const bool cone = r.method == "static" || r.method == "kinetic";
    out << m.sequence << ',' << (m.real ? "blender" : "generated") << ',' << m.vertices << ',' << m.triangles
        << ',' << m.planes << ',' << u_label(m.upsample) << ',' << m.frames << ',' << r.method << ','
        << r.rays << ',' << r.threads << ',' << csv_quote(r.config) << ',' << num(r.ms_per_frame()) << ','
        << num(r.cpu_ms_per_frame()) << ',' << num(r.ms_first) << ',' << num(lo) << ',' << num(hi) << ','
        << num(cone ? us_per(&r, slice_vertices) : NAN) << ',' << num(us_per(&r, double(m.vertices))) << ','
        << (r.measured_accuracy() ? num(r.err.mean) + ',' + num(r.err.p95) : std::string(",")) << ','
        << num(r.flicker) << ',' << (cone ? num(m.max_static_kinetic) : std::string()) << ','
        << num(r.slice_vertices, "%.1f") << ',' << num(r.peak_mb, "%.1f") << ','
        << num(r.rss_before_mb, "%.1f") << ',' << num(r.peak_mb - r.rss_before_mb, "%.1f") << ','
        << (r.peak_reset ? 1 : 0);
    if (r.kinetic && r.kinetic->frames) {
      const KineticTotals& t = *r.kinetic;
      const KineticFrameStats& k = t.sum;
      for (const KineticCounter& c : kKineticCounters) out << ',' << num(t.per_frame(k.*c.field), "%.2f");
      for (std::size_t i = 1; i < k.rebuilt_because.size(); ++i)
        out << ',' << num(t.per_frame(k.rebuilt_because[i]), "%.2f");
    } else {
      for (std::size_t i = 0; i < std::size(kKineticCounters) + rebuild_reason_columns().size(); ++i)
        out << ',';
    }
    out << ',' << csv_quote(r.status) << '\n';
  }
  out.flush();
}

/// The alternated ratio's cell: "median (min–max)", or "–" where it was not measured.
std::string alternated_cell(const Measurement& m) {
  if (m.alternated_ratios.empty()) return "–";
  const auto [lo, hi] = std::minmax_element(m.alternated_ratios.begin(), m.alternated_ratios.end());
  return format("%.2f (%.2f–%.2f)", median(m.alternated_ratios), *lo, *hi);
}

std::string headline_tables(const Options& options, const std::vector<Measurement>& all) {
  std::ostringstream out;
  const bool two = std::find(options.threads.begin(), options.threads.end(), 2) != options.threads.end();
  out << "**Against ray casting at matched error** (u = 1; Embree configured as measured fastest, fixed "
         "directions; K* = Embree's rays per vertex and side whose error equals the cone engine's, log-log "
         "interpolated over "
      << options.rays.size() << " ray counts " << options.rays.front() << "–" << options.rays.back()
      << "; < 1: pleat is faster; \"paper's plan\": the static engine on the paper's 6 axis orientations "
         "with "
         "nearer-endpoint storage, the baseline of pleat's defaults):\n\n";
  out << "| sequence | vertices | cone err mean / p95 | cone flicker | paper's plan: err mean / p95, flicker "
         "| "
         "static ÷ paper's plan, CPU | K* (mean) | Embree(K*) CPU ms, 1 thread | "
         "static ÷ Embree(K*), 1 thread (CPU) | static ÷ Embree(K*), 1 thread, timed in turn (CPU; median, "
         "min–max of 3) |";
  if (two) out << " static ÷ Embree(K*), 2 threads (wall) |";
  out << " kinetic ÷ Embree(K*), 1 thread (CPU) |";
  if (two) out << " kinetic ÷ Embree(K*), 2 threads (wall) |";
  out << " K* (p95) | static ÷ Embree(K* p95), 1 thread (CPU) | Embree flicker at K* | Embree "
      << options.random_rays
      << " rays, new directions each frame: flicker |\n|---|---|---|---|---|---|---|---|---|---|";
  if (two) out << "---|";
  out << "---|";
  if (two) out << "---|";
  out << "---|---|---|---|\n";
  for (const auto& [seq, vertices] : sequence_keys(all)) {
    const Measurement* m = find(all, seq, vertices, 1);
    if (!m) continue;
    const MethodRow* s = m->row("static");
    MatchedRays k1, k2, kp;
    if (!s || !s->measured_accuracy() || !matched_embree(*m, 1, false, k1, true)) continue;
    const bool have2 = two && matched_embree(*m, 2, false, k2);
    const bool have_p = matched_embree(*m, 1, true, kp, true);
    const MethodRow* random = m->row("embree-random", 1, options.random_rays);
    const MethodRow* paper = m->row("paper");
    out << "| " << seq << " | " << vertices << " | " << format("%.3f / %.3f", s->err.mean, s->err.p95)
        << " | " << cell(s->flicker, "%.4f") << " | "
        << (paper && paper->measured_accuracy()
                ? format("%.3f / %.3f, %.4f", paper->err.mean, paper->err.p95, paper->flicker)
                : std::string("–"))
        << " | " << cell(cpu_of(s) / cpu_of(paper), "%.2f") << " | " << rays_cell(k1) << " | "
        << cell(k1.ms, "%.1f") << " | " << ratio_cell(cpu_of(s), k1) << " | " << alternated_cell(*m) << " |";
    if (two) out << ' ' << (have2 ? ratio_cell(ms_of(m->row("static", 2)), k2) : "–") << " |";
    out << ' ' << ratio_cell(cpu_of(m->row("kinetic")), k1) << " |";
    if (two) out << ' ' << (have2 ? ratio_cell(ms_of(m->row("kinetic", 2)), k2) : "–") << " |";
    out << ' ' << (have_p ? rays_cell(kp) : "–") << " | " << (have_p ? ratio_cell(cpu_of(s), kp) : "–")
        << " | " << cell(k1.flicker, "%.4f") << " | " << cell(random ? random->flicker : NAN, "%.4f")
        << " |\n";
  }

  std::vector<double> ups;
  for (const auto& m : all)
    if (std::find(ups.begin(), ups.end(), m.upsample) == ups.end()) ups.push_back(m.upsample);
  std::sort(ups.begin(), ups.end());
  out << "\n**Cost per element and kinetic ÷ static** (one thread; µs of CPU per slice vertex and per mesh "
         "vertex "
         "at u = 1; Embree's at K* for comparison; kinetic ÷ static = median CPU time per frame, both "
         "engines "
         "frame by frame in turn):\n\n";
  out << "| sequence | vertices | slice vertices | static µs / slice vertex | static µs / mesh vertex | "
         "kinetic µs / "
         "mesh vertex | Embree(K*) µs / mesh vertex |";
  for (double u : ups) out << " kinetic ÷ static, u = " << u_label(u) << " |";
  out << "\n|---|---|---|---|---|---|---|";
  for (std::size_t i = 0; i < ups.size(); ++i) out << "---|";
  out << '\n';
  for (const auto& [seq, vertices] : sequence_keys(all)) {
    const Measurement* m = find(all, seq, vertices, 1);
    const MethodRow* s = m ? m->row("static") : nullptr;
    const MethodRow* k = m ? m->row("kinetic") : nullptr;
    MatchedRays k1;
    double embree_us = NAN;
    if (m && matched_embree(*m, 1, false, k1, true) && k1.bound == MatchedRays::Bound::Inside)
      embree_us = 1000.0 * k1.ms / double(vertices);  // CPU time at K*, interpolated like the wall time
    out << "| " << seq << " | " << vertices << " | " << cell(s ? s->slice_vertices : NAN, "%.0f") << " | "
        << cell(m ? us_per(s, s ? s->slice_vertices : NAN) : NAN, "%.2f") << " | "
        << cell(us_per(s, double(vertices)), "%.1f") << " | " << cell(us_per(k, double(vertices)), "%.1f")
        << " | " << cell(embree_us, "%.1f") << " |";
    for (double u : ups) {
      const Measurement* mu = find(all, seq, vertices, u);
      const MethodRow* su = mu ? mu->row("static") : nullptr;
      const MethodRow* ku = mu ? mu->row("kinetic") : nullptr;
      out << ' ' << cell(cpu_of(ku) / cpu_of(su), "%.2f") << " |";
    }
    out << '\n';
  }
  // The headline goes into docs/benchmarks.md, which names runs by date; the commit is in frame_coherence.md.
  char today[16] = "";
  const std::time_t now = std::time(nullptr);
  std::strftime(today, sizeof today, "%Y-%m-%d", std::gmtime(&now));
  out << "\nAll figures from one run of `bash bench/run_frame_coherence.sh` on " << today << ", " << machine()
      << ". Error = mean and 95th percentile of |A − A_ref| over vertices, both sides and the timed frames, "
         "against Embree with "
      << options.reference_rays
      << " rays; flicker = mean |(A_{t+1} − A_t) − (R_{t+1} − R_t)| over consecutive frames. Ratios at one "
         "thread "
         "compare median process CPU time per frame (the one-core cost, robust to other jobs on the shared "
         "machine), "
         "at two threads median wall time. Everything else, and how the peer is configured: "
         "`bench/results/frame_coherence.md`.\n";
  return out.str();
}

void write_markdown(const fs::path& path, const Options& options, const SourceState& source,
                    const std::vector<Measurement>& all, double total_seconds, bool memory_reset,
                    const std::vector<std::string>& failures) {
  std::ofstream out(path);
  out << "# Frame coherence: kinetic vs static engine vs Embree ray casting at its best\n\n";
  out << "Written by `bench/frame_coherence_bench` (`" << options.command_line
      << "`; `bench/run_frame_coherence.sh` runs it and the plots). Commit **" << source.commit << "**"
      << (source.dirty.empty() ? std::string()
                               : " plus uncommitted changes to " + source.dirty +
                                     " (`git diff HEAD | sha256sum`: " + source.dirty_hash + "…)")
      << ". Machine: " << machine() << ", load average at the end "
      << shell_output("cut -d' ' -f1-3 /proc/loadavg") << ". Whole run: " << format("%.0f", total_seconds)
      << " s wall.\n\n";
  out << "Every method runs on the same frames; the cone engines on the same plan (`make_diffuse_plan` on "
         "the first frame with its defaults: "
      << setting_name(Setting{})
      << " = orientations spread over the sphere, their planes' spacing in average edge lengths, storage "
         "rule). "
         "**ms** = wall milliseconds per "
         "frame, the "
         "median over frames 1..N−1 (frame 0 builds the engines / Embree's BVH and is not counted); **CPU** "
         "= "
         "process CPU time (at one thread, the one-core cost). Threads: TBB limited to the count given "
         "(`tbb::global_control`); every u runs at one thread, u = 1 also at each count of `--threads`. "
         "**Error** (u = 1) = |A − A_ref| over every vertex and side and every timed frame, against Embree "
         "with "
      << options.reference_rays << " rays (another seed; above " << options.reference_sample
      << " vertices on every k-th vertex, k chosen for about that many), mean / 95th percentile. **Flicker** "
         "= the "
         "mean over consecutive frame pairs of |(A_{t+1} − A_t) − (R_{t+1} − R_t)|, R the reference. "
         "**Embree** = BVH update to the frame + vertex normals + K stratified cosine-weighted rays per "
         "vertex and "
         "side with the one-ring side test (shading/ray_visibility.hpp), directions fixed per vertex and "
         "side "
         "across frames; `embree-random` draws new directions each frame. Its configuration is the fastest "
         "of a "
         "greedy sweep per sequence (ray call, coherence hint, robust flag, refit vs rebuild; below). "
         "**K\\*** = the ray count whose error equals the static engine's, log-log interpolated between the "
         "bracketing ray counts of the ladder (time and flicker at K\\* likewise); `< 8` / `> 1024`: off the "
         "ladder, the ratio then a bound.\n\n";
  out << "## Headline\n\n" << headline_tables(options, all) << "\n";
  if (!options.plans.empty()) out << "## Plans: error against cost\n\n" << plan_tables(all);

  out << "## The peer's configuration\n\nPer sequence and size, the configurations tried (one thread, "
      << options.sweep_rays
      << " rays per vertex and side; the median process CPU ms per frame, the least of two runs made in turn "
         "with the step's other candidates), fastest first; the first is used.\n\n";
  out << "| sequence | vertices | configurations tried (CPU ms per frame) |\n|---|---|---|\n";
  for (const auto& m : all) {
    if (m.peer_sweep.empty()) continue;
    out << "| " << m.sequence << " | " << m.vertices << " | ";
    for (std::size_t i = 0; i < m.peer_sweep.size(); ++i)
      out << (i ? "; " : "") << (i == 0 ? "**" : "") << m.peer_sweep[i].config << " "
          << cell(m.peer_sweep[i].ms, "%.1f") << (i == 0 ? "**" : "");
    out << " |\n";
  }

  out << "\n## The ray ladder (u = 1)\n\n| sequence | vertices | rays | ms, 1 thread | ms, 2 threads | err "
         "mean / p95 | "
         "flicker |\n|---|---|---|---|---|---|---|\n";
  for (const auto& m : all) {
    for (const MethodRow* r : m.ladder(1)) {
      const MethodRow* r2 = m.row("embree", 2, r->rays);
      out << "| " << m.sequence << " | " << m.vertices << " | " << r->rays << " | " << cell(ms_of(r), "%.1f")
          << " | " << cell(ms_of(r2), "%.1f") << " | "
          << (r->measured_accuracy() ? format("%.4f / %.4f", r->err.mean, r->err.p95) : "–") << " | "
          << cell(r->flicker, "%.4f") << " |\n";
    }
    if (const MethodRow* r = m.row("embree-random", 1, options.random_rays))
      out << "| " << m.sequence << " | " << m.vertices << " | " << r->rays
          << " (new directions each frame) | " << cell(ms_of(r), "%.1f") << " | – | "
          << (r->measured_accuracy() ? format("%.4f / %.4f", r->err.mean, r->err.p95) : "–") << " | "
          << cell(r->flicker, "%.4f") << " |\n";
  }

  out << "\n## Cone engines per temporal resolution\n\n| sequence | vertices | u | frames | planes | static "
         "ms | kinetic ms "
         "| kinetic ÷ static | static CPU ms | kinetic CPU ms | static ms, 2 threads | kinetic ms, 2 threads "
         "| cone err "
         "mean / p95 | cone flicker | max \\|A_s − A_k\\| "
         "|\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& m : all) {
    const MethodRow* s = m.row("static");
    const MethodRow* k = m.row("kinetic");
    const MethodRow* s2 = m.row("static", 2);
    const MethodRow* k2 = m.row("kinetic", 2);
    out << "| " << m.sequence << " | " << m.vertices << " | " << u_label(m.upsample) << " | " << m.frames
        << " | " << m.planes << " | " << cell(ms_of(s), "%.1f") << " | " << cell(ms_of(k), "%.1f") << " | "
        << cell(ms_of(k) / ms_of(s), "%.2f") << " | "
        << cell(s && s->ok() ? s->cpu_ms_per_frame() : NAN, "%.1f") << " | "
        << cell(k && k->ok() ? k->cpu_ms_per_frame() : NAN, "%.1f") << " | " << cell(ms_of(s2), "%.1f")
        << " | " << cell(ms_of(k2), "%.1f") << " | "
        << (s && s->measured_accuracy() ? format("%.4f / %.4f", s->err.mean, s->err.p95) : "–") << " | "
        << cell(s ? s->flicker : NAN, "%.4f") << " | " << cell(m.max_static_kinetic, "%.1e") << " |";
    if (s && !s->ok()) out << " static: " << s->status;
    if (k && !k->ok()) out << " kinetic: " << k->status;
    out << '\n';
  }

  // Growth with vertex count (generated kinds, u = 1).
  out << "\n## Growth with vertex count\n\nLog-log slope of ms per frame (one thread, u = 1) against "
         "vertices "
         "between the smallest and largest size measured (generated kinds; 1 = linear). Embree at the "
         "ladder's "
         "middle ray count.\n\n| sequence | sizes | static | kinetic | Embree |\n|---|---|---|---|---|\n";
  const int middle_rays = options.rays[options.rays.size() / 2];
  std::map<std::string, std::pair<const Measurement*, const Measurement*>> span;
  for (const auto& m : all) {
    if (m.real || m.upsample != 1) continue;
    auto& [a, b] = span[m.sequence];
    if (!a || m.vertices < a->vertices) a = &m;
    if (!b || m.vertices > b->vertices) b = &m;
  }
  for (const auto& [seq, ab] : span) {
    const Measurement* a = ab.first;  // named copies: a lambda below captures them
    const Measurement* b = ab.second;
    if (a == b) continue;
    auto slope = [&](const std::string& method, int rays) {
      const double ta = ms_of(a->row(method, 1, rays)), tb = ms_of(b->row(method, 1, rays));
      return std::log(tb / ta) / std::log(double(b->vertices) / double(a->vertices));
    };
    out << "| " << seq << " | " << a->vertices << "→" << b->vertices << " | "
        << cell(slope("static", 0), "%.2f") << " | " << cell(slope("kinetic", 0), "%.2f") << " | "
        << cell(slope("embree", middle_rays), "%.2f") << " |\n";
  }

  out << "\n## Kinetic engine, mean per frame (one thread)\n\nSide changes = (mesh vertex, plane) crossings, "
         "regular / critical; removed / inserted = slice vertices edited locally; certificates checked at "
         "the "
         "frame (failed); put back = slice vertices taken out and re-inserted to repair failed certificates; "
         "relabeled = fan swaps (a vanishing slice vertex's triangulation vertex handed to a new one); "
         "slices "
         "unchanged / repaired / rebuilt (rebuild reasons in the CSV); time = share of advance() carrying "
         "the "
         "structure (slicing, edits, certificates, put-backs, rebuilds, regions) / growing the 2D cones / "
         "assembling (storage, fill, 3D cones).\n\n";
  out << "| sequence | vertices | u | planes | side changes reg / crit | relabeled | removed / inserted | "
         "certificates (failed) | put back | unchanged | repaired | rebuilt | time: structure / 2D cones / "
         "assembly |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& m : all) {
    const MethodRow* k = m.row("kinetic");
    if (!k || !k->kinetic || !k->kinetic->frames) continue;
    const KineticTotals& totals = *k->kinetic;
    const KineticFrameStats& t = totals.sum;
    auto pf = [&](std::size_t v) { return format("%.1f", totals.per_frame(v)); };
    out << "| " << m.sequence << " | " << m.vertices << " | " << u_label(m.upsample) << " | " << m.planes
        << " | " << pf(t.side_changes_regular) << " / " << pf(t.side_changes_critical) << " | "
        << pf(t.relabeled) << " | " << pf(t.removed) << " / " << pf(t.inserted) << " | " << pf(t.certificates)
        << " (" << pf(t.certificates_failed) << ") | " << pf(t.reinserted) << " | " << pf(t.slices_unchanged)
        << " | " << pf(t.slices_repaired) << " | " << pf(t.slices_rebuilt) << " | ";
    // One thread: the slices' summed seconds and the assembly's wall time add up to advance()'s.
    auto share = [&](double seconds) {
      return t.seconds > 0 ? format("%.0f%%", 100 * seconds / t.seconds) : "–";
    };
    out << share(t.structure_seconds) << " / " << share(t.cone_seconds) << " / " << share(t.assembly_seconds)
        << " |\n";
  }

  out << "\n## Peak memory\n\nThe cone engines run in a child process (both alive, frames in turn), Embree "
         "in the main "
         "one. **peak** = VmHWM at the end of a window, **+** = peak − resident set at its start. ";
  out << (memory_reset
              ? "VmHWM is reset at the start of each window (static: construction and frame 0; kinetic: "
                "construction and every later frame, with the static engine's per-frame transients).\n\n"
              : "Resetting VmHWM failed on this machine: **peak** is the process-wide high-water mark.\n\n");
  out << "| sequence | vertices | u | static MB (+) | kinetic MB (+) | Embree, largest K, MB (+) |\n"
         "|---|---|---|---|---|---|\n";
  for (const auto& m : all) {
    auto mb = [](const MethodRow* r) {
      return r ? format("%.0f (+%.0f)", r->peak_mb, r->peak_mb - r->rss_before_mb) : std::string("–");
    };
    const auto ladder = m.ladder(1);
    out << "| " << m.sequence << " | " << m.vertices << " | " << u_label(m.upsample) << " | "
        << mb(m.row("static")) << " | " << mb(m.row("kinetic")) << " | "
        << mb(ladder.empty() ? nullptr : ladder.back()) << " |\n";
  }

  out << "\n## Problems\n\n";
  if (failures.empty())
    out << "None: every method ran on every measurement, and static and kinetic agreed to 1e-9 wherever both "
           "ran.\n";
  for (const auto& f : failures) out << "- " << f << '\n';
}

}  // namespace pleat::bench
