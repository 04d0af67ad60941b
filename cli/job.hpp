// The job layer under `pleat visibility` and `pleat shade`: a job's specification declared as options
// (JobOptions: the input, the frames, the scene, the plan, the engine's parameters, the chunking; one check,
// sim_io/job_spec.hpp's, shared with the Python module), the collective preamble every rank runs once
// (prepare: outputs checked, the input loaded in shares, the frame range, the scene, the plan made by rank 0
// and broadcast, the chunks planned against the checkpoint), and the run of the frames (run_frames: the
// command's compute and consume callbacks over the chunks, cli/run_chunks.hpp). A command is its own
// options, its two callbacks and its outputs. Every function here is collective (cli/world.hpp).
#pragma once

#include <CLI/CLI.hpp>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "cli/chunk_plan.hpp"
#include "cli/cli_options.hpp"
#include "cli/run_chunks.hpp"
#include "cli/shared_load.hpp"
#include "kinetic/kinetic_visibility.hpp"
#include "sim_io/job_spec.hpp"
#include "sim_io/scene.hpp"

namespace pleat::cli {

/// A job's specification as command-line options.
struct JobOptions {
  InputOptions in;
  std::string frames;  ///< --frames
  SceneOptions scene;
  PlanOptions plan;
  ChunkOptions chunking;
  std::string engine = "kinetic";  ///< --engine
  bool serial = false;             ///< --serial: one thread
  kinetic::KineticPolicy policy;   ///< --max-edit-fraction

  /// Declares INPUT, --cache, --frames, the plan's and the scene's options, and with `engine` --engine,
  /// --serial and --max-edit-fraction; every value is checked as it is parsed (check()).
  void add_to(CLI::App& command, bool engine_options);
  /// The specification shared with the Python module.
  JobSpec spec() const;
  /// spec().check(), naming the command line's options: std::invalid_argument.
  void check() const { spec().check(JobSpec::Naming::CommandLine); }
  /// The threads a frame runs on.
  int threads() const;
};

/// What a command adds to the preamble.
struct JobSteps {
  /// On rank 0, before anything is read: refuse outputs that cannot be written (check_outputs).
  std::function<void()> check_outputs;
  /// Collective, once the scene is made and before the plan: the command's own preparation (shade: the up
  /// axis, a cone cache). Returns whether cones are computed (false: no plan is made or sent).
  std::function<bool(const MeshSequence& sequence, std::size_t first, std::size_t last)> before_plan;
  /// On rank 0, once the plan is made: what the command reports about it.
  std::function<void(const MeshSequence& sequence, const SlicingPlan& plan, std::size_t first)> on_plan;
  /// The checkpoint's key: what decides the outputs' bytes besides the frames and the plan.
  std::function<std::uint64_t(const SlicingPlan& plan)> key;
};

/// A prepared job: what every rank holds alike before the frames are computed (not movable: the scene
/// points at the sequence).
struct PreparedJob {
  explicit PreparedJob(SharedSequence loaded) : input(std::move(loaded)) {}
  PreparedJob(const PreparedJob&) = delete;
  PreparedJob& operator=(const PreparedJob&) = delete;

  SharedSequence input;
  std::size_t first = 0, last = 0;  ///< the requested frames
  std::optional<Scene> scene;       ///< the cloth in its scene (occluders, ground)
  bool computes_cones = true;       ///< else the command reads them (no plan)
  SlicingPlan plan;
  ChunkJob chunks;
  double loaded_at = 0.0, planned_at = 0.0, chunked_at = 0.0;  ///< this rank's start-up (World::seconds)

  const MeshSequence& sequence() const { return input.sequence; }
};

/// The collective preamble, once: outputs checked (rank 0), the input loaded with the loading pass shared
/// (load_shared), --frames, the scene, the command's steps, the plan made by rank 0 (written by --save-plan,
/// its first frame warned about and its memory checked) and broadcast, the chunks planned. Errors are agreed
/// on (together): every rank throws the one rank 0 reports.
std::unique_ptr<PreparedJob> prepare(const JobOptions& options, const JobSteps& steps);

/// Runs the prepared job's chunks: `compute` on this rank's, `consume` on rank 0 in frame order
/// (run_chunks).
void run_frames(const PreparedJob& job, const std::string& what, const ComputeChunk& compute,
                const ConsumeFrame& consume, const FrameWork* work);

/// "  N chunks over R ranks, K kept from the checkpoint\n" when the job was split, else "".
std::string chunks_line(const ChunkJob& chunks);

}  // namespace pleat::cli
