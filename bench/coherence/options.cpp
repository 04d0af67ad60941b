// Flag parsing of the frame-coherence benchmark.
#include "bench/coherence/options.hpp"

#include <cstdio>
#include <cstdlib>

#include "bench/bench_args.hpp"
#include "bench/coherence/sequences.hpp"

namespace pleat::bench {

namespace {

[[noreturn]] void usage_error(const std::string& what) {
  std::fprintf(stderr,
               "frame_coherence_bench: %s (see the flags at the top of bench/frame_coherence_bench.cpp)\n",
               what.c_str());
  std::exit(2);
}

template <class T, class F>
std::vector<T> parse_list(const std::string& text, F&& convert) {
  std::vector<T> values;
  for (const auto& s : split(text)) values.push_back(convert(s));
  return values;
}

}  // namespace

Options parse_options(int argc, char** argv) {
  Options o;
  for (int i = 0; i < argc; ++i) o.command_line += (i ? " " : "") + std::string(argv[i]);
  o.data = std::filesystem::path(PLEAT_BENCH_SOURCE_DIR) / "data";
  bool explicit_sequences = false, explicit_sizes = false, explicit_upsample = false, explicit_frames = false,
       explicit_rays = false, explicit_reference = false;
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
    } else if (arg == "--rays") {
      o.rays = parse_list<int>(next(), to_int);
      explicit_rays = true;
    } else if (arg == "--threads") {
      o.threads = parse_list<int>(next(), to_int);
    } else if (arg == "--sweep-rays") {
      o.sweep_rays = to_int(next());
    } else if (arg == "--random-rays") {
      o.random_rays = to_int(next());
    } else if (arg == "--reference-rays") {
      o.reference_rays = to_int(next());
      explicit_reference = true;
    } else if (arg == "--reference-sample") {
      o.reference_sample = Index(to_int(next()));
    } else if (arg == "--plans") {
      try {
        for (const std::string& item : split(next())) o.plans.push_back(parse_setting(item, arg));
      } catch (const std::invalid_argument& e) {
        usage_error(e.what());
      }
    } else if (arg == "--data") {
      o.data = next();
    } else if (arg == "--cloth-alone") {
      o.cloth_alone = true;
    } else if (arg == "--vertex-errors") {
      o.vertex_errors = true;
    } else if (arg == "--kinetic-timeout") {
      o.kinetic_timeout_s = to_double(next());
    } else if (arg == "--worker") {
      o.worker_result = next();
    } else if (arg == "--worker-threads") {
      o.worker_threads = to_int(next());
    } else if (arg == "--worker-keep-sky") {
      o.worker_keep_sky = true;
    } else if (arg == "--help" || arg == "-h") {
      std::printf(
          "frame_coherence_bench [--quick] [--out DIR] [--sequences "
          "drape,pile,rucked,curtain,roll,flag,sleeve]\n"
          "  [--sizes 3025,29929] [--upsample 0.5,1,2,4,8] [--frames 8] [--large-frames 4] [--large-upsample "
          "LIST]\n"
          "  [--rays 8,12,16,24,32,48,64,96,128,256,1024] [--threads 1,2] [--sweep-rays 32] [--random-rays "
          "16]\n"
          "  [--reference-rays 4096] [--reference-sample 4000] [--data DIR] [--cloth-alone] "
          "[--kinetic-timeout S]\n"
          "  [--vertex-errors]\n"
          "  [--plans orientations:spacing:storage[:spiral],...]\n");
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
    if (!explicit_rays) o.rays = {8, 16, 64};
    if (!explicit_reference) o.reference_rays = 512;
    o.large_frames = 0;
  }
  if (o.sequences.empty()) o.sequences = default_sequences(o.data);
  if (o.frames < 3 || (o.large_frames != 0 && o.large_frames < 3)) usage_error("--frames must be at least 3");
  for (double u : o.upsample)
    if (!(u > 0)) usage_error("--upsample values must be positive");
  for (int k : o.rays)
    if (k < 1) usage_error("--rays values must be positive");
  for (std::size_t i = 1; i < o.rays.size(); ++i)
    if (o.rays[i] <= o.rays[i - 1]) usage_error("--rays must be ascending");
  if (o.threads.empty()) usage_error("--threads needs at least one count");
  for (int t : o.threads)
    if (t < 1) usage_error("--threads values must be positive");
  if (o.reference_rays < 1 || o.sweep_rays < 1 || o.random_rays < 0)
    usage_error("ray counts must be positive");
  if (o.reference_sample < 1) usage_error("--reference-sample must be positive");
  for (std::size_t i = 0; i < o.plans.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (setting_name(o.plans[i]) == setting_name(o.plans[j]))
        usage_error("--plans names " + setting_name(o.plans[i]) + " twice");
  for (const auto& s : o.sequences)
    if (!is_sequence_name(s, o.data)) usage_error("unknown sequence '" + s + "'");
  return o;
}

}  // namespace pleat::bench
