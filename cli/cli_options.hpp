// Options shared by the subcommands, each declared once: the input cloth (INPUT and --cache), the frame range
// (--frames), lights (--light), the slicing plan and the chunking of a distributed job (--checkpoint,
// --chunks).
#pragma once

#include <CLI/CLI.hpp>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cli/output_paths.hpp"
#include "sim_io/mesh_sequence.hpp"
#include "sim_io/scene.hpp"
#include "sim_io/sequence_plan.hpp"
#include "static_core/mesh.hpp"
#include "static_core/slicing_plan.hpp"
#include "support/input_error.hpp"

namespace pleat::cli {

/// Parses "A:B" (a slice, Python style: half-open, either end may be left out, negatives count from the end,
/// ends beyond the frames are clamped; it must select a frame) or "N" (an index, Python style: that frame
/// only, negative from the end; it must exist) against `count` frames into [first, last). Throws
/// std::invalid_argument naming `option` (the option the text came from).
void parse_frame_range(const std::string& text, std::size_t count, std::size_t& first, std::size_t& last,
                       const std::string& option = "--frames");

/// The cloth a subcommand reads: INPUT (an .obj with --cache, a numbered OBJ sequence, .gltf or .glb).
struct InputOptions {
  std::string input;
  std::string cache;
  /// Adds the required positional INPUT and --cache.
  void add_to(CLI::App& command);
  /// The files they read (files_read_for), for check_outputs.
  std::vector<InputFile> files() const;
};

/// `compute()`, an engine's frame f of `in`, with a frame the engine refuses (an InputError: too wide, too
/// far out) named by the input's file and the frame's index.
template <class Compute>
decltype(auto) compute_frame(Compute&& compute, const InputOptions& in, std::size_t f) {
  try {
    return compute();
  } catch (const InputError& e) {
    throw InputError(in.cache.empty() ? in.input : in.cache, "frame " + std::to_string(f), e.reason());
  }
}

/// --frames A:B | N (parse_frame_range).
void add_frames_option(CLI::App& command, std::string& frames);

/// --light, repeatable, one spec each (shading/lights.hpp's syntax); `default_text` says what applies
/// without.
void add_light_option(CLI::App& command, std::vector<std::string>& specs, const std::string& default_text);

/// How a job's frames are split under mpirun or kept between runs (cli/chunk_plan.hpp): --checkpoint DIR
/// and --chunks N, the same for every subcommand that distributes.
struct ChunkOptions {
  std::string checkpoint;
  std::size_t chunks = 0;  ///< 0: one per rank under mpirun, one without
  void add_to(CLI::App& command);
};

/// The scene the cloth was simulated in (sim_io/scene.hpp): --occluder PATH[,cache=CACHE] (repeatable) and
/// --ground AXIS=VALUE. The same on every subcommand that computes cones.
struct SceneOptions {
  std::vector<std::string> occluders;
  std::string ground;
  std::optional<double> contact_tolerance;  ///< --contact-tolerance (default: Scene's)
  /// Declares the options; `check`, when given, runs as --contact-tolerance is parsed.
  void add_to(CLI::App& command, std::function<void()> check = {});
  /// Reads the occluders (InputError naming the file on bad input).
  Scene make(const MeshSequence& cloth) const;
  /// What the options say, for the checkpoint's job key: "" with no occluder.
  std::string describe() const;
  /// The files the occluders are read from, for check_outputs (a malformed spec: none; make() says why).
  std::vector<InputFile> files() const;
};

/// The plan options (sim_io/sequence_plan.hpp) as command-line options, and --save-plan FILE.
struct PlanOptions : pleat::PlanOptions {
  std::string save_plan;  ///< --save-plan: also write the plan made to this file

  void add_to(CLI::App& command);
  /// The plan for `sequence`; writes --save-plan.
  SlicingPlan make(const MeshSequence& sequence) const;
  /// --plan, as an input, for check_outputs.
  std::vector<InputFile> files() const;
  /// --save-plan, as an output, for check_outputs.
  OutputFile output() const { return {"--save-plan", save_plan}; }
};

}  // namespace pleat::cli
