// The frame-coherence benchmark's outputs: the CSV (one row per measurement x method x rays x threads), the
// markdown report and the headline tables of docs/benchmarks.md.
#pragma once

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "bench/coherence/measurement.hpp"
#include "bench/coherence/options.hpp"

namespace pleat::bench {

/// The source state, read when the run starts: HEAD, the tracked files that differ from it and a hash of
/// that difference, so that the results can be tied to an exact source state.
struct SourceState {
  std::string commit, dirty, dirty_hash;
};
SourceState read_source_state();

/// Embree's K* (for the mean or the 95th-percentile error of the static engine) at `threads`, from the
/// ladder of a u = 1 measurement (errors and flicker of its one-thread rows, times of `threads`' rows: wall
/// time, or process CPU time if `cpu`). False when the ladder or the cone error is missing.
bool matched_embree(const Measurement& m, int threads, bool p95, MatchedRays& out, bool cpu = false);
/// The same for the error of `target`, any row of m that measured accuracy (a "plan" row, the paper's).
bool matched_embree(const Measurement& m, const MethodRow& target, int threads, bool p95, MatchedRays& out,
                    bool cpu = false);

void write_csv_header(std::ostream& out);
void write_csv_rows(std::ostream& out, const Measurement& m);

/// The headline of docs/benchmarks.md: the cone engines against Embree at matched error, and cost per element
/// with kinetic ÷ static per temporal resolution.
std::string headline_tables(const Options& options, const std::vector<Measurement>& all);

void write_markdown(const std::filesystem::path& path, const Options& options, const SourceState& source,
                    const std::vector<Measurement>& all, double total_seconds, bool memory_reset,
                    const std::vector<std::string>& failures);

}  // namespace pleat::bench
