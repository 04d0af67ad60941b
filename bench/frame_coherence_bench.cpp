// The frame-coherence benchmark (project issue 6): what keeping slices alive from frame to frame buys.
//
// For each cloth sequence x size x temporal resolution it times, per frame, on the same frames and the same
// diffuse slicing plan (make_diffuse_plan on the first frame, the paper's 6 orientations):
//   static   StaticVisibility::compute, a full recompute of every frame;
//   kinetic  KineticVisibility::advance (constructed on the first frame), which keeps every slice alive;
//   embreeK  Embree per-vertex ray casting, K = 64, 256, 1024 cosine-weighted rays per vertex and side, with
//            vertex normals and a BVH refit of the frame in the timing (as a user's frame loop would do);
// all with TBB's default threads. Time = wall ms per frame, the median over the frames after the first.
// Accuracy: on the first and last timed frames (frames 1 and N-1), |A - A_ref| over every vertex and both
// sides against Embree with 4096 rays (another seed), mean and 95th percentile; static and kinetic must
// agree to 1e-9 there. Peak memory: VmHWM of /proc/self/status, reset (clear_refs 5) before each engine.
// Writes DIR/frame_coherence.csv (one row per sequence x size x upsample x method) and
// DIR/frame_coherence.md; progress goes to stderr. Plain executable: no Google Benchmark main.
//
// Sequences: "drape" is the bundled Blender simulation (data/drape/drape.obj + drape.pc2, 3,111 vertices,
// its size fixed), from its sample 20 on (the table turns and drags the folds); "curtain", "roll", "flag",
// "sleeve" are ClothGenerator's kinds at resolution sqrt(size) (3025 -> 55, 29929 -> 173, 300304 -> 548),
// 48 frames per motion cycle (24 fps), from frame 8 on (the cycle loops, so any length is available).
// Temporal resolution u: 1 = native frames; u = 2, 4, 8 insert u-1 linearly interpolated frames between
// consecutive native frames; u = 0.5 takes every other native frame. Frame k is at native time k / u.
//
// Flags (all optional):
//   --quick                  curtain 3025, u = 1 and 2, 3 frames (the test suite's run, ~20 s)
//   --out DIR                output directory (default bench/results)
//   --sequences a,b,...      default drape,curtain,roll,flag,sleeve
//   --sizes n,...            vertex counts of generated kinds: 3025, 29929, 300304 (default 3025,29929)
//   --upsample u,...         default 0.5,1,2,4,8
//   --frames N               frames per measurement (default 8; the first is not timed)
//   --large-frames N         frames per measurement above 10,000 vertices (default 4; 0: --frames)
//   --large-upsample u,...   temporal resolutions above 10,000 vertices (default: --upsample)
//   --large-embree-upsample u,...|all  the temporal resolutions at which Embree and the accuracy (4096-ray
//                            reference) are measured above 10,000 vertices (default 1: Embree's cost per
//                            frame does not depend on u, and the reference costs ~25 s a frame at 30k)
// The defaults fit a full run in about 15 minutes on 2 shared cores (bench/run_frame_coherence.sh).
//   --rays K,...             default 64,256,1024
//   --reference-rays K       default 4096
//   --data DIR               the repository's data/ (default: found from this source file's path)
//   --kinetic-timeout S      seconds without progress before the cone engines' process is declared hung
//                            (default: 60, --quick 20, + 1 ms per vertex + 30 x the longest step so far)
// The two cone engines run in a child process (this program with the internal flag --kinetic-worker FILE,
// which rebuilds the same frames and plan), frame by frame in turn (static.compute(k), kinetic.advance(k)) so
// that both times of a frame see the same load on a shared machine. A hang (no progress for the timeout: the
// worker is killed) or a crash is reported in the outputs, the static engine then runs alone, and the run
// goes on. Exit status 1 and "frame_coherence: FAILED: ..." lines when any engine failed or static
// and kinetic differ by more than 1e-9.
#include <malloc.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "bench/bench_args.hpp"
#include "kinetic/kinetic_visibility.hpp"
#include "shading/embree_scene.hpp"
#include "shading/ray_visibility.hpp"
#include "sim_io/cloth_generators.hpp"
#include "sim_io/mesh_sequence.hpp"
#include "static_core/slicing_plan.hpp"
#include "static_core/visibility.hpp"

namespace pleat {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr Index kLargeVertices = 10000;
constexpr int kGeneratorCycle = 48;        // frames per motion cycle of the generated kinds
constexpr std::size_t kGeneratedStart = 8;  // first native frame of the generated kinds
constexpr std::size_t kDrapeStart = 20;     // first native sample of the drape (Blender frame 41)
constexpr std::uint64_t kMethodSeed = 7;
constexpr std::uint64_t kReferenceSeed = 0x5eed4096;
constexpr double kEqualTolerance = 1e-9;

// ---- Options ----

struct Options {
  bool quick = false;
  fs::path out = "bench/results";
  std::vector<std::string> sequences{"drape", "curtain", "roll", "flag", "sleeve"};
  std::vector<Index> sizes{3025, 29929};
  std::vector<double> upsample{0.5, 1, 2, 4, 8};
  int frames = 8;
  int large_frames = 4;                          // 0: frames
  std::vector<double> large_upsample;             // empty: upsample
  std::vector<double> large_embree_upsample{1};   // empty: all
  std::vector<int> rays{64, 256, 1024};
  int reference_rays = 4096;
  double kinetic_timeout_s = 0;  // 0: (60 s, quick: 20 s) + 30 x the static engine's time for all frames
  fs::path data;
  fs::path kinetic_worker;  // internal: run the kinetic engine for one measurement and write its row here
  std::string command_line;
};

using bench::split;

template <class T, class F>
std::vector<T> parse_list(const std::string& text, F&& convert) {
  std::vector<T> values;
  for (const auto& s : split(text)) values.push_back(convert(s));
  return values;
}

[[noreturn]] void usage_error(const std::string& what) {
  std::fprintf(stderr, "frame_coherence_bench: %s (see the flags at the top of bench/frame_coherence_bench.cpp)\n",
               what.c_str());
  std::exit(2);
}

Options parse_options(int argc, char** argv) {
  Options o;
  for (int i = 0; i < argc; ++i) o.command_line += (i ? " " : "") + std::string(argv[i]);
  o.data = fs::path(__FILE__).parent_path().parent_path() / "data";
  bool explicit_sequences = false, explicit_sizes = false, explicit_upsample = false, explicit_frames = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) usage_error(arg + " needs a value");
      return argv[++i];
    };
    auto to_int = [&](const std::string& s) {
      try {
        return std::stoi(s);
      } catch (...) {
        usage_error("bad number '" + s + "' for " + arg);
      }
    };
    auto to_double = [&](const std::string& s) {
      try {
        return std::stod(s);
      } catch (...) {
        usage_error("bad number '" + s + "' for " + arg);
      }
    };
    if (arg == "--quick") {
      o.quick = true;
    } else if (arg == "--out") {
      o.out = next();
    } else if (arg == "--sequences") {
      o.sequences = split(next());
      explicit_sequences = true;
    } else if (arg == "--sizes") {
      o.sizes = parse_list<Index>(next(), [&](const std::string& s) { return Index(to_int(s)); });
      explicit_sizes = true;
    } else if (arg == "--upsample") {
      o.upsample = parse_list<double>(next(), to_double);
      explicit_upsample = true;
    } else if (arg == "--frames") {
      o.frames = to_int(next());
      explicit_frames = true;
    } else if (arg == "--large-frames") {
      o.large_frames = to_int(next());
    } else if (arg == "--large-upsample") {
      o.large_upsample = parse_list<double>(next(), to_double);
    } else if (arg == "--large-embree-upsample") {
      const std::string v = next();
      o.large_embree_upsample = v == "all" ? std::vector<double>{} : parse_list<double>(v, to_double);
    } else if (arg == "--rays") {
      o.rays = parse_list<int>(next(), to_int);
    } else if (arg == "--reference-rays") {
      o.reference_rays = to_int(next());
    } else if (arg == "--data") {
      o.data = next();
    } else if (arg == "--kinetic-timeout") {
      o.kinetic_timeout_s = to_double(next());
    } else if (arg == "--kinetic-worker") {
      o.kinetic_worker = next();
    } else if (arg == "--help" || arg == "-h") {
      std::printf(
          "frame_coherence_bench [--quick] [--out DIR] [--sequences drape,curtain,roll,flag,sleeve]\n"
          "  [--sizes 3025,29929] [--upsample 0.5,1,2,4,8] [--frames 8] [--large-frames N]\n"
          "  [--large-upsample LIST] [--large-embree-upsample LIST] [--rays 64,256,1024]\n"
          "  [--reference-rays 4096] [--data DIR] [--kinetic-timeout S]\n");
      std::exit(0);
    } else {
      usage_error("unknown flag '" + arg + "'");
    }
  }
  if (o.quick) {  // the smallest run that goes through every path; explicit flags still win
    if (!explicit_sequences) o.sequences = {"curtain"};
    if (!explicit_sizes) o.sizes = {3025};
    if (!explicit_upsample) o.upsample = {1, 2};
    if (!explicit_frames) o.frames = 3;
  }
  if (o.frames < 3 || (o.large_frames != 0 && o.large_frames < 3)) usage_error("--frames must be at least 3");
  if (o.quick) o.large_frames = 0;
  for (double u : o.upsample)
    if (!(u > 0)) usage_error("--upsample values must be positive");
  for (int k : o.rays)
    if (k < 1) usage_error("--rays values must be positive");
  if (o.reference_rays < 1) usage_error("--reference-rays must be positive");
  for (const auto& s : o.sequences)
    if (s != "drape" && !parse_cloth_kind(s)) usage_error("unknown sequence '" + s + "'");
  return o;
}

