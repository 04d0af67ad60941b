#include "cli/job.hpp"

#include <sstream>

#include "cli/input_warnings.hpp"
#include "cli/job_error.hpp"
#include "cli/memory_limit.hpp"
#include "cli/world.hpp"

namespace pleat::cli {

void JobOptions::add_to(CLI::App& command, bool engine_options) {
  in.add_to(command);
  add_frames_option(command, frames);
  if (engine_options) {
    command
        .add_option("--engine", engine,
                    "kinetic (default: slices kept alive and repaired between frames) or static (full "
                    "recompute per frame); both give the same output")
        ->check(CLI::IsMember({"static", "kinetic"}));
    command
        .add_option_function<double>(
            "--max-edit-fraction",
            [this](double value) {
              policy.max_edit_fraction = value;
              check();
            },
            "kinetic: rebuild a slice when the slice vertices removed, inserted and put back in a frame "
            "exceed this fraction of it (+2)")
        ->default_str((std::ostringstream() << policy.max_edit_fraction).str());
    command.add_flag("--serial", serial, "one thread (default: TBB over slices)");
  }
  plan.add_to(command);
  scene.add_to(command, [this] { check(); });
}

JobSpec JobOptions::spec() const {
  JobSpec spec;
  spec.plan = plan;
  spec.engine = engine;
  spec.max_edit_fraction = policy.max_edit_fraction;
  spec.ground = scene.ground;
  spec.contact_tolerance = scene.contact_tolerance;
  return spec;
}

int JobOptions::threads() const { return serial ? 1 : run_threads(); }

namespace {

/// Before any work, under a known memory limit: refuses a first frame that cannot fit (memory_limit.hpp).
void check_memory(const JobOptions& options, const PreparedJob& job) {
  const Frame frame = job.sequence().frame(job.first);
  const Frame sliced = job.scene->num_occluders() ? job.scene->with_occluders(job.first, frame) : frame;
  compute_frame(
      [&] {
        check_memory_before_start(job.scene->topology(), sliced, job.plan, job.first, options.threads());
      },
      options.in, job.first);
}

}  // namespace

std::unique_ptr<PreparedJob> prepare(const JobOptions& options, const JobSteps& steps) {
  together([&] {
    if (World::root() && steps.check_outputs) steps.check_outputs();
  });
  auto job = std::make_unique<PreparedJob>(load_shared(options.in.input, options.in.cache));
  job->loaded_at = World::seconds();
  const MeshSequence& sequence = job->sequence();
  together([&] { parse_frame_range(options.frames, sequence.num_frames(), job->first, job->last); });
  // The cloth in its scene: the engines slice the occluders with it (every rank reads them).
  together([&] { job->scene.emplace(options.scene.make(sequence)); });
  if (steps.before_plan) job->computes_cones = steps.before_plan(sequence, job->first, job->last);
  // The plan is made for the whole sequence (never from the requested frames), on rank 0, and sent to the
  // others; rank 0 looks at the first requested frame (later frames are not checked, `pleat info` checks
  // them).
  together([&] {
    if (!World::root()) return;
    if (job->computes_cones) job->plan = options.plan.make(sequence);
    warn_about_cloth(sequence, job->first);
    if (!job->computes_cones) return;
    if (steps.on_plan) steps.on_plan(sequence, job->plan, job->first);
    check_memory(options, *job);
  });
  if (job->computes_cones) broadcast_plan(job->plan);
  job->planned_at = World::seconds();
  job->chunks = plan_chunks(job->input, job->first, job->last, options.chunking.chunks,
                            job->computes_cones ? &job->plan : nullptr, options.chunking.checkpoint,
                            steps.key(job->plan));
  job->chunked_at = World::seconds();
  return job;
}

void run_frames(const PreparedJob& job, const std::string& what, const ComputeChunk& compute,
                const ConsumeFrame& consume, const FrameWork* work) {
  run_chunks(job.chunks, what, compute, consume, work);
}

std::string chunks_line(const ChunkJob& chunks) {
  if (chunks.bounds.size() <= 2 && !World::distributed()) return "";
  return "  " + std::to_string(chunks.bounds.size() - 1) + " chunks over " + std::to_string(World::size()) +
         " ranks" +
         (chunks.kept_chunks ? ", " + std::to_string(chunks.kept_chunks) + " kept from the checkpoint" : "") +
         "\n";
}

}  // namespace pleat::cli
