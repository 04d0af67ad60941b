// pleat visibility: per-vertex sky visibility A of both sides, every frame, as the visibility CSV.
#include <chrono>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>

#include "cli/cli_options.hpp"
#include "cli/commands.hpp"
#include "cli/progress.hpp"
#include "kinetic/kinetic_visibility.hpp"
#include "shading/cone_cache.hpp"
#include "sim_io/atomic_file.hpp"
#include "sim_io/mesh_sequence.hpp"
#include "sim_io/visibility_csv.hpp"
#include "static_core/visibility.hpp"

namespace pleat::cli {
namespace {

struct VisibilityOptions {
  InputOptions in;
  std::string output;
  std::string engine = "kinetic";
  std::string cones;  // optional cone cache (.cones)
  std::string frames;
  std::string stats;
  PlanOptions plan;
  bool serial = false;
  kinetic::KineticPolicy policy;
};

nlohmann::json stats_json(std::size_t frame, double seconds, const VisibilityStats& s) {
  return {{"frame", frame},
          {"seconds", seconds},
          {"slices", s.slices},
          {"slice_vertices", s.slice_vertices},
          {"regions", s.regions},
          {"windows", s.windows},
          {"regions_with_holes", s.regions_with_holes},
          {"crossing_slices", s.crossing_slices},
          {"chain_crossings", s.chain_crossings},
          {"filled_fraction", s.filled_fraction}};
}

nlohmann::json kinetic_json(const KineticFrameStats& k) {
  nlohmann::json rebuilt;
  for (int r = 1; r < static_cast<int>(kinetic::RebuildReason::count); ++r)
    rebuilt[kinetic::rebuild_reason_name(static_cast<kinetic::RebuildReason>(r))] = k.rebuilt_because[r];
  nlohmann::json out;
  for (const KineticCounter& c : kKineticCounters) out[c.name] = k.*c.field;
  out["rebuilt_because"] = rebuilt;
  return out;
}

/// One engine behind one call per frame: the static engine recomputes, the kinetic one advances.
class Engine {
 public:
  Engine(const std::string& kind, const MeshTopology& topology, const SlicingPlan& plan, bool parallel,
         const kinetic::KineticPolicy& policy)
      : m_policy(policy) {
    if (kind == "static")
      m_static.emplace(topology, plan, VisibilityParams{parallel});
    else
      m_plan = plan, m_topology = &topology, m_parallel = parallel;
  }
  const FrameVisibility& next(const Frame& frame) {
    if (m_static) return m_static->compute(frame);
    if (!m_kinetic) {
      KineticParams params;  // invariant checks: on in Debug builds only
      params.parallel = m_parallel;
      params.policy = m_policy;
      m_kinetic.emplace(*m_topology, m_plan, frame, params);
      return m_kinetic->current();
    }
    return m_kinetic->advance(frame);
  }
  const KineticFrameStats* kinetic_stats() const { return m_kinetic ? &m_kinetic->last_stats() : nullptr; }