// ---- Small helpers ----

std::string format(const char* fmt, auto... args) {
  char buffer[512];
  std::snprintf(buffer, sizeof buffer, fmt, args...);
  return buffer;
}

double elapsed_ms(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

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

std::string upsample_label(double u) { return format("%g", u); }

// ---- Memory: VmHWM / VmRSS from /proc/self/status ----

double status_mb(const char* key) {
  std::ifstream in("/proc/self/status");
  const std::size_t n = std::strlen(key);
  for (std::string line; std::getline(in, line);)
    if (line.compare(0, n, key) == 0 && line.size() > n && line[n] == ':')
      return std::strtod(line.c_str() + n + 1, nullptr) / 1024.0;  // kB -> MB
  return NAN;
}

/// Returns memory freed by the previous engine to the system, then resets the peak (Linux >= 4.0:
/// "5" > /proc/self/clear_refs sets VmHWM to the current RSS). Returns whether the reset worked.
bool start_memory_window(double& rss_before) {
  malloc_trim(0);
  rss_before = status_mb("VmRSS");
  {
    std::ofstream clear("/proc/self/clear_refs");
    clear << "5";
    clear.flush();
    if (!clear) return false;
  }
  return status_mb("VmHWM") <= rss_before + 1.0;
}

// ---- Sequences and their frames ----

struct Sequence {
  std::string name;
  Index size = 0;  // as asked for (0 for the drape)
  bool real = false;
  MeshTopology topology;
  std::function<Frame(std::size_t)> native;  // native frame i, counted from the start frame
  std::size_t native_available = 0;          // SIZE_MAX: loops
};

Sequence make_sequence(const std::string& name, Index size, const Options& options) {
  Sequence s;
  s.name = name;
  s.size = size;
  if (name == "drape") {
    const MeshSequence seq = load_sequence(options.data / "drape" / "drape.obj", options.data / "drape" / "drape.pc2");
    s.real = true;
    s.topology = seq.topology();
    s.native_available = seq.num_frames() > kDrapeStart ? seq.num_frames() - kDrapeStart : 0;
    s.native = [seq](std::size_t i) { return seq.frame(kDrapeStart + i); };
    return s;
  }
  const int resolution = static_cast<int>(std::lround(std::sqrt(double(size))));
  if (cloth_vertex_count(resolution) != size)
    throw std::invalid_argument(format("size %u is not a square grid (try 3025, 29929, 300304)", size));
  auto generator = std::make_shared<ClothGenerator>(*parse_cloth_kind(name),
                                                    GeneratorParams{resolution, kGeneratorCycle, 24.0, 0});
  s.topology = generator->topology();
  s.native_available = SIZE_MAX;
  s.native = [generator](std::size_t i) { return generator->frame((kGeneratedStart + i) % kGeneratorCycle); };
  return s;
}

/// Frames 0..count-1 at temporal resolution u: frame k at native time k / u, linear between native frames.
std::vector<Frame> make_frames(const Sequence& s, double u, int count) {
  std::map<std::size_t, Frame> native;
  auto get = [&](std::size_t i) -> const Frame& {
    if (i >= s.native_available)
      throw std::out_of_range(format("%s has %zu frames from its start; u=%g x %d frames needs frame %zu",
                                     s.name.c_str(), s.native_available, u, count, i));
    auto it = native.find(i);
    if (it == native.end()) it = native.emplace(i, s.native(i)).first;
    return it->second;
  };
  std::vector<Frame> frames(count);
  for (int k = 0; k < count; ++k) {
    const double t = double(k) / u;
    const std::size_t i = static_cast<std::size_t>(std::floor(t + 1e-9));
    const double f = t - double(i);
    const Frame& a = get(i);
    if (f < 1e-9) {
      frames[k] = a;
      continue;
    }
    const Frame& b = get(i + 1);
    Frame& out = frames[k];
    out.time = (1 - f) * a.time + f * b.time;
    out.positions.resize(a.positions.size());
    for (std::size_t v = 0; v < a.positions.size(); ++v) out.positions[v] = (1 - f) * a.positions[v] + f * b.positions[v];
  }
  return frames;
}

// ---- Results ----

/// Sky visibility of every vertex, both sides: [front..., back...].
using SkyValues = std::vector<double>;

SkyValues sky_of(const FrameVisibility& r) {
  SkyValues a;
  a.reserve(r.measures[0].size() + r.measures[1].size());
  for (int side = 0; side < 2; ++side)
    for (const ConeMeasures& m : r.measures[side]) a.push_back(m.sky_visibility);
  return a;
}

SkyValues sky_of(const std::array<std::vector<double>, 2>& r) {
  SkyValues a(r[0]);
  a.insert(a.end(), r[1].begin(), r[1].end());
  return a;
}

struct ErrorStats {
  double mean = NAN, p95 = NAN;
};

ErrorStats error_stats(std::vector<double> e) {
  ErrorStats s;
  if (e.empty()) return s;
  double sum = 0;
  for (double x : e) sum += x;
  s.mean = sum / double(e.size());
  const std::size_t k = static_cast<std::size_t>(std::ceil(0.95 * double(e.size()))) - 1;
  std::nth_element(e.begin(), e.begin() + k, e.end());
  s.p95 = e[k];
  return s;
}

std::vector<double> abs_errors(const SkyValues& a, const SkyValues& ref) {
  std::vector<double> e(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) e[i] = std::abs(a[i] - ref[i]);
  return e;
}

/// Kinetic counters, summed over the timed frames (divided by their number when written).
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

/// The counters a worker hands to its parent, in this order (then the rebuild reasons).
constexpr std::size_t KineticFrameStats::*kKineticCounters[] = {
    &KineticFrameStats::certificates,          &KineticFrameStats::exact_certificates,
    &KineticFrameStats::flips,                 &KineticFrameStats::hull_enter,
    &KineticFrameStats::hull_leave,            &KineticFrameStats::touches,
    &KineticFrameStats::side_changes_regular,  &KineticFrameStats::side_changes_critical,
    &KineticFrameStats::removed,               &KineticFrameStats::inserted,
    &KineticFrameStats::slices_unchanged,      &KineticFrameStats::slices_repaired,
    &KineticFrameStats::slices_rebuilt};
constexpr std::size_t kNumKineticCounters = std::size(kKineticCounters);

struct MethodRow {
  std::string method;  // static, kinetic, embree64, ...
  int rays = 0;
  std::vector<double> ms;  // per timed frame (frames 1..N-1)
  double ms_first = NAN;   // frame 0 (construction / BVH build / warm-up)
  std::array<SkyValues, 2> sky;  // at the two accuracy frames
  ErrorStats err, err_first, err_last;
  double peak_mb = NAN, rss_before_mb = NAN;
  bool peak_reset = false;
  double slice_vertices = NAN;  // per frame, mean over the timed frames
  std::optional<KineticTotals> kinetic;
  std::string status = "ok";

  double ms_per_frame() const { return median(ms); }
  bool ok() const { return status == "ok"; }
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
  double max_static_kinetic = NAN;  // max |A_static - A_kinetic| on the accuracy frames
  bool reference_ok = false;

  const MethodRow* row(const std::string& method) const {
    for (const auto& r : rows)
      if (r.method == method) return &r;
    return nullptr;
  }
};

// ---- The cone engines, frame by frame, in a child process ----

/// Frames 1 and N-1: where accuracy is measured.
std::array<std::size_t, 2> accuracy_frames_of(int frame_count) { return {1, std::size_t(frame_count - 1)}; }

/// One line per step to a file the parent watches (a hung engine stops writing).
struct Heartbeat {
  std::ofstream out;
  void beat(const std::string& what) {
    if (!out.is_open()) return;
    out << what << '\n';
    out.flush();
  }
};

/// The static engine alone (when the child process failed).
MethodRow run_static(const MeshTopology& topology, const SlicingPlan& plan, const std::vector<Frame>& frames) {
  const auto accuracy = accuracy_frames_of(int(frames.size()));
  MethodRow row;
  row.method = "static";
  row.peak_reset = start_memory_window(row.rss_before_mb);
  try {
    StaticVisibility engine(topology, plan);
    double slice_vertices = 0;
    for (std::size_t k = 0; k < frames.size(); ++k) {
      const auto start = Clock::now();
      const FrameVisibility& r = engine.compute(frames[k]);
      const double ms = elapsed_ms(start);
      if (k == 0) {
        row.ms_first = ms;
        continue;
      }
      row.ms.push_back(ms);
      slice_vertices += double(r.stats.slice_vertices);
      for (int slot = 0; slot < 2; ++slot)
        if (k == accuracy[slot]) row.sky[slot] = sky_of(r);
    }
    row.slice_vertices = slice_vertices / double(row.ms.size());
  } catch (const std::exception& e) {
    row.status = std::string("error: ") + e.what();
  }
  row.peak_mb = status_mb("VmHWM");
  return row;
}

/// Both engines on the same frames, frame by frame: static.compute(k), then kinetic.advance(k), so that the two
/// times of a frame see the same load on a shared machine. The static engine computes frame 0 too (not
/// timed in the median: its buffers grow there), the kinetic engine is constructed on it. Memory: VmHWM is
/// reset before the static engine is built, and read after its frame 0 (it allocates almost nothing on later
/// frames); it is reset again before the kinetic engine is built and read at the end, so the kinetic window
/// holds the kinetic engine plus the static engine's per-frame transients.
std::array<MethodRow, 2> run_cone_engines(const MeshTopology& topology, const SlicingPlan& plan,
                                          const std::vector<Frame>& frames, Heartbeat& heartbeat) {
  const auto accuracy = accuracy_frames_of(int(frames.size()));
  MethodRow s, k;
  s.method = "static";
  k.method = "kinetic";
  k.kinetic.emplace();
  std::optional<StaticVisibility> static_engine;
  std::optional<KineticVisibility> kinetic_engine;
  s.peak_reset = start_memory_window(s.rss_before_mb);
  try {
    static_engine.emplace(topology, plan);
    const auto start = Clock::now();
    static_engine->compute(frames[0]);
    s.ms_first = elapsed_ms(start);
  } catch (const std::exception& e) {
    s.status = std::string("error at frame 0: ") + e.what();
  }
  s.peak_mb = status_mb("VmHWM");
  heartbeat.beat("static 0");
  k.peak_reset = start_memory_window(k.rss_before_mb);
  try {
    const auto start = Clock::now();
    kinetic_engine.emplace(topology, plan, frames[0]);
    k.ms_first = elapsed_ms(start);
  } catch (const std::exception& e) {
    k.status = std::string("error in the constructor: ") + e.what();
  } catch (...) {
    k.status = "error in the constructor: unknown exception";
  }
  heartbeat.beat("kinetic 0");
  double static_sv = 0, kinetic_sv = 0;
  for (std::size_t f = 1; f < frames.size(); ++f) {
    if (s.ok()) try {
        const auto start = Clock::now();
        const FrameVisibility& r = static_engine->compute(frames[f]);
        s.ms.push_back(elapsed_ms(start));
        static_sv += double(r.stats.slice_vertices);
        for (int slot = 0; slot < 2; ++slot)
          if (f == accuracy[slot]) s.sky[slot] = sky_of(r);
      } catch (const std::exception& e) {
        s.status = format("error at frame %zu: ", f) + e.what();
      }
    heartbeat.beat(format("static %zu", f));
    if (k.ok()) try {
        const auto start = Clock::now();
        const FrameVisibility& r = kinetic_engine->advance(frames[f]);
        k.ms.push_back(elapsed_ms(start));
        k.kinetic->add(kinetic_engine->last_stats());
        kinetic_sv += double(r.stats.slice_vertices);
        for (int slot = 0; slot < 2; ++slot)
          if (f == accuracy[slot]) k.sky[slot] = sky_of(r);
      } catch (const std::exception& e) {
        k.status = format("error at frame %zu: ", f) + e.what();
      } catch (...) {
        k.status = format("error at frame %zu: unknown exception", f);
      }
    heartbeat.beat(format("kinetic %zu", f));
  }
  k.peak_mb = status_mb("VmHWM");
  if (!s.ms.empty()) s.slice_vertices = static_sv / double(s.ms.size());
  if (!k.ms.empty()) k.slice_vertices = kinetic_sv / double(k.ms.size());
  return {std::move(s), std::move(k)};
}

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
  for (auto counter : kKineticCounters) f.push_back(double(t.sum.*counter));
  for (std::size_t r : t.sum.rebuilt_because) f.push_back(double(r));
  return f;
}

