// The cone engines (static and kinetic) of one measurement, frame by frame, in a child process, so that a
// hang or a crash of an engine is reported and the benchmark goes on.
//
// The child is this program run with the internal flag --worker FILE (plus the measurement's sequence, size,
// u, frames, --worker-threads T and, where accuracy is measured, --worker-keep-sky and --plans): it rebuilds
// the same frames and plans, runs static.compute(k) and kinetic.advance(k) (then the other plans' static
// engines) in turn on every frame (so that the times of a frame see the same load on a shared machine) with
// T TBB threads, and writes the rows to FILE (text, one key per line) and a line per step to FILE.beat. The
// parent kills the child when FILE.beat stays unchanged longer than the allowed silence: --kinetic-timeout if
// given, else (60 s, --quick 20 s) + 1 ms per vertex + 30 x the longest gap between heartbeats so far.
//
// Memory (memory_window.hpp): the peak is reset before the static engine is built and read after its frame 0
// (it allocates almost nothing later), then reset before the kinetic engine is built and read at the end (so
// the kinetic window also holds the static engine's per-frame transients, and the other plans' engines and
// their transients where they run: the paper's and --plans, at u = 1).
#pragma once

#include <array>
#include <string>
#include <variant>

#include "bench/coherence/measurement.hpp"
#include "bench/coherence/options.hpp"
#include "static_core/slicing_plan.hpp"

namespace pleat::bench {

/// The static engine alone, in this process (when the child failed, and timed in turn with Embree at K*),
/// with TBB's current thread limit.
MethodRow run_static(const MeshTopology& topology, const SlicingPlan& plan, const std::vector<Frame>& frames,
                     bool keep_sky);

/// Entry of the child process (Options::worker_result set). Returns the exit status.
int run_cone_worker(const Options& options);

/// Runs the child for one measurement: the rows {static, kinetic} (with `keep_sky` also "paper": the static
/// engine on make_paper_plan, the baseline of the accuracy and cost comparison, then a "plan" row per
/// Options::plans, the static engine on that plan, its name in MethodRow::config), or why the child failed.
std::variant<std::vector<MethodRow>, std::string> run_cone_engines_in_child(const std::string& sequence,
                                                                            Index size, Index vertices,
                                                                            double u, int frames, int threads,
                                                                            bool keep_sky,
                                                                            const Options& options);

}  // namespace pleat::bench
