// pleat visibility: per-vertex sky visibility A of both sides, every frame, as the visibility CSV.
#include <chrono>
#include <iostream>
#include <memory>
#include <new>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>

#include "cli/cli_options.hpp"
#include "cli/commands.hpp"
#include "cli/contact_warning.hpp"
#include "cli/global_options.hpp"
#include "cli/input_warnings.hpp"
#include "cli/job.hpp"
#include "cli/job_error.hpp"
#include "cli/memory_limit.hpp"
#include "cli/run_chunks.hpp"
#include "cli/shared_load.hpp"
#include "cli/world.hpp"
#include "kinetic/engine.hpp"
#include "kinetic/kinetic_visibility.hpp"
#include "shading/cone_cache.hpp"
#include "sim_io/mesh_report.hpp"
#include "sim_io/mesh_sequence.hpp"
#include "sim_io/visibility_csv.hpp"
#include "static_core/plan_codec.hpp"
#include "static_core/visibility.hpp"
#include "support/atomic_file.hpp"
#include "support/byte_stream.hpp"
#include "support/fingerprint.hpp"

namespace pleat::cli {
namespace {

struct VisibilityOptions {
  JobOptions job;  // the input, frames, scene, plan, engine and chunking
  std::string output;
  std::string cones;  // optional cone cache (.cones)
  std::string cones_encoding = "exact";
  std::string stats;
  std::string timings;
};

// What --stats records per frame is what the frame and the plan determine, so that it is the same byte for
// byte whatever the engine, the number of ranks or the chunk boundaries (issue 16): counts of slices,
// regions, windows, crossings. How the run went -- the time of each frame, the rank and chunk that computed
// it, the kinetic engine's counters (which depend on where its chunk started: a chunk's first frame is a
// static build) -- goes to --timings.
nlohmann::json stats_json(std::size_t frame, const VisibilityStats& s, const MeshSequence& cloth) {
  return {{"frame", frame},
          {"slices", s.slices},
          {"slice_vertices", s.slice_vertices},
          {"regions", s.regions},
          {"windows", s.windows},
          {"regions_with_holes", s.regions_with_holes},
          {"crossing_slices", s.crossing_slices},
          {"chain_crossings", s.chain_crossings},
          {"filled_fraction", s.filled_fraction},
          {"penetrating_vertices", s.penetrating_vertices},
          {"deepest_penetration", s.deepest_penetration},
          {"deepest_vertex", input_vertex(cloth, s.deepest_vertex)}};
}

nlohmann::json kinetic_json(const KineticFrameStats& k) {
  nlohmann::json rebuilt;
  for (int r = 1; r < static_cast<int>(kinetic::RebuildReason::count); ++r)
    rebuilt[kinetic::rebuild_reason_name(static_cast<kinetic::RebuildReason>(r))] = k.rebuilt_because[r];
  nlohmann::json out;
  for (const KineticCounter& c : kKineticCounters) out[c.name] = k.*c.field;
  out["rebuilt_because"] = rebuilt;
  out["seconds_by_stage"] = {
      {"structure", k.structure_seconds}, {"cones_2d", k.cone_seconds}, {"assembly", k.assembly_seconds}};
  return out;
}

/// The streamed outputs of rank 0: the CSV and, with --cones, the cone cache.
struct VisibilityOutputs {
  std::optional<VisibilityCsvWriter> csv;
  std::optional<ConeCacheWriter> cones;

  /// Makes the outputs' directories and opens the writers for frames [first, last).
  void open(const VisibilityOptions& options, const MeshSequence& sequence, std::size_t first,
            std::size_t last, ConeEncoding encoding) {
    create_parent_directory(options.output);
    if (!options.stats.empty()) create_parent_directory(options.stats);
    if (!options.timings.empty()) create_parent_directory(options.timings);
    csv.emplace(options.output, sequence.welded_of_input(), isolated_vertices(sequence.topology()));
    if (options.cones.empty()) return;
    create_parent_directory(options.cones);
    std::vector<std::uint32_t> frame_ids;
    for (std::size_t f = first; f < last; ++f) frame_ids.push_back(std::uint32_t(f));
    cones.emplace(options.cones, sequence.topology(), sequence.welded_of_input(), sequence.frame_rate(),
                  options.job.plan.describe(), std::move(frame_ids), encoding);
  }