 private:
  std::optional<StaticVisibility> m_static;
  std::optional<KineticVisibility> m_kinetic;
  SlicingPlan m_plan;
  const MeshTopology* m_topology = nullptr;
  bool m_parallel = true;
  kinetic::KineticPolicy m_policy;
};

void run(const VisibilityOptions& options) {
  const MeshSequence sequence = load_sequence(options.in.input, options.in.cache);
  std::size_t first = 0, last = 0;
  parse_frame_range(options.frames, sequence.num_frames(), first, last);
  const MeshTopology& topology = sequence.topology();
  const Frame first_frame = sequence.frame(first);
  const SlicingPlan plan = options.plan.make(topology, first_frame);

  create_parent_directory(options.output);
  if (!options.stats.empty()) create_parent_directory(options.stats);
  VisibilityCsvWriter csv(options.output, sequence.welded_of_input());
  std::optional<ConeCacheWriter> cones;
  if (!options.cones.empty()) {
    create_parent_directory(options.cones);
    std::vector<std::uint32_t> frame_ids;
    for (std::size_t f = first; f < last; ++f) frame_ids.push_back(std::uint32_t(f));
    cones.emplace(options.cones, topology, sequence.welded_of_input(), sequence.frame_rate(),
                  options.plan.describe(), std::move(frame_ids));
  }
  nlohmann::json stats = {{"input", options.in.input},         {"engine", options.engine},
                          {"plan", options.plan.describe()},   {"planes", plan.planes.size()},
                          {"vertices", topology.num_vertices}, {"faces", topology.triangles.size()},
                          {"frames", nlohmann::json::array()}};
  VisibilityParams params;
  params.parallel = !options.serial;
  Progress progress("visibility", last - first);
  std::size_t crossing_frames = 0;
  Engine engine(options.engine, topology, plan, params.parallel, options.policy);
  for (std::size_t f = first; f < last; ++f) {
    const Frame frame = f == first ? first_frame : sequence.frame(f);
    const auto start = std::chrono::steady_clock::now();
    const FrameVisibility& vis = engine.next(frame);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::vector<double> front(topology.num_vertices), back(topology.num_vertices);
    for (Index v = 0; v < topology.num_vertices; ++v) {
      front[v] = vis.measure(Side::Front, v).sky_visibility;
      back[v] = vis.measure(Side::Back, v).sky_visibility;
    }
    csv.add_frame(f, front, back);
    if (cones) cones->add_frame(frame, vis);
    nlohmann::json frame_stats = stats_json(f, seconds, vis.stats);
    if (f != first && engine.kinetic_stats()) frame_stats["kinetic"] = kinetic_json(*engine.kinetic_stats());
    stats["frames"].push_back(frame_stats);
    crossing_frames += vis.stats.crossing_slices > 0;
    progress.advance();
  }
  progress.finish();
  if (!options.stats.empty()) write_file_atomically(options.stats, stats.dump(2) + "\n");
  if (cones) cones->commit();
  csv.commit();
  std::cout << "wrote " << options.output << ": " << (last - first) << " frames x "
            << sequence.num_input_vertices() << " vertices (" << plan.planes.size()
            << " planes: " << options.plan.describe() << ")\n";
  if (cones) std::cout << "wrote " << options.cones << ": the 3D cones of every frame\n";
  if (crossing_frames > 0)
    std::cout << "warning: chains cross in " << crossing_frames
              << " frames (the surface self-intersects there); crossing points were inserted and counted in "
                 "--stats\n";
}

}  // namespace

void register_visibility_command(CLI::App& app) {
  auto options = std::make_shared<VisibilityOptions>();
  CLI::App* cmd =
      app.add_subcommand("visibility", "per-vertex sky visibility A (front, back) of every frame, as CSV");
  options->in.add_to(*cmd);
  cmd->add_option("-o,--output", options->output, "the visibility CSV (frame,vertex,front,back)")->required();
  cmd->add_option("--engine", options->engine,
                  "kinetic (default: slices kept alive and repaired between frames) or static (full "
                  "recompute per frame); both give the same output")
      ->check(CLI::IsMember({"static", "kinetic"}));
  add_frames_option(*cmd, options->frames);
  cmd->add_option("--stats", options->stats, "also write per-frame statistics as JSON");
  cmd->add_option("--cones", options->cones,
                  "also write every frame's 3D cones to a cone cache (.cones), for `pleat shade --cones`");
  cmd->add_option(
         "--max-edit-fraction", options->policy.max_edit_fraction,
         "kinetic: rebuild a slice when the slice vertices removed, inserted and put back in a frame exceed "
         "this fraction of it (+2)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_flag("--serial", options->serial, "one thread (default: TBB over slices)");
  options->plan.add_to(*cmd);
  cmd->footer(
      "Example:\n  pleat visibility data/drape/drape.obj --cache data/drape/drape.pc2 -o drape.csv --stats "
      "stats.json");
  cmd->callback([options] { run(*options); });
}

}  // namespace pleat::cli