KineticTotals kinetic_from_fields(const std::vector<double>& f) {
  KineticTotals t;
  if (f.size() != 1 + kNumKineticCounters + t.sum.rebuilt_because.size())
    throw std::runtime_error("bad kinetic counter line");
  t.frames = int(f[0]);
  for (std::size_t i = 0; i < kNumKineticCounters; ++i) t.sum.*kKineticCounters[i] = std::size_t(f[1 + i]);
  for (std::size_t i = 0; i < t.sum.rebuilt_because.size(); ++i)
    t.sum.rebuilt_because[i] = std::size_t(f[1 + kNumKineticCounters + i]);
  return t;
}

/// --kinetic-worker FILE: builds the same frames and plan as the parent, runs both cone engines, writes their
/// rows to FILE (text, one key per line) and heartbeats to FILE.beat.
int run_kinetic_worker(const Options& options) {
  Heartbeat heartbeat;
  heartbeat.out.open(options.kinetic_worker.string() + ".beat");
  const Sequence seq = make_sequence(options.sequences.at(0), options.sizes.at(0), options);
  const std::vector<Frame> frames = make_frames(seq, options.upsample.at(0), options.frames);
  const SlicingPlan plan = make_diffuse_plan(seq.topology, frames[0], DiffusePlanParams{});
  heartbeat.beat("frames");
  const auto rows = run_cone_engines(seq.topology, plan, frames, heartbeat);
  const fs::path tmp = options.kinetic_worker.string() + ".tmp";
  {
    std::ofstream out(tmp);
    for (const MethodRow& row : rows) {
      const std::string& m = row.method;
      out << "status " << m << ' ' << row.status << '\n';
      write_values(out, m + ".ms_first", {row.ms_first});
      write_values(out, m + ".ms", row.ms);
      write_values(out, m + ".memory",
                   {row.slice_vertices, row.peak_mb, row.rss_before_mb, row.peak_reset ? 1.0 : 0.0});
      if (row.kinetic) write_values(out, m + ".kinetic", kinetic_fields(*row.kinetic));
      write_values(out, m + ".sky0", row.sky[0]);
      write_values(out, m + ".sky1", row.sky[1]);
    }
    if (!out) return 1;
  }
  fs::rename(tmp, options.kinetic_worker);
  return 0;
}