  /// Writes out and closes every output (--stats and --timings too: a full disk fails here, replacing
  /// nothing), then renames them all into place together, the CSV last: it exists only when every other
  /// output was written.
  void commit(const VisibilityOptions& options, const nlohmann::json& stats, nlohmann::json& timings) {
    std::optional<AtomicFile> stats_file, timings_file;
    if (!options.stats.empty()) {
      stats_file.emplace(options.stats);
      stats_file->stream() << stats.dump(2) << "\n";
      stats_file->close();
    }
    timings["seconds_total"] = World::seconds();
    if (!options.timings.empty()) {
      timings_file.emplace(options.timings);
      timings_file->stream() << timings.dump(2) << "\n";
      timings_file->close();
    }
    if (cones) cones->close();
    csv->close();
    const CommitWindow window;
    if (stats_file) stats_file->commit();
    if (timings_file) timings_file->commit();
    if (cones) cones->commit();
    csv->commit();
  }
};

/// Refuses, before any work, outputs that cannot be written or that are inputs (check_outputs).
void check_visibility_outputs(const VisibilityOptions& options) {
  const JobOptions& job = options.job;
  std::vector<InputFile> inputs = job.in.files();
  for (const auto& more : {job.scene.files(), job.plan.files()})
    inputs.insert(inputs.end(), more.begin(), more.end());
  check_outputs({{"-o", options.output},
                 {"--stats", options.stats},
                 {"--timings", options.timings},
                 {"--cones", options.cones, /*stdout_allowed=*/false},  // its frame table is written last
                 job.plan.output()},
                {{"--checkpoint", job.chunking.checkpoint, {"chunk_*.pleatchunk"}}}, inputs);
}

/// Frame `f` (`frame`, the cloth's positions) in its scene through `engine`: the engine's counters in `work`
/// (progress within the frame), and running out of memory said with what the frame needs.
const FrameVisibility& visibility_of(Engine& engine, const Scene& scene, const Frame& frame, std::size_t f,
                                     const VisibilityOptions& options, FrameWork& work) {
  const Frame sliced = scene.num_occluders() ? scene.with_occluders(f, frame) : frame;
  work.counters.reset();
  work.frame.store(std::int64_t(f));
  try {
    const FrameVisibility& vis =
        compute_frame([&]() -> const FrameVisibility& { return engine.compute(sliced); }, options.job.in, f);
    work.frame.store(-1);
    return vis;
  } catch (const std::bad_alloc&) {
    work.frame.store(-1);
    throw out_of_memory_in_frame(scene.topology(), sliced, engine.plan(), f, options.job.threads());
  }
}

/// What decides the outputs' bytes: the checkpoint's job key.
std::uint64_t job_key(const VisibilityOptions& options, const SlicingPlan& plan, ConeEncoding encoding) {
  Fingerprint key;
  key.add("visibility")
      .add(options.job.scene.describe())
      .add(options.job.engine)
      .add(options.job.plan.describe())
      .add_value(plan_fingerprint(plan))
      .add(options.cones.empty() ? "no cones" : cone_encoding_name(encoding));  // a chunk holds its cones
  return key.value();
}

/// A frame's --timings entry: its seconds, rank and time of finishing, and the rank's start-up times for a
/// chunk's first frame (`startup`), else the kinetic engine's counters (of `engine`, if kinetic).
nlohmann::json timing_json(std::size_t f, double seconds, const nlohmann::json* startup,
                           const Engine* engine) {
  nlohmann::json timing = {
      {"frame", f}, {"seconds", seconds}, {"rank", World::rank()}, {"finished_at", World::seconds()}};
  if (startup) {
    timing["chunk_start"] = true;
    timing["rank_startup"] = *startup;
  } else if (engine && engine->kinetic_stats()) {
    timing["kinetic"] = kinetic_json(*engine->kinetic_stats());
  }
  return timing;
}

/// The number of planes that cut frame `first` (reported).
std::size_t planes_in_frame(const MeshSequence& sequence, const SlicingPlan& plan, std::size_t first) {
  std::vector<SlicingPlane> planes;
  planes_for_frame(plan, cloth_vertices(sequence.topology()), sequence.frame(first), planes);
  return planes.size();
}

/// One run of `pleat visibility` over a prepared job: compute() on every rank, consume() and finish() on rank
/// 0 (the outputs, streamed in frame order and renamed into place at the end).
class VisibilityRun {
 public:
  VisibilityRun(const VisibilityOptions& options, const PreparedJob& job, ConeEncoding encoding,
                std::size_t first_planes)
      : m_options(options), m_job(job), m_encoding(encoding), m_first_planes(first_planes) {
    const MeshTopology& topology = job.sequence().topology();
    m_stats = {{"input", options.job.in.input},       {"engine", options.job.engine},
               {"plan", options.job.plan.describe()}, {"planes", first_planes},
               {"vertices", topology.num_vertices},   {"faces", topology.triangles.size()},
               {"frames", nlohmann::json::array()}};
    m_timings = {{"ranks", World::size()},
                 {"chunks", job.chunks.bounds.size() - 1},
                 {"chunks_from_checkpoint", job.chunks.kept_chunks},
                 {"frames", nlohmann::json::array()}};
    m_startup = {
        {"loaded_at", job.loaded_at}, {"planned_at", job.planned_at}, {"chunked_at", job.chunked_at}};
    m_work.vertices = topology.num_vertices;
    together([&] {
      if (World::root()) m_outputs.open(options, job.sequence(), job.first, job.last, encoding);
    });
  }

