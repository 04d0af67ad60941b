// The static and kinetic engines of one measurement in a watched child process (see cone_worker.hpp).
#include "bench/coherence/cone_worker.hpp"

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <tbb/global_control.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <thread>

#include "bench/coherence/memory_window.hpp"
#include "bench/coherence/sequences.hpp"
#include "bench/coherence/stopwatch.hpp"
#include "static_core/visibility.hpp"

namespace pleat::bench {

namespace fs = std::filesystem;

namespace {

SkyValues sky_of(const FrameVisibility& r) {
  SkyValues a;
  a.reserve(r.measures[0].size() + r.measures[1].size());
  for (int side = 0; side < 2; ++side)
    for (const ConeMeasures& m : r.measures[side]) a.push_back(m.sky_visibility);
  return a;
}

/// One line per step to a file the parent watches (a hung engine stops writing).
struct Heartbeat {
  std::ofstream out;
  void beat(const std::string& what) {
    if (!out.is_open()) return;
    out << what << '\n';
    out.flush();
  }
};

/// A row's name in the worker's result file: its method, with a plan's name ("plan=12:0.5:aimed-on-fan").
std::string row_key(const MethodRow& row) {
  return row.config.empty() ? row.method : row.method + "=" + row.config;
}

/// Times one frame of an engine into `row`; the result's sky values are kept if asked.
template <class Step>
void timed_frame(MethodRow& row, bool keep_sky, double& slice_vertices, Step&& step) {
  const Stopwatch watch;
  const FrameVisibility& r = step();
  row.ms.push_back(watch.wall_ms());
  row.cpu_ms.push_back(watch.process_cpu_ms());
  slice_vertices += double(r.stats.slice_vertices);
  if (keep_sky) row.sky.push_back(sky_of(r));
}

/// A static engine on another plan than the default, with its row: "paper" (the paper's plan) or "plan"
/// (Options::plans, its name in MethodRow::config).
struct ExtraPlan {
  std::string method, config;
  SlicingPlan plan;
};

/// Static and kinetic engines on `plan`, frame by frame in turn, and a static engine on each of `extras`
/// after them in every frame.
std::vector<MethodRow> run_engines(const MeshTopology& topology, const SlicingPlan& plan,
                                   const std::vector<ExtraPlan>& extras, const std::vector<Frame>& frames,
                                   int threads, bool keep_sky, Heartbeat& heartbeat) {
  MethodRow s, k;
  s.method = "static";
  k.method = "kinetic";
  s.threads = k.threads = threads;
  k.kinetic.emplace();
  std::vector<MethodRow> extra_rows(extras.size());
  std::vector<std::optional<StaticVisibility>> extra_engines(extras.size());
  std::vector<double> extra_sv(extras.size(), 0.0);
  for (std::size_t e = 0; e < extras.size(); ++e) {
    MethodRow& row = extra_rows[e];
    row.method = extras[e].method;
    row.config = extras[e].config;
    row.threads = threads;
    try {
      extra_engines[e].emplace(topology, extras[e].plan);
      const Stopwatch watch;
      extra_engines[e]->compute(frames[0]);
      row.ms_first = watch.wall_ms();
    } catch (const std::exception& ex) {
      row.status = std::string("error at frame 0: ") + ex.what();
    }
    heartbeat.beat(row_key(row) + " 0");
  }
  std::optional<StaticVisibility> static_engine;
  std::optional<KineticVisibility> kinetic_engine;
  s.peak_reset = start_memory_window(s.rss_before_mb);
  try {
    static_engine.emplace(topology, plan);
    const Stopwatch watch;
    static_engine->compute(frames[0]);
    s.ms_first = watch.wall_ms();
  } catch (const std::exception& e) {
    s.status = std::string("error at frame 0: ") + e.what();
  }
  s.peak_mb = status_mb("VmHWM");
  heartbeat.beat("static 0");
  k.peak_reset = start_memory_window(k.rss_before_mb);
  try {
    const Stopwatch watch;
    kinetic_engine.emplace(topology, plan, frames[0]);
    k.ms_first = watch.wall_ms();
  } catch (const std::exception& e) {
    k.status = std::string("error in the constructor: ") + e.what();
  } catch (...) {
    k.status = "error in the constructor: unknown exception";
  }
  heartbeat.beat("kinetic 0");
  double static_sv = 0, kinetic_sv = 0;
  for (std::size_t f = 1; f < frames.size(); ++f) {
    if (s.ok()) try {
        timed_frame(s, keep_sky, static_sv,
                    [&]() -> const FrameVisibility& { return static_engine->compute(frames[f]); });
      } catch (const std::exception& e) {
        s.status = "error at frame " + std::to_string(f) + ": " + e.what();
      }
    heartbeat.beat("static " + std::to_string(f));
    if (k.ok()) try {
        timed_frame(k, keep_sky, kinetic_sv, [&]() -> const FrameVisibility& {
          const FrameVisibility& r = kinetic_engine->advance(frames[f]);
          k.kinetic->add(kinetic_engine->last_stats());
          return r;
        });
      } catch (const std::exception& e) {
        k.status = "error at frame " + std::to_string(f) + ": " + e.what();
      } catch (...) {
        k.status = "error at frame " + std::to_string(f) + ": unknown exception";
      }
    heartbeat.beat("kinetic " + std::to_string(f));
    for (std::size_t e = 0; e < extras.size(); ++e) {
      MethodRow& row = extra_rows[e];
      if (row.ok()) try {
          timed_frame(row, keep_sky, extra_sv[e],
                      [&]() -> const FrameVisibility& { return extra_engines[e]->compute(frames[f]); });
        } catch (const std::exception& ex) {
          row.status = "error at frame " + std::to_string(f) + ": " + ex.what();
        }
      heartbeat.beat(row_key(row) + " " + std::to_string(f));
    }
  }
  k.peak_mb = status_mb("VmHWM");
  if (!s.ms.empty()) s.slice_vertices = static_sv / double(s.ms.size());
  if (!k.ms.empty()) k.slice_vertices = kinetic_sv / double(k.ms.size());
  for (std::size_t e = 0; e < extras.size(); ++e)
    if (!extra_rows[e].ms.empty())
      extra_rows[e].slice_vertices = extra_sv[e] / double(extra_rows[e].ms.size());
  std::vector<MethodRow> rows;
  rows.push_back(std::move(s));
  rows.push_back(std::move(k));
  for (MethodRow& row : extra_rows) rows.push_back(std::move(row));
  return rows;
}

// ---- The worker's result file: "status METHOD TEXT" lines, and "KEY COUNT v1 v2 ..." lines ----

/// The kinetic counters a worker hands to its parent: kKineticCounters in order, the rebuild reasons, then
/// the seconds (advance, structure, 2D cones, assembly).
constexpr std::size_t kNumKineticCounters = std::size(kKineticCounters);
constexpr std::size_t kNumKineticSeconds = 4;

void write_values(std::ostream& out, const std::string& key, const std::vector<double>& values) {
  out << key << ' ' << values.size();
  char buffer[32];
  for (double v : values) {
    std::snprintf(buffer, sizeof buffer, " %.17g", v);
    out << buffer;
  }
  out << '\n';
}

std::vector<double> kinetic_fields(const KineticTotals& t) {
  std::vector<double> f{double(t.frames)};
  for (const KineticCounter& c : kKineticCounters) f.push_back(double(t.sum.*c.field));
  for (std::size_t r : t.sum.rebuilt_because) f.push_back(double(r));
  for (double seconds : {t.sum.seconds, t.sum.structure_seconds, t.sum.cone_seconds, t.sum.assembly_seconds})
    f.push_back(seconds);
  return f;
}

KineticTotals kinetic_from_fields(const std::vector<double>& f) {
  KineticTotals t;
  const std::size_t seconds_at = 1 + kNumKineticCounters + t.sum.rebuilt_because.size();
  if (f.size() != seconds_at + kNumKineticSeconds) throw std::runtime_error("bad kinetic counter line");
  t.frames = int(f[0]);
  for (std::size_t i = 0; i < kNumKineticCounters; ++i)
    t.sum.*kKineticCounters[i].field = std::size_t(f[1 + i]);
  for (std::size_t i = 0; i < t.sum.rebuilt_because.size(); ++i)
    t.sum.rebuilt_because[i] = std::size_t(f[1 + kNumKineticCounters + i]);
  t.sum.seconds = f[seconds_at];
  t.sum.structure_seconds = f[seconds_at + 1];
  t.sum.cone_seconds = f[seconds_at + 2];
  t.sum.assembly_seconds = f[seconds_at + 3];
  return t;
}

std::vector<MethodRow> read_worker_result(const fs::path& path, int threads) {
  std::ifstream in(path);
  std::vector<std::pair<std::string, std::string>> status;  // (row key, status), in the file's order
  std::map<std::string, std::vector<double>> values;
  for (std::string line; std::getline(in, line);) {
    std::istringstream fields(line);
    std::string key;
    fields >> key;
    if (key == "status") {
      auto& [row, text] = status.emplace_back();
      fields >> row;
      std::getline(fields >> std::ws, text);
      continue;
    }
    std::size_t count = 0;
    fields >> count;
    std::vector<double> v(count);
    for (double& x : v) {
      std::string token;  // "nan" and "inf" read back through strtod
      fields >> token;
      x = std::strtod(token.c_str(), nullptr);
    }
    values[key] = std::move(v);
  }
  if (status.size() < 2 || status[0].first != "static" || status[1].first != "kinetic")
    throw std::runtime_error("the worker's result does not start with the static and kinetic rows");
  std::vector<MethodRow> rows(status.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    MethodRow& row = rows[i];
    const std::string& m = status[i].first;
    const auto eq = m.find('=');
    row.method = m.substr(0, eq);
    if (eq != std::string::npos) row.config = m.substr(eq + 1);
    row.threads = threads;
    for (const char* key : {".ms_first", ".ms", ".cpu_ms", ".memory", ".frames_with_sky"})
      if (!values.count(m + key)) throw std::runtime_error("no '" + m + key + "' in the worker's result");
    row.status = status[i].second;
    row.ms_first = values[m + ".ms_first"].at(0);
    row.ms = values[m + ".ms"];
    row.cpu_ms = values[m + ".cpu_ms"];
    const auto& memory = values[m + ".memory"];
    row.slice_vertices = memory.at(0);
    row.peak_mb = memory.at(1);
    row.rss_before_mb = memory.at(2);
    row.peak_reset = memory.at(3) != 0;
    if (values.count(m + ".kinetic")) row.kinetic = kinetic_from_fields(values[m + ".kinetic"]);
    const auto frames_with_sky = static_cast<std::size_t>(values[m + ".frames_with_sky"].at(0));
    for (std::size_t f = 0; f < frames_with_sky; ++f)
      row.sky.push_back(values.at(m + ".sky" + std::to_string(f)));
  }
  return rows;
}

}  // namespace

MethodRow run_static(const MeshTopology& topology, const SlicingPlan& plan, const std::vector<Frame>& frames,
                     bool keep_sky) {
  MethodRow row;
  row.method = "static";
  row.peak_reset = start_memory_window(row.rss_before_mb);
  try {
    StaticVisibility engine(topology, plan);
    const Stopwatch watch;
    engine.compute(frames[0]);
    row.ms_first = watch.wall_ms();
    double slice_vertices = 0;
    for (std::size_t k = 1; k < frames.size(); ++k)
      timed_frame(row, keep_sky, slice_vertices,
                  [&]() -> const FrameVisibility& { return engine.compute(frames[k]); });
    row.slice_vertices = slice_vertices / double(row.ms.size());
  } catch (const std::exception& e) {
    row.status = std::string("error: ") + e.what();
  }
  row.peak_mb = status_mb("VmHWM");
  return row;
}

int run_cone_worker(const Options& options) {
  Heartbeat heartbeat;
  heartbeat.out.open(options.worker_result.string() + ".beat");
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism,
                              std::size_t(options.worker_threads));
  const Sequence seq =
      make_sequence(options.sequences.at(0), options.sizes.at(0), options.data, !options.cloth_alone);
  const std::vector<Frame> frames = make_frames(seq, options.upsample.at(0), options.frames);
  const SlicingPlan plan = default_plan(seq, frames[0]);
  std::vector<ExtraPlan> extras;
  if (options.worker_keep_sky) {
    extras.push_back({"paper", "", paper_plan(seq, frames[0])});
    for (const Setting& p : options.plans)
      extras.push_back({"plan", setting_name(p), setting_plan(seq, frames[0], p)});
  }
  heartbeat.beat("frames");
  const auto rows = run_engines(seq.topology, plan, extras, frames, options.worker_threads,
                                options.worker_keep_sky, heartbeat);
  const fs::path tmp = options.worker_result.string() + ".tmp";
  {
    std::ofstream out(tmp);
    for (const MethodRow& row : rows) {
      const std::string m = row_key(row);
      out << "status " << m << ' ' << row.status << '\n';
      write_values(out, m + ".ms_first", {row.ms_first});
      write_values(out, m + ".ms", row.ms);
      write_values(out, m + ".cpu_ms", row.cpu_ms);
      write_values(out, m + ".memory",
                   {row.slice_vertices, row.peak_mb, row.rss_before_mb, row.peak_reset ? 1.0 : 0.0});
      if (row.kinetic) write_values(out, m + ".kinetic", kinetic_fields(*row.kinetic));
      write_values(out, m + ".frames_with_sky", {double(row.sky.size())});
      for (std::size_t f = 0; f < row.sky.size(); ++f)
        write_values(out, m + ".sky" + std::to_string(f), row.sky[f]);
    }
    if (!out) return 1;
  }
  fs::rename(tmp, options.worker_result);
  return 0;
}