std::array<MethodRow, 2> read_worker_result(const fs::path& path) {
  std::ifstream in(path);
  std::map<std::string, std::string> status;
  std::map<std::string, std::vector<double>> values;
  for (std::string line; std::getline(in, line);) {
    std::istringstream fields(line);
    std::string key;
    fields >> key;
    if (key == "status") {
      std::string method;
      fields >> method;
      std::getline(fields >> std::ws, status[method]);
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
  std::array<MethodRow, 2> rows;
  rows[0].method = "static";
  rows[1].method = "kinetic";
  for (MethodRow& row : rows) {
    const std::string& m = row.method;
    for (const char* key : {".ms_first", ".ms", ".memory", ".sky0", ".sky1"})
      if (!values.count(m + key) || !status.count(m))
        throw std::runtime_error("no '" + m + key + "' in the worker's result");
    row.status = status[m];
    row.ms_first = values[m + ".ms_first"].at(0);
    row.ms = values[m + ".ms"];
    const auto& memory = values[m + ".memory"];
    row.slice_vertices = memory.at(0);
    row.peak_mb = memory.at(1);
    row.rss_before_mb = memory.at(2);
    row.peak_reset = memory.at(3) != 0;
    if (values.count(m + ".kinetic")) row.kinetic = kinetic_from_fields(values[m + ".kinetic"]);
    row.sky[0] = values[m + ".sky0"];
    row.sky[1] = values[m + ".sky1"];
  }
  return rows;
}

/// Runs this program as `--kinetic-worker` for one measurement. The worker is killed (by its pid) when its
/// heartbeat file stays unchanged longer than the allowed silence: --kinetic-timeout if given, else
/// (60 s, --quick 20 s) + 1 ms per vertex + 30 x the longest gap between heartbeats so far. Returns the rows,
/// or the reason the worker failed.
std::variant<std::array<MethodRow, 2>, std::string> run_worker_child(const std::string& sequence, Index size,
                                                                     Index vertices, double u, int frame_count,
                                                                     const Options& options) {
  static int counter = 0;
  const fs::path result =
      fs::temp_directory_path() / format("frame_coherence_worker_%d_%d.txt", int(getpid()), counter++);
  const fs::path beat = result.string() + ".beat";
  fs::remove(result);
  fs::remove(beat);
  std::vector<std::string> args{"frame_coherence_bench", "--kinetic-worker", result.string(), "--sequences", sequence,
                                "--sizes", std::to_string(size), "--upsample", format("%.17g", u), "--frames",
                                std::to_string(frame_count), "--data", options.data.string()};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (const int err = posix_spawn(&pid, "/proc/self/exe", nullptr, nullptr, argv.data(), environ); err != 0)
    return std::string("cannot start the worker process: ") + std::strerror(err);
  const double base_s = (options.quick ? 20.0 : 60.0) + double(vertices) / 1000.0;
  auto last_change = Clock::now();
  std::uintmax_t last_size = 0;
  double longest_gap_s = 0;
  std::string last_step = "start";
  int wstatus = 0;
  for (;;) {
    const pid_t done = waitpid(pid, &wstatus, WNOHANG);
    if (done == pid) break;
    if (done < 0) return std::string("waitpid: ") + std::strerror(errno);
    std::error_code ec;
    const std::uintmax_t size_now = fs::file_size(beat, ec);
    if (!ec && size_now != last_size) {
      longest_gap_s = std::max(longest_gap_s, elapsed_ms(last_change) / 1000.0);
      last_change = Clock::now();
      last_size = size_now;
      std::ifstream in(beat);
      for (std::string line; std::getline(in, line);) last_step = line;
    }
    const double allowed_s = options.kinetic_timeout_s > 0 ? options.kinetic_timeout_s : base_s + 30.0 * longest_gap_s;
    if (elapsed_ms(last_change) > 1000.0 * allowed_s) {
      kill(pid, SIGKILL);
      waitpid(pid, &wstatus, 0);
      fs::remove(beat);
      return format("hung: nothing done for %.0f s after step '%s' (worker killed)", allowed_s, last_step.c_str());
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  {
    std::ifstream in(beat);
    for (std::string line; std::getline(in, line);) last_step = line;
  }
  fs::remove(beat);
  if (WIFSIGNALED(wstatus))
    return format("crashed: signal %d (%s) after step '%s'", WTERMSIG(wstatus), strsignal(WTERMSIG(wstatus)),
                  last_step.c_str());
  if (!fs::exists(result))
    return format("the worker exited with status %d and no result, after step '%s'", WEXITSTATUS(wstatus),
                  last_step.c_str());
  try {
    auto rows = read_worker_result(result);
    fs::remove(result);
    return rows;
  } catch (const std::exception& e) {
    return std::string("unreadable worker result: ") + e.what();
  }
}

// ---- The measurement of one sequence x size x u ----

void progress(const Measurement& m, const std::string& text) {
  std::fprintf(stderr, "[frame_coherence] %s %u u=%g: %s\n", m.sequence.c_str(), m.vertices, m.upsample,
               text.c_str());
}

Measurement measure(const Sequence& seq, double u, int frame_count, bool with_embree, const Options& options,
                    std::vector<std::string>& failures) {
  Measurement m;
  m.sequence = seq.name;
  m.real = seq.real;
  m.vertices = seq.topology.num_vertices;
  m.triangles = seq.topology.triangles.size();
  m.upsample = u;
  m.frames = frame_count;
  const MeshTopology& topology = seq.topology;
  const std::vector<Frame> frames = make_frames(seq, u, frame_count);
  const SlicingPlan plan = make_diffuse_plan(topology, frames[0], DiffusePlanParams{});
  m.planes = plan.planes.size();
  const std::array<std::size_t, 2> accuracy_frames = accuracy_frames_of(frame_count);
  auto accuracy_slot = [&](std::size_t k) -> int {
    return k == accuracy_frames[1] ? 1 : k == accuracy_frames[0] ? 0 : -1;
  };
  progress(m, format("%d frames, %zu planes", frame_count, plan.planes.size()));

  // The cone engines, in a child process so that a hang or a crash of the kinetic engine is reported and the
  // run goes on (the static engine then runs alone, here).
  {
    auto child = run_worker_child(seq.name, seq.size, m.vertices, u, frame_count, options);
    MethodRow s, k;
    if (auto* rows = std::get_if<std::array<MethodRow, 2>>(&child)) {
      s = std::move((*rows)[0]);
      k = std::move((*rows)[1]);
    } else {
      const std::string why = std::get<std::string>(child);
      progress(m, "the cone engines' process failed (" + why + "); the static engine runs alone");
      k.method = "kinetic";
      k.status = why;
      s = run_static(topology, plan, frames);
    }
    progress(m, format("static %.1f ms/frame (first %.1f)", s.ms_per_frame(), s.ms_first));
    if (!s.ok())
      failures.push_back(format("%s %u u=%g: static %s", m.sequence.c_str(), m.vertices, u, s.status.c_str()));
    if (k.ok())
      progress(m, format("kinetic %.1f ms/frame (construction %.1f), %.1f events/frame, rebuilt %.1f of %zu "
                         "slices/frame",
                         k.ms_per_frame(), k.ms_first, k.kinetic->per_frame(k.kinetic->sum.events()),
                         k.kinetic->per_frame(k.kinetic->sum.slices_rebuilt), plan.planes.size()));
    else {
      progress(m, "kinetic FAILED: " + k.status);
      failures.push_back(format("%s %u u=%g: kinetic %s", m.sequence.c_str(), m.vertices, u, k.status.c_str()));
    }
    m.rows.push_back(std::move(s));
    m.rows.push_back(std::move(k));
  }

  // Embree ray casting, one scene per ray count: built on frame 0, refitted to every later frame.
  if (with_embree)
    for (int rays : options.rays) {
      MethodRow row;
      row.method = "embree" + std::to_string(rays);
      row.rays = rays;
      row.peak_reset = start_memory_window(row.rss_before_mb);
      try {
        RayVisibilityParams params;
        params.rays_per_vertex = rays;
        params.seed = kMethodSeed;
        std::unique_ptr<EmbreeScene> scene;
        for (std::size_t k = 0; k < frames.size(); ++k) {
          const auto start = Clock::now();
          if (!scene) scene = std::make_unique<EmbreeScene>(topology, frames[k]);
          const auto normals = vertex_normals(topology, frames[k]);
          auto a = ray_cast_sky_visibility(*scene, topology, frames[k], normals, params);
          const double ms = elapsed_ms(start);
          if (k == 0)
            row.ms_first = ms;
          else
            row.ms.push_back(ms);
          if (const int slot = accuracy_slot(k); slot >= 0) row.sky[slot] = sky_of(a);
        }
      } catch (const std::exception& e) {
        row.status = std::string("error: ") + e.what();
        failures.push_back(format("%s %u u=%g: %s %s", m.sequence.c_str(), m.vertices, u, row.method.c_str(),
                                  row.status.c_str()));
      }
      row.peak_mb = status_mb("VmHWM");
      progress(m, format("%s %.1f ms/frame", row.method.c_str(), row.ms_per_frame()));
      m.rows.push_back(std::move(row));
    }

  // Reference (untimed) on the accuracy frames, and the errors (where Embree is measured).
  std::array<SkyValues, 2> reference;
  if (with_embree) try {
    for (int slot = 0; slot < 2; ++slot) {
      const Frame& frame = frames[accuracy_frames[slot]];
      const auto start = Clock::now();
      EmbreeScene scene(topology, frame);
      RayVisibilityParams params;
      params.rays_per_vertex = options.reference_rays;
      params.seed = kReferenceSeed;
      reference[slot] = sky_of(ray_cast_sky_visibility(scene, topology, frame, vertex_normals(topology, frame), params));
      progress(m, format("reference (%d rays) on frame %zu: %.0f ms", options.reference_rays, accuracy_frames[slot],
                         elapsed_ms(start)));
    }
    m.reference_ok = true;
  } catch (const std::exception& e) {
    failures.push_back(format("%s %u u=%g: reference %s", m.sequence.c_str(), m.vertices, u, e.what()));
  }
  for (MethodRow& row : m.rows) {
    if (!m.reference_ok || row.sky[0].empty() || row.sky[1].empty()) continue;
    auto first = abs_errors(row.sky[0], reference[0]);
    auto last = abs_errors(row.sky[1], reference[1]);
    row.err_first = error_stats(first);
    row.err_last = error_stats(last);
    first.insert(first.end(), last.begin(), last.end());
    row.err = error_stats(std::move(first));
  }

  // Static and kinetic must give the same output.
  const MethodRow* s = m.row("static");
  const MethodRow* k = m.row("kinetic");
  if (s->ok() && k->ok()) {
    double worst = 0;
    for (int slot = 0; slot < 2; ++slot) {
      if (s->sky[slot].size() != k->sky[slot].size()) {
        worst = INFINITY;
        break;
      }
      for (std::size_t i = 0; i < s->sky[slot].size(); ++i)
        worst = std::max(worst, std::abs(s->sky[slot][i] - k->sky[slot][i]));
    }
    m.max_static_kinetic = worst;
    const bool equal = worst <= kEqualTolerance;
    progress(m, format("max |A_static - A_kinetic| on frames %zu and %zu = %.3g %s", accuracy_frames[0],
                       accuracy_frames[1], worst, equal ? "(<= 1e-9: equal)" : "ASSERTION FAILED (> 1e-9)"));
    if (!equal)
      failures.push_back(format("%s %u u=%g: max |A_static - A_kinetic| = %.3g > 1e-9", m.sequence.c_str(), m.vertices,
                                u, worst));
  }
  if (const MethodRow* c = m.row("static"); c && !std::isnan(c->err.mean))
    progress(m, format("cone error vs %d rays: mean %.4f, p95 %.4f", options.reference_rays, c->err.mean, c->err.p95));
  return m;
}

// ---- Output ----

std::string num(double x, const char* fmt = "%.6g") { return std::isfinite(x) ? format(fmt, x) : std::string(); }

std::string csv_quote(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::vector<std::string> rebuild_reason_columns() {
  std::vector<std::string> names;
  for (int r = 1; r < static_cast<int>(kinetic::RebuildReason::count); ++r)
    names.push_back(std::string("rebuilt_") + kinetic::rebuild_reason_name(static_cast<kinetic::RebuildReason>(r)));
  return names;
}

void write_csv_header(std::ostream& out) {
  out << "sequence,source,vertices,triangles,planes,upsample,frames,method,rays,ms_per_frame,ms_first_frame,ms_min,"
         "ms_max,mean_err,p95_err,mean_err_first,p95_err_first,mean_err_last,p95_err_last,max_static_kinetic_diff,"
         "slice_vertices,peak_rss_mb,rss_before_mb,peak_increase_mb,peak_reset,events,flips,hull_enter,hull_leave,"
         "touches,side_changes_regular,side_changes_critical,removed,inserted,slices_unchanged,slices_repaired,"
         "slices_rebuilt,certificates,exact_certificates";
  for (const auto& name : rebuild_reason_columns()) out << ',' << name;
  out << ",status\n";
}

void write_csv_rows(std::ostream& out, const Measurement& m) {
  for (const MethodRow& r : m.rows) {
    double lo = NAN, hi = NAN;
    if (!r.ms.empty()) {
      lo = *std::min_element(r.ms.begin(), r.ms.end());
      hi = *std::max_element(r.ms.begin(), r.ms.end());
    }
    out << m.sequence << ',' << (m.real ? "blender" : "generated") << ',' << m.vertices << ',' << m.triangles << ','
        << m.planes << ',' << upsample_label(m.upsample) << ',' << m.frames << ',' << r.method << ',' << r.rays << ','
        << num(r.ms_per_frame()) << ',' << num(r.ms_first) << ',' << num(lo) << ',' << num(hi) << ','
        << num(r.err.mean) << ',' << num(r.err.p95) << ',' << num(r.err_first.mean) << ',' << num(r.err_first.p95)
        << ',' << num(r.err_last.mean) << ',' << num(r.err_last.p95) << ','
        << (r.method == "static" || r.method == "kinetic" ? num(m.max_static_kinetic) : std::string()) << ','
        << num(r.slice_vertices, "%.1f") << ',' << num(r.peak_mb, "%.1f") << ',' << num(r.rss_before_mb, "%.1f") << ','
        << num(r.peak_mb - r.rss_before_mb, "%.1f") << ',' << (r.peak_reset ? 1 : 0);
    if (r.kinetic && r.kinetic->frames) {
      const KineticTotals& t = *r.kinetic;
      const KineticFrameStats& k = t.sum;
      for (std::size_t v : {k.events(), k.flips, k.hull_enter, k.hull_leave, k.touches, k.side_changes_regular,
                            k.side_changes_critical, k.removed, k.inserted, k.slices_unchanged, k.slices_repaired,
                            k.slices_rebuilt, k.certificates, k.exact_certificates})
        out << ',' << num(t.per_frame(v), "%.2f");
      for (std::size_t i = 1; i < k.rebuilt_because.size(); ++i) out << ',' << num(t.per_frame(k.rebuilt_because[i]), "%.2f");
    } else {
      for (std::size_t i = 0; i < 14 + rebuild_reason_columns().size(); ++i) out << ',';
    }
    out << ',' << csv_quote(r.status) << '\n';
  }
  out.flush();
}

std::string cell_ms(const MethodRow* r) {
  if (!r) return "–";
  if (!r->ok()) return "failed";
  return num(r->ms_per_frame(), r->ms_per_frame() < 100 ? "%.1f" : "%.0f");
}
std::string cell_err(const MethodRow* r) {
  if (!r || std::isnan(r->err.mean)) return "–";
  return format("%.3f / %.3f", r->err.mean, r->err.p95);
}

/// Log-log slope of ms/frame against vertices between the smallest and largest generated size measured.
double growth_slope(const std::vector<Measurement>& all, const std::string& seq, double u, const std::string& method,
                    Index& small, Index& large) {
  const MethodRow *a = nullptr, *b = nullptr;
  small = large = 0;
  for (const auto& m : all) {
    if (m.sequence != seq || m.upsample != u) continue;
    const MethodRow* r = m.row(method);
    if (!r || !r->ok() || r->ms.empty()) continue;
    if (!a || m.vertices < small) a = r, small = m.vertices;
    if (!b || m.vertices > large) b = r, large = m.vertices;
  }
  if (!a || !b || small == large) return NAN;
  return std::log(b->ms_per_frame() / a->ms_per_frame()) / std::log(double(large) / double(small));
}

/// The source state, read when the run starts (the tree may change while it runs): HEAD, the tracked files that
/// differ from it (the measured code may include another engineer's work in progress) and a hash of that
/// difference, so that the results can be tied to an exact source state.
struct SourceState {
  std::string commit, dirty, dirty_hash;
};

SourceState read_source_state() {
  const fs::path root = fs::path(__FILE__).parent_path().parent_path();
  const std::string git = "git -C '" + root.string() + "' ";
  SourceState s;
  s.commit = shell_output(git + "rev-parse --short HEAD 2>/dev/null");
  s.dirty = shell_output(git + "diff HEAD --name-only 2>/dev/null | paste -sd, - | sed 's/,/, /g'");
  s.dirty_hash = shell_output(git + "diff HEAD 2>/dev/null | sha256sum | cut -c1-12");
  if (s.commit.empty()) s.commit = "unknown";
  return s;
}

/// The cheapest Embree row whose mean error is at most the cone engine's (of those measured), or null.
const MethodRow* matched_embree(const Measurement& m, const Options& options) {
  const MethodRow* s = m.row("static");
  if (!s || std::isnan(s->err.mean)) return nullptr;
  const MethodRow* match = nullptr;
  for (int rays : options.rays) {
    const MethodRow* e = m.row("embree" + std::to_string(rays));
    if (e && e->ok() && !std::isnan(e->err.mean) && e->err.mean <= s->err.mean &&
        (!match || e->ms_per_frame() < match->ms_per_frame()))
      match = e;
  }
  return match;
}

/// The README's headline (bench/run_frame_coherence.sh puts it there): per sequence and size, kinetic ÷ static
/// per frame at every temporal resolution, and the cone engines against Embree at matched error (u = 1).
std::string headline_table(const Options& options, const SourceState& source, const std::vector<Measurement>& all) {
  std::vector<double> ups;
  for (const auto& m : all)
    if (std::find(ups.begin(), ups.end(), m.upsample) == ups.end()) ups.push_back(m.upsample);
  std::sort(ups.begin(), ups.end());
  std::ostringstream out;
  out << "| sequence | vertices |";
  for (double u : ups) out << " kinetic ÷ static, u = " << upsample_label(u) << " |";
  out << " cone err (mean) | Embree rays at matched err | static ÷ Embree | kinetic ÷ Embree |\n|---|---|";
  for (std::size_t i = 0; i < ups.size(); ++i) out << "---|";
  out << "---|---|---|---|\n";
  std::vector<std::pair<std::string, Index>> keys;
  for (const auto& m : all)
    if (std::find(keys.begin(), keys.end(), std::make_pair(m.sequence, m.vertices)) == keys.end())
      keys.emplace_back(m.sequence, m.vertices);
  for (const auto& [seq, vertices] : keys) {
    out << "| " << seq << " | " << vertices << " |";
    const Measurement* native = nullptr;
    for (double u : ups) {
      std::string cell = "–";
      for (const auto& m : all) {
        if (m.sequence != seq || m.vertices != vertices || m.upsample != u) continue;
        if (u == 1) native = &m;
        const MethodRow* s = m.row("static");
        const MethodRow* k = m.row("kinetic");
        if (s && k && s->ok() && k->ok()) cell = format("%.2f", k->ms_per_frame() / s->ms_per_frame());
      }
      out << ' ' << cell << " |";
    }
    const MethodRow* match = native ? matched_embree(*native, options) : nullptr;
    const MethodRow* s = native ? native->row("static") : nullptr;
    const MethodRow* k = native ? native->row("kinetic") : nullptr;
    if (!match || !s) {
      out << ' ' << (s && !std::isnan(s->err.mean) ? format("%.3f", s->err.mean) : std::string("–"))
          << " | – | – | – |\n";
      continue;
    }
    out << ' ' << format("%.3f", s->err.mean) << " | " << match->rays << format(" (err %.3f)", match->err.mean)
        << " | " << format("%.2f", s->ms_per_frame() / match->ms_per_frame()) << " | "
        << (k && k->ok() ? format("%.2f", k->ms_per_frame() / match->ms_per_frame()) : std::string("–")) << " |\n";
  }
  out << "\nMedian wall time per frame, all engines in one run of `bench/run_frame_coherence.sh` on commit "
      << source.commit << (source.dirty.empty() ? "" : " (plus uncommitted changes)") << ", "
      << shell_output("nproc") << " cores (" << shell_output("grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'")
      << ", shared); < 1 means the first is faster. Matched error: the cheapest of " << options.rays.size()
      << " ray counts whose mean |A − A_ref| (against " << options.reference_rays
      << " rays) is at most the cone engine's. Everything else: `bench/results/frame_coherence.md`.\n";
  return out.str();
}

void write_markdown(const fs::path& path, const Options& options, const SourceState& source,
                    const std::vector<Measurement>& all, double total_seconds, bool memory_reset,
                    const std::vector<std::string>& failures) {
  std::ofstream out(path);
  const std::string& commit = source.commit;
  const std::string& dirty = source.dirty;
  const std::string& dirty_hash = source.dirty_hash;
  std::string cpu = shell_output("grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'");
  const std::string nproc = shell_output("nproc");
  const std::string load = shell_output("cut -d' ' -f1-3 /proc/loadavg");

  out << "# Frame coherence: kinetic vs static engine vs Embree ray casting\n\n";
  out << "Written by `bench/frame_coherence_bench` (`" << options.command_line << "`; `bench/run_frame_coherence.sh` "
      << "runs it and the plots). Commit **" << commit << "**"
      << (dirty.empty() ? std::string()
                        : " plus uncommitted changes to " + dirty + " (`git diff HEAD | sha256sum`: " + dirty_hash + "…)")
      << ". Machine: " << nproc
      << " cores (`nproc`), " << (cpu.empty() ? "unknown CPU" : cpu) << ", load average at the end " << load
      << " (shared: other jobs may run on the same cores). Whole run: " << format("%.0f", total_seconds)
      << " s wall.\n\n";
  out << "Every engine runs with TBB's default threads on the same frames and the same plan (`make_diffuse_plan` "
         "on the first frame, 6 orientations, planes one average edge length apart). **ms** = wall milliseconds "
         "per frame, the median over frames 1..N-1 (frame 0 builds the kinetic engine / Embree's BVH and is not "
         "counted). Embree = normals + BVH refit + K cosine-weighted rays per vertex and side. **Error** = "
         "|A − A_ref| over all vertices and both sides, pooled over frames 1 and N−1, against Embree with "
         << options.reference_rays
         << " rays (another seed; its own noise σ ≤ √(A(1−A)/K) ≤ 0.008), written mean / 95th percentile. The "
            "reference is the same estimator as the Embree rows, so their error is their sampling noise only, "
            "while the cone engine's includes its bias. "
            "u = temporal resolution: 1 native frames, 2/4/8 with 1/3/7 interpolated frames between native "
            "ones, 0.5 every other native frame. drape: the bundled Blender simulation from sample 20 (Blender "
            "frame 41); generated kinds: 48 frames per cycle from frame 8.\n\n";

  out << "## Headline\n\n" << headline_table(options, source, all) << "\n";
  out << "## Time per frame and accuracy\n\n";
  out << "| sequence | vertices | u | frames | static ms | kinetic ms | kinetic / static | Embree 64 ms (err) | Embree "
         "256 ms (err) | Embree 1024 ms (err) | cone err (mean / p95) | max \\|A_s − A_k\\| |\n";
  out << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& m : all) {
    const MethodRow* s = m.row("static");
    const MethodRow* k = m.row("kinetic");
    std::string ratio = "–";
    if (s && k && s->ok() && k->ok()) ratio = format("%.2f", k->ms_per_frame() / s->ms_per_frame());
    out << "| " << m.sequence << " | " << m.vertices << " | " << upsample_label(m.upsample) << " | " << m.frames
        << " | " << cell_ms(s) << " | " << cell_ms(k) << " | " << ratio;
    for (int rays : {64, 256, 1024}) {
      const MethodRow* e = m.row("embree" + std::to_string(rays));
      if (!e)
        out << " | –";
      else
        out << " | " << cell_ms(e) << (std::isnan(e->err.mean) ? "" : format(" (%.3f)", e->err.mean));
    }
    out << " | " << cell_err(s) << " | " << num(m.max_static_kinetic, "%.1e") << " |\n";
  }
  out << "\nEmbree errors: mean here, mean / 95th percentile below. \"–\": not measured at that temporal "
         "resolution (above 10,000 vertices, Embree and the reference run at the u given by "
         "--large-embree-upsample only: Embree's cost per frame does not depend on u).\n\n";

  out << "| sequence | vertices | u | Embree 64 err | Embree 256 err | Embree 1024 err | cone err frame 1 | cone err "
         "frame N−1 |\n|---|---|---|---|---|---|---|---|\n";
  for (const auto& m : all) {
    out << "| " << m.sequence << " | " << m.vertices << " | " << upsample_label(m.upsample);
    for (int rays : {64, 256, 1024}) out << " | " << cell_err(m.row("embree" + std::to_string(rays)));
    const MethodRow* s = m.row("static");
    out << " | " << (s && !std::isnan(s->err_first.mean) ? format("%.3f / %.3f", s->err_first.mean, s->err_first.p95) : "–")
        << " | " << (s && !std::isnan(s->err_last.mean) ? format("%.3f / %.3f", s->err_last.mean, s->err_last.p95) : "–")
        << " |\n";
  }

  // Matched error: per sequence and size, at u = 1 (Embree's cost does not depend on u).
  out << "\n## Matched error\n\nPer sequence and size: the cheapest ray count (of those measured) whose mean error is "
         "at most the cone engine's, and pleat's time per frame relative to it (< 1: pleat is faster at that "
         "accuracy). Embree and the cone error at u = 1; the kinetic engine at u = 1 and at the largest u "
         "measured.\n\n";
  double u_max = 0;
  for (const auto& m : all) u_max = std::max(u_max, m.upsample);
  out << "| sequence | vertices | cone mean err | cheapest K with err ≤ cone | its err | Embree ms | static ÷ Embree | "
         "kinetic ÷ Embree (u=1) | kinetic ÷ Embree (u=" << upsample_label(u_max) << ") |\n|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& m : all) {
    if (m.upsample != 1) continue;
    const MethodRow* s = m.row("static");
    if (!s || std::isnan(s->err.mean)) continue;
    const MethodRow* match = matched_embree(m, options);
    out << "| " << m.sequence << " | " << m.vertices << " | " << format("%.3f", s->err.mean) << " | ";
    if (!match) {
      out << "none of " << options.rays.size() << " | – | – | – | – | – |\n";
      continue;
    }
    const MethodRow* k1 = m.row("kinetic");
    const MethodRow* kmax = nullptr;
    for (const auto& other : all)
      if (other.sequence == m.sequence && other.vertices == m.vertices && other.upsample == u_max)
        kmax = other.row("kinetic");
    const double e_ms = match->ms_per_frame();
    out << match->rays << " | " << format("%.3f", match->err.mean) << " | " << cell_ms(match) << " | "
        << format("%.2f", s->ms_per_frame() / e_ms) << " | "
        << (k1 && k1->ok() ? format("%.2f", k1->ms_per_frame() / e_ms) : std::string("–")) << " | "
        << (kmax && kmax->ok() ? format("%.2f", kmax->ms_per_frame() / e_ms) : std::string("–")) << " |\n";
  }

  // Growth with vertex count.
  out << "\n## Growth with vertex count\n\nLog-log slope of ms/frame against vertices between the smallest and "
         "largest size measured (generated kinds; 1 = linear), per method and temporal resolution.\n\n";
  std::vector<std::string> methods{"static", "kinetic"};
  for (int rays : options.rays) methods.push_back("embree" + std::to_string(rays));
  out << "| sequence | u | sizes |";
  for (const auto& method : methods) out << ' ' << method << " |";
  out << "\n|---|---|---|";
  for (std::size_t i = 0; i < methods.size(); ++i) out << "---|";
  out << '\n';
  bool any_slope = false;
  std::vector<std::pair<std::string, double>> keys;
  for (const auto& m : all)
    if (!m.real && std::find(keys.begin(), keys.end(), std::make_pair(m.sequence, m.upsample)) == keys.end())
      keys.emplace_back(m.sequence, m.upsample);
  for (const auto& [seq, u] : keys) {
    Index small = 0, large = 0;
    std::string cells;
    bool any = false;
    for (const auto& method : methods) {
      Index a = 0, b = 0;
      const double slope = growth_slope(all, seq, u, method, a, b);
      if (std::isfinite(slope)) small = a, large = b, any = true;
      cells += ' ';
      cells += std::isfinite(slope) ? format("%.2f", slope) : std::string("–");
      cells += " |";
    }
    if (!any) continue;
    any_slope = true;
    out << "| " << seq << " | " << upsample_label(u) << " | " << small << "→" << large << " |" << cells << '\n';
  }
  if (!any_slope) out << "\n(One size measured: no slope.)\n";

  // Kinetic counters.
  out << "\n## Kinetic engine, mean per frame\n\nEvents = flips + hull enter + hull leave + touches; side changes = "
         "(mesh vertex, plane) crossings, regular / critical; removed / inserted = slice vertices edited locally; "
         "slices unchanged / repaired / rebuilt (of all planes; rebuild reasons in the CSV).\n\n";
  out << "| sequence | vertices | u | planes | events | flips | hull enter / leave | touches | side changes reg / crit | "
         "removed / inserted | unchanged | repaired | rebuilt | certificates (exact) |\n";
  out << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& m : all) {
    const MethodRow* k = m.row("kinetic");
    out << "| " << m.sequence << " | " << m.vertices << " | " << upsample_label(m.upsample) << " | " << m.planes;
    if (!k || !k->kinetic || !k->kinetic->frames) {
      out << " | " << (k ? k->status : "–") << " | | | | | | | | | |\n";
      continue;
    }
    const KineticTotals& totals = *k->kinetic;
    const KineticFrameStats& t = totals.sum;
    auto pf = [&](std::size_t v) { return format("%.1f", totals.per_frame(v)); };
    out << " | " << pf(t.events()) << " | " << pf(t.flips) << " | " << pf(t.hull_enter) << " / " << pf(t.hull_leave)
        << " | " << pf(t.touches) << " | " << pf(t.side_changes_regular) << " / " << pf(t.side_changes_critical)
        << " | " << pf(t.removed) << " / " << pf(t.inserted) << " | " << pf(t.slices_unchanged) << " | "
        << pf(t.slices_repaired) << " | " << pf(t.slices_rebuilt) << " | " << pf(t.certificates) << " ("
        << pf(t.exact_certificates) << ") |";
    if (!k->ok()) out << " " << k->status;
    out << '\n';
  }

  // Memory.
  out << "\n## Peak memory\n\n";
  out << "The cone engines run in a child process (both engines alive, frames in turn), Embree in the main one, "
         "after them. **peak** = VmHWM (peak resident set) of the process at the end of a window, **+** = peak − "
         "resident set at the window's start, i.e. what the engine added at its peak (frames, plan, TBB threads "
         "were already resident). ";
  if (memory_reset)
    out << "VmHWM is reset (`echo 5 > /proc/self/clear_refs`, after `malloc_trim`) at the start of each window: "
           "static = its construction and frame 0 (it allocates almost nothing on later frames); kinetic = its "
           "construction and every later frame, which also holds the static engine's per-frame transients; "
           "Embree K = the scene and all frames at K rays.\n\n";
  else
    out << "Resetting VmHWM failed on this machine, so **peak** is the process-wide high-water mark: within a "
           "process, a later window's peak includes the earlier ones' (order: static, kinetic; Embree 64, 256, "
           "1024).\n\n";
  out << "| sequence | vertices | u | static MB (+) | kinetic MB (+) | Embree 64 MB (+) | Embree 256 MB (+) | Embree 1024 MB "
         "(+) |\n|---|---|---|---|---|---|---|---|\n";
  for (const auto& m : all) {
    out << "| " << m.sequence << " | " << m.vertices << " | " << upsample_label(m.upsample);
    for (const std::string method : {"static", "kinetic", "embree64", "embree256", "embree1024"}) {
      const MethodRow* r = m.row(method);
      out << " | " << (r ? format("%.0f (+%.0f)", r->peak_mb, r->peak_mb - r->rss_before_mb) : std::string("–"));
    }
    out << " |\n";
  }

  out << "\n## Problems\n\n";
  if (failures.empty())
    out << "None: every engine ran on every measurement, and static and kinetic agreed to 1e-9 wherever both ran.\n";
  for (const auto& f : failures) out << "- " << f << '\n';
}

int run(int argc, char** argv) {
  const Options options = parse_options(argc, argv);
  if (!options.kinetic_worker.empty()) return run_kinetic_worker(options);
  const auto run_start = Clock::now();
  const SourceState source = read_source_state();
  fs::create_directories(options.out);
  const fs::path csv_path = options.out / "frame_coherence.csv";
  const fs::path md_path = options.out / "frame_coherence.md";
  const fs::path csv_tmp = csv_path.string() + ".partial";
  std::ofstream csv(csv_tmp);
  if (!csv) {
    std::fprintf(stderr, "frame_coherence_bench: cannot write %s\n", csv_tmp.c_str());
    return 2;
  }
  write_csv_header(csv);

  double rss0 = 0;
  const bool memory_reset = start_memory_window(rss0);
  std::vector<Measurement> all;
  std::vector<std::string> failures;
  for (const std::string& name : options.sequences) {
    std::vector<Index> sizes = options.sizes;
    if (name == "drape") sizes = {0};  // fixed size
    for (Index size : sizes) {
      std::optional<Sequence> seq;
      try {
        seq = make_sequence(name, size, options);
      } catch (const std::exception& e) {
        std::fprintf(stderr, "[frame_coherence] %s %u: cannot make the sequence: %s\n", name.c_str(), size, e.what());
        failures.push_back(format("%s %u: %s", name.c_str(), size, e.what()));
        continue;
      }
      const bool large = seq->topology.num_vertices > kLargeVertices;
      const int frames = large && options.large_frames ? options.large_frames : options.frames;
      const auto& ups = large && !options.large_upsample.empty() ? options.large_upsample : options.upsample;
      for (double u : ups) {
        const bool with_embree =
            !large || options.large_embree_upsample.empty() ||
            std::find(options.large_embree_upsample.begin(), options.large_embree_upsample.end(), u) !=
                options.large_embree_upsample.end();
        try {
          all.push_back(measure(*seq, u, frames, with_embree, options, failures));
          write_csv_rows(csv, all.back());
        } catch (const std::exception& e) {
          std::fprintf(stderr, "[frame_coherence] %s %u u=%g: FAILED: %s\n", name.c_str(), seq->topology.num_vertices,
                       u, e.what());
          failures.push_back(format("%s %u u=%g: %s", name.c_str(), seq->topology.num_vertices, u, e.what()));
        }
        std::fprintf(stderr, "[frame_coherence] elapsed %.0f s\n", elapsed_ms(run_start) / 1000.0);
      }
    }
  }
  csv.close();
  fs::rename(csv_tmp, csv_path);
  const double total = elapsed_ms(run_start) / 1000.0;
  write_markdown(md_path, options, source, all, total, memory_reset, failures);
  {
    std::ofstream headline(options.out / "frame_coherence_headline.md");
    headline << headline_table(options, source, all);
  }
  std::printf("frame_coherence: wrote %s and %s (%zu measurements, %.0f s)\n", csv_path.c_str(), md_path.c_str(),
              all.size(), total);
  if (!failures.empty()) {
    for (const auto& f : failures) std::printf("frame_coherence: FAILED: %s\n", f.c_str());
    return 1;
  }
  return 0;
}

}  // namespace
}  // namespace pleat

int main(int argc, char** argv) {
  try {
    return pleat::run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "frame_coherence_bench: %s\n", e.what());
    return 1;
  }
}
