#include "cli/cli_options.hpp"

#include <algorithm>
#include <stdexcept>

#include "cli/global_options.hpp"
#include "shading/lights.hpp"
#include "sim_io/plan_file.hpp"
#include "static_core/cone_rules.hpp"
#include "support/atomic_file.hpp"

namespace pleat::cli {

void parse_frame_range(const std::string& text, std::size_t count, std::size_t& first, std::size_t& last,
                       const std::string& option) {
  first = 0;
  last = count;
  if (text.empty()) return;
  const auto total = static_cast<long long>(count);
  const auto number = [&](const std::string& s) {
    std::size_t used = 0;
    long long v = 0;
    try {
      v = std::stoll(s, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (s.empty() || used != s.size())
      throw std::invalid_argument(option + ": '" + text + "' is not A:B or N");
    return v;
  };
  const std::size_t colon = text.find(':');
  if (colon == std::string::npos) {  // an index, as Python's list[N]: it must exist
    const long long n = number(text);
    if (n >= total || n < -total)
      throw std::invalid_argument(option + ": frame " + text + " is out of range: the input has " +
                                  std::to_string(count) + (count == 1 ? " frame (0" : " frames (0 to ") +
                                  (count == 1 ? "" : std::to_string(count - 1)) + ", or -1 to -" +
                                  std::to_string(count) + " from the end)");
    first = static_cast<std::size_t>(n < 0 ? n + total : n);
    last = first + 1;
    return;
  }
  // A slice, as Python's list[A:B]: negative ends count from the end, ends beyond the frames are clamped.
  const auto end = [&](const std::string& s, long long fallback) {
    long long v = s.empty() ? fallback : number(s);
    if (v < 0) v += total;
    return static_cast<std::size_t>(std::clamp(v, 0LL, total));
  };
  first = end(text.substr(0, colon), 0);
  last = end(text.substr(colon + 1), total);
  if (first >= last)
    throw std::invalid_argument(option + ": '" + text + "' selects no frame of " + std::to_string(count));
}

std::vector<InputFile> InputOptions::files() const {
  std::vector<InputFile> files;
  for (const std::filesystem::path& file : files_read_for(input)) files.push_back({"INPUT", file.string()});
  if (!cache.empty()) files.push_back({"--cache", cache});
  return files;
}

void InputOptions::add_to(CLI::App& command) {
  command
      .add_option("INPUT", input,
                  "the cloth: .obj (with --cache), a numbered OBJ sequence (printf pattern like "
                  "frames/f_%04d.obj, or a directory), .gltf or .glb")
      ->required();
  command.add_option("--cache", cache, "point cache for an .obj input: .pc2 or .mdd");
}

void add_frames_option(CLI::App& command, std::string& frames) {
  command.add_option(
      "--frames", frames,
      "frames A:B (first A, up to but excluding B; either may be omitted; negative counts from "
      "the end) or N, as 0-based indices in the sequence (not source frame numbers)");
}

void ChunkOptions::add_to(CLI::App& command) {
  command.add_option(
      "--checkpoint", checkpoint,
      "keep every finished chunk in DIR; a rerun of the same command computes only the missing "
      "chunks (a changed input, plan or option invalidates them)");
  command.add_option(
      "--chunks", chunks,
      "split the frames into this many contiguous chunks of nearly equal cost (default: one per "
      "rank under mpirun; one without)");
}

void add_light_option(CLI::App& command, std::vector<std::string>& specs, const std::string& default_text) {
  command
      .add_option(
          "--light", specs,
          "a light (repeatable): " + light_spec_syntax() + "; any but env take rgb=R,G,B. " + default_text)
      ->allow_extra_args(
          false);  // one spec per --light: `--light sky:1 cloth.obj` keeps cloth.obj positional
}

void SceneOptions::add_to(CLI::App& command, std::function<void()> check) {
  command
      .add_option(
          "--occluder", occluders,
          "a mesh of the scene that blocks the sky but receives no cones (repeatable): PATH (.obj, an OBJ "
          "sequence, .gltf/.glb; one frame: static) or PATH,cache=CACHE (.obj with .pc2/.mdd); an animated "
          "one needs the cloth's frame count and rate")
      ->allow_extra_args(false);
  command.add_option(
      "--ground", ground,
      "an infinite ground plane AXIS=VALUE, e.g. y=0 (the bundled data is Y-up) or z=0 (Blender): a floor, "
      "solid below the plane (-AXIS=VALUE: solid above it); cloth below a floor counts as resting on it");
  command.add_option_function<double>(
      "--contact-tolerance",
      [this, check](double value) {
        contact_tolerance = value;
        if (check) check();
      },
      "how far behind an open occluder's surface (a plane mesh) cloth still counts as resting on it, in "
      "scene "
      "units; cloth inside a closed occluder or below --ground always does, and vertices deeper than this "
      "are "
      "reported (default: 1/2 of the cloth's mean edge length in the first frame)");
}

Scene SceneOptions::make(const MeshSequence& cloth) const {
  std::vector<OccluderSpec> specs;
  for (const std::string& o : occluders) specs.push_back(parse_occluder_spec(o));
  std::vector<GroundPlane> grounds;
  if (!ground.empty()) grounds.push_back(parse_ground_plane(ground));
  return Scene(cloth, specs, grounds, contact_tolerance);
}

std::vector<InputFile> SceneOptions::files() const {
  std::vector<InputFile> files;
  for (const std::string& text : occluders) {
    try {
      const OccluderSpec spec = parse_occluder_spec(text);
      for (const std::filesystem::path& file : files_read_for(spec.path))
        files.push_back({"--occluder", file.string()});
      if (!spec.cache.empty()) files.push_back({"--occluder", spec.cache});
    } catch (const std::exception&) {
    }
  }
  return files;
}

std::string SceneOptions::describe() const {
  std::string text;
  for (const std::string& o : occluders) text += "occluder " + o + "; ";
  if (!ground.empty()) text += "ground " + ground;
  if (contact_tolerance) text += "; contact " + std::to_string(*contact_tolerance);
  return text;
}

namespace {

/// "a (what a does), b (what b does) or c (...)".
template <class Rule>
std::string rules_help(std::span<const Rule* const> table) {
  std::string text;
  for (std::size_t i = 0; i < table.size(); ++i)
    text += (i == 0                  ? ""
             : i + 1 == table.size() ? " or "
                                     : ", ") +
            std::string(table[i]->name) + " (" + std::string(table[i]->summary) + ")";
  return text;
}

}  // namespace

void PlanOptions::add_to(CLI::App& command) {
  std::vector<CLI::Option*> placement;  // what --plan replaces
  placement.push_back(command.add_option(
      "--orientations", orientations,
      "plane orientations (6: the paper's axis-aligned ones; other counts are spread over the sphere)"));
  placement.back()->check(CLI::Range(1, 1000));
  // Each value is checked as it is parsed, by the library's check (PlanOptions::check: the Python module's).
  const auto checked = [this](auto& field) {
    return [this, &field](const auto& value) {
      field = value;
      check(Naming::CommandLine);
    };
  };
  CLI::Option* absolute = command.add_option_function<double>(
      "--spacing", checked(spacing),
      "distance between parallel planes, > 0 (default: 1/2 of the average edge length; with --paper one)");
  placement.push_back(absolute);
  placement.push_back(
      command
          .add_option_function<double>(
              "--spacing-edges", checked(spacing_edges),
              "distance between parallel planes in average edge lengths of the first frame, > 0 (default "
              "0.5: "
              "every measured sequence within mean error 0.02 of ray-traced truth; 0.75 costs about 0.7x as "
              "much per frame)")
          ->excludes(absolute));
  placement.push_back(command.add_option_function<int>(
      "--planes", checked(planes_per_orientation),
      "planes per orientation, >= 1, spread over the extent of every frame (overrides --spacing and "
      "--spacing-edges)"));
  placement.push_back(command.add_flag(
      "--adaptive", adaptive,
      "place planes by the paper's recursive median split (§2.3.3) on the first frame instead of evenly"));
  placement.push_back(
      command
          .add_option("--max-missing", max_missing,
                      "with --adaptive: stop when at most this fraction of vertices lacks a cone")
          ->check(CLI::Range(0.0, 1.0)));
  placement.push_back(command
                          .add_option_function<std::string>(
                              "--cone-storage", checked(storage),
                              "how 2D cones reach mesh vertices: " + rules_help(cone_storage_rules()))
                          ->default_str(storage));
  placement.push_back(command
                          .add_option_function<std::string>("--cone-reconstruction", checked(reconstruction),
                                                            "how a vertex's 2D cones become its 3D cone: " +
                                                                rules_help(cone_reconstruction_rules()))
                          ->default_str(reconstruction));
  placement.push_back(command.add_flag(
      "--paper", paper,
      "the paper's method: its 6 axis-aligned orientations and nearer-endpoint storage (overrides "
      "--orientations and --cone-storage)"));
  CLI::Option* pinned = command.add_option(
      "--plan", plan_file,
      "cut with the plan in FILE (written by --save-plan) instead of making one: the same planes for every "
      "farm task, machine and edit of the cache");
  for (CLI::Option* o : placement) pinned->excludes(o);
  command.add_option(
      "--save-plan", save_plan,
      "also write the slicing plan to FILE (JSON: orientations, spacing or planes, the rules)");
}

std::vector<InputFile> PlanOptions::files() const {
  if (plan_file.empty()) return {};
  return {{"--plan", plan_file}};
}

SlicingPlan PlanOptions::make(const MeshSequence& sequence) const {
  SlicingPlan plan = pleat::PlanOptions::make(sequence, Naming::CommandLine);
  if (!save_plan.empty()) {
    create_parent_directory(save_plan);
    write_plan_file(save_plan, plan);
  }
  return plan;
}

}  // namespace pleat::cli