std::variant<std::vector<MethodRow>, std::string> run_cone_engines_in_child(const std::string& sequence,
                                                                            Index size, Index vertices,
                                                                            double u, int frame_count,
                                                                            int threads, bool keep_sky,
                                                                            const Options& options) {
  static int counter = 0;
  const fs::path result = fs::temp_directory_path() / ("frame_coherence_worker_" + std::to_string(getpid()) +
                                                       "_" + std::to_string(counter++) + ".txt");
  const fs::path beat = result.string() + ".beat";
  fs::remove(result);
  fs::remove(beat);
  char u_text[32];
  std::snprintf(u_text, sizeof u_text, "%.17g", u);
  std::vector<std::string> args{"frame_coherence_bench",
                                "--worker",
                                result.string(),
                                "--sequences",
                                sequence,
                                "--sizes",
                                std::to_string(size),
                                "--upsample",
                                u_text,
                                "--frames",
                                std::to_string(frame_count),
                                "--data",
                                options.data.string(),
                                "--worker-threads",
                                std::to_string(threads)};
  if (keep_sky) args.emplace_back("--worker-keep-sky");
  if (keep_sky && !options.plans.empty()) {
    std::string plans;
    for (const Setting& p : options.plans) plans += (plans.empty() ? "" : ",") + setting_name(p);
    args.emplace_back("--plans");
    args.push_back(plans);
  }
  if (options.cloth_alone) args.emplace_back("--cloth-alone");
  std::vector<char*> argv;
  argv.reserve(args.size() + 1);
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (const int err = posix_spawn(&pid, "/proc/self/exe", nullptr, nullptr, argv.data(), environ); err != 0)
    return std::string("cannot start the worker process: ") + std::strerror(err);
  const double base_s = (options.quick ? 20.0 : 60.0) + double(vertices) / 1000.0;
  Stopwatch since_change;
  std::uintmax_t last_size = 0;
  double longest_gap_s = 0;
  std::string last_step = "start";
  int wstatus = 0;
  auto read_last_step = [&] {
    std::ifstream in(beat);
    for (std::string line; std::getline(in, line);) last_step = line;
  };
  for (;;) {
    const pid_t done = waitpid(pid, &wstatus, WNOHANG);
    if (done == pid) break;
    if (done < 0) return std::string("waitpid: ") + std::strerror(errno);
    std::error_code ec;
    const std::uintmax_t size_now = fs::file_size(beat, ec);
    if (!ec && size_now != last_size) {
      longest_gap_s = std::max(longest_gap_s, since_change.wall_ms() / 1000.0);
      since_change = Stopwatch();
      last_size = size_now;
      read_last_step();
    }
    const double allowed_s =
        options.kinetic_timeout_s > 0 ? options.kinetic_timeout_s : base_s + 30.0 * longest_gap_s;
    if (since_change.wall_ms() > 1000.0 * allowed_s) {
      kill(pid, SIGKILL);
      waitpid(pid, &wstatus, 0);
      fs::remove(beat);
      return "hung: nothing done for " + std::to_string(int(allowed_s)) + " s after step '" + last_step +
             "' (worker killed)";
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  read_last_step();
  fs::remove(beat);
  if (WIFSIGNALED(wstatus))
    return "crashed: signal " + std::to_string(WTERMSIG(wstatus)) + " (" + strsignal(WTERMSIG(wstatus)) +
           ") after step '" + last_step + "'";
  if (!fs::exists(result))
    return "the worker exited with status " + std::to_string(WEXITSTATUS(wstatus)) +
           " and no result, after step '" + last_step + "'";
  try {
    auto rows = read_worker_result(result, threads);
    fs::remove(result);
    return rows;
  } catch (const std::exception& e) {
    return std::string("unreadable worker result: ") + e.what();
  }
}

}  // namespace pleat::bench
