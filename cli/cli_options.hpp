// Options shared by the subcommands, each declared once: the input cloth (INPUT and --cache), the frame range
// (--frames), lights (--light), the slicing plan and the chunking of a distributed job (--checkpoint,
// --chunks).
#pragma once

#include <CLI/CLI.hpp>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sim_io/mesh_sequence.hpp"
#include "sim_io/scene.hpp"
#include "sim_io/sequence_plan.hpp"
#include "static_core/input_error.hpp"
#include "static_core/mesh.hpp"
#include "static_core/slicing_plan.hpp"

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

/// Creates the directory an output file goes into (that of the file its symbolic links lead to), if missing;
/// nothing for "-" (standard output).
void create_parent_directory(const std::filesystem::path& output);

/// One output file of a subcommand: the option naming it, its path (empty: not asked for), and whether "-"
/// (standard output) may stand for it.
struct OutputFile {
  std::string option;
  std::string path;
  bool stdout_allowed = true;
};

/// Refuses, before any work, with a usage error (exit status 2): an output file whose path is not a regular
/// file after following links (sim_io/atomic_file.hpp's resolve_output_target), "-" where it is not allowed
/// or for two outputs, one file named by two outputs, and an output directory that exists and is not a
/// directory. When an output is "-", moves the lines saying what was written to stderr (report_to_stderr()).
void check_outputs(const std::vector<OutputFile>& files,
                   const std::vector<std::pair<std::string, std::string>>& directories = {});

/// The scene the cloth was simulated in (sim_io/scene.hpp): --occluder PATH[,cache=CACHE] (repeatable) and
/// --ground AXIS=VALUE. The same on every subcommand that computes cones.
struct SceneOptions {
  std::vector<std::string> occluders;
  std::string ground;
  std::optional<double> contact_tolerance;  ///< --contact-tolerance (default: Scene's)
  void add_to(CLI::App& command);
  /// Reads the occluders (InputError naming the file on bad input).
  Scene make(const MeshSequence& cloth) const;
  /// What the options say, for the checkpoint's job key: "" with no occluder.
  std::string describe() const;
};

/// The plan options (sim_io/sequence_plan.hpp) as command-line options, and --save-plan FILE.
struct PlanOptions : pleat::PlanOptions {
  std::string save_plan;  ///< --save-plan: also write the plan made to this file

  void add_to(CLI::App& command);
  /// The plan for `sequence`; writes --save-plan.
  SlicingPlan make(const MeshSequence& sequence) const;
};

}  // namespace pleat::cli
