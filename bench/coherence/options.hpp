// The frame-coherence benchmark's options (bench/frame_coherence_bench.cpp lists the flags).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "bench/coherence/plan_setting.hpp"
#include "static_core/mesh.hpp"

namespace pleat::bench {

struct Options {
  bool quick = false;
  std::filesystem::path out = "bench/results";
  std::vector<std::string> sequences;  // default: every real sequence in data/, then the generated kinds
  std::vector<Index> sizes{3025, 29929};
  std::vector<double> upsample{0.5, 1, 2, 4, 8};
  int frames = 8;
  int large_frames = 4;                // 0: frames
  std::vector<double> large_upsample;  // empty: upsample
  std::vector<int> rays{8, 12, 16, 24, 32, 48, 64, 96, 128, 256, 1024};
  std::vector<int> threads{1, 2};  // thread counts at u = 1 (the first also at every u)
  int sweep_rays = 32;             // ray count of the peer-configuration sweep
  int random_rays = 16;            // ray count of the per-frame-random-directions row (0: none)
  int reference_rays = 4096;
  Index reference_sample = 4000;  // the reference estimates about this many vertices (a stride above it)
  double kinetic_timeout_s = 0;   // 0: automatic (see cone_worker.hpp)
  std::filesystem::path data;
  std::vector<Setting> plans;  // extra static-engine rows at u = 1 (the first thread count), one per plan
  bool cloth_alone = false;    // real sequences without the colliders they were simulated against
  bool vertex_errors = false;  // write each measurement's per-value errors at u = 1 (write_vertex_errors)
  // Internal: this process is a cone-engine worker for one measurement, writing its rows here.
  std::filesystem::path worker_result;
  int worker_threads = 1;
  bool worker_keep_sky = false;
  std::string command_line;
};

/// Parses the flags; exits with status 2 and a message on a bad one, 0 after --help.
Options parse_options(int argc, char** argv);

}  // namespace pleat::bench