  const FrameWork& work() const { return m_work; }

  /// One chunk: a fresh engine (the kinetic one starts with a static build), every frame's result as bytes.
  void compute(std::size_t chunk_first, std::size_t chunk_last, const EmitFrame& emit) {
    const MeshSequence& sequence = m_job.sequence();
    const Scene& scene = *m_job.scene;
    const Index n = sequence.topology().num_vertices;
    Engine engine(scene.topology(), m_job.plan,
                  {engine_kind_from_name(m_options.job.engine),
                   !m_options.job.serial,
                   m_options.job.policy,
                   {},
                   &m_work.counters});
    std::vector<double> front(n), back(n);
    for (std::size_t f = chunk_first; f < chunk_last; ++f) {
      const Frame frame = sequence.frame(f);  // the cloth's (the cone cache's fingerprint is of it)
      const auto start = std::chrono::steady_clock::now();
      const FrameVisibility& vis = visibility_of(engine, scene, frame, f, m_options, m_work);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      for (Index v = 0; v < n; ++v) {
        front[v] = vis.measure(Side::Front, v).sky_visibility;
        back[v] = vis.measure(Side::Back, v).sky_visibility;
      }
      const nlohmann::json timing = f == chunk_first ? timing_json(f, seconds, &m_startup, nullptr)
                                                     : timing_json(f, seconds, nullptr, &engine);
      ByteWriter bytes;
      bytes.put_array(front).put_array(back);
      bytes.put<std::uint64_t>(vis.stats.crossing_slices);
      bytes.put_string(stats_json(f, vis.stats, sequence).dump()).put_string(timing.dump());
      // The frame's block of the cone cache, written by rank 0 in frame order like the CSV.
      if (!m_options.cones.empty()) bytes.put_string(encode_cone_frame(frame, vis, m_encoding));
      emit(f, bytes.take());
    }
  }

  /// Rank 0: frame f's bytes into the outputs.
  void consume(std::size_t f, std::string_view payload) {
    const auto start = std::chrono::steady_clock::now();
    m_gathered_bytes += payload.size();
    ByteReader bytes(payload);
    const auto front = bytes.get_array<double>();
    const auto back = bytes.get_array<double>();
    m_crossing_frames += bytes.get<std::uint64_t>() > 0;
    m_outputs.csv->add_frame(f, m_job.sequence().source_frame(f), front, back);
    const nlohmann::json& frame_stats =
        m_stats["frames"].emplace_back(nlohmann::json::parse(bytes.get_string()));
    m_contact.add(f, frame_stats["penetrating_vertices"], frame_stats["deepest_penetration"],
                  frame_stats["deepest_vertex"]);
    m_timings["frames"].push_back(nlohmann::json::parse(bytes.get_string()));
    m_timings["frames"].back()["payload_bytes"] = payload.size();
    if (m_outputs.cones) m_outputs.cones->add_encoded_frame(bytes.get_string());
    m_write_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  /// Rank 0: the outputs committed, the report and the warnings.
  void finish() {
    m_timings["rank0_write_seconds"] = m_write_seconds;
    m_timings["gathered_bytes"] = m_gathered_bytes;
    m_outputs.commit(m_options, m_stats, m_timings);
    report() << "wrote " << m_options.output << ": " << (m_job.last - m_job.first) << " frames x "
             << m_job.sequence().num_input_vertices() << " vertices (" << m_first_planes
             << (m_job.plan.spacing > 0 ? " planes in the first frame: " : " planes: ")
             << m_options.job.plan.describe() << ")\n"
             << chunks_line(m_job.chunks);
    if (m_outputs.cones) report() << "wrote " << m_options.cones << ": the 3D cones of every frame\n";
    m_contact.warn(m_job.scene->topology().contact_tolerance, std::cerr);
    if (m_crossing_frames > 0)
      std::cerr << "pleat: warning: chains cross in " << m_crossing_frames
                << " frames (the cloth self-intersects there); crossing points were inserted and counted in "
                   "--stats\n";
  }

 private:
  const VisibilityOptions& m_options;
  const PreparedJob& m_job;
  ConeEncoding m_encoding;
  std::size_t m_first_planes;
  VisibilityOutputs m_outputs;
  nlohmann::json m_stats, m_timings, m_startup;
  FrameWork m_work;  // progress within long frames
  std::size_t m_crossing_frames = 0;
  ContactWarning m_contact;
  double m_write_seconds = 0.0;  // rank 0's time to write the gathered frames (a serial part of the job)
  std::size_t m_gathered_bytes = 0;
};

void run(const VisibilityOptions& options) {
  const ConeEncoding encoding =
      options.cones_encoding == "compact" ? ConeEncoding::Compact : ConeEncoding::Exact;
  std::size_t first_planes = 0;  // the planes of the first requested frame (reported; rank 0's)
  JobSteps steps;
  steps.check_outputs = [&] { check_visibility_outputs(options); };
  steps.on_plan = [&](const MeshSequence& sequence, const SlicingPlan& plan, std::size_t first) {
    first_planes = planes_in_frame(sequence, plan, first);
  };
  steps.key = [&](const SlicingPlan& plan) { return job_key(options, plan, encoding); };
  const std::unique_ptr<PreparedJob> job = prepare(options.job, steps);
  VisibilityRun run(options, *job, encoding, first_planes);
  run_frames(
      *job, "visibility",
      [&](std::size_t a, std::size_t b, const EmitFrame& emit) { run.compute(a, b, emit); },
      [&](std::size_t f, std::string_view payload) { run.consume(f, payload); }, &run.work());
  if (World::root()) run.finish();
}

}  // namespace

void register_visibility_command(CLI::App& app) {
  auto options = std::make_shared<VisibilityOptions>();
  CLI::App* cmd =
      app.add_subcommand("visibility", "per-vertex sky visibility A (front, back) of every frame, as CSV");
  options->job.add_to(*cmd, /*engine_options=*/true);
  cmd->add_option("-o,--output", options->output,
                  "the visibility CSV (frame,vertex,front,back,source_frame); - for standard output")
      ->required();
  cmd->add_option(
      "--stats", options->stats,
      "also write per-frame statistics as JSON (what the frame and plan determine: slices, regions, "
      "windows, crossings; the same at any number of ranks)");
  cmd->add_option("--timings", options->timings,
                  "also write how the run went as JSON: seconds per frame, the rank that computed it, the "
                  "kinetic engine's counters");
  options->job.chunking.add_to(*cmd);
  cmd->add_option("--cones", options->cones,
                  "also write every frame's 3D cones to a cone cache (.cones), for `pleat shade --cones`");
  cmd->add_option(
         "--cones-encoding", options->cones_encoding,
         "exact (the engines' doubles: shading from the cache equals shading from fresh cones) or "
         "compact (the cones' directions in 16-bit octahedral coordinates, within 5e-5 radians: about "
         "1/3.5 of the size)")
      ->check(CLI::IsMember({"exact", "compact"}))
      ->capture_default_str();
  cmd->footer(
      "Example:\n  pleat visibility data/drape/drape.obj --cache data/drape/drape.pc2 -o drape.csv --stats "
      "stats.json");
  cmd->callback([options] { run(*options); });
}

}  // namespace pleat::cli
