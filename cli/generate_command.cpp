// `pleat generate KIND -o OUT.obj`: writes an analytic animated cloth (sim_io/cloth_generators.hpp) as an
// OBJ of frame 0 plus a PC2 point cache of every frame beside it (OUT with the extension .pc2), the pair
// `pleat info/visibility/shade OUT.obj --cache OUT.pc2` reads back. OUT.obj, which the user named, is
// replaced like any output; an existing OUT.pc2, which the user did not name, only with --force. Frames are
// generated one at a time; the PC2 writer takes them all, so memory is about 24 bytes x vertices x frames.
#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>

#include "cli/cli_options.hpp"
#include "cli/commands.hpp"
#include "cli/global_options.hpp"
#include "cli/job_error.hpp"
#include "cli/progress.hpp"
#include "sim_io/cloth_generators.hpp"
#include "sim_io/mesh_sequence.hpp"
#include "sim_io/obj_format.hpp"
#include "sim_io/pc2_format.hpp"
#include "support/atomic_file.hpp"

namespace pleat::cli {

namespace {

struct GenerateOptions {
  std::string kind;
  std::string output;
  bool force = false;
  GeneratorParams params;
};

std::string kind_list() {
  std::string list;
  for (ClothKind kind : kAllClothKinds)
    list += (list.empty() ? "" : ", ") + std::string(cloth_kind_name(kind));
  return list;
}

void run_generate(const GenerateOptions& options) {
  const std::optional<ClothKind> kind = parse_cloth_kind(options.kind);
  if (!kind)
    throw std::invalid_argument("unknown cloth kind '" + options.kind + "' (choose " + kind_list() + ")");
  const std::filesystem::path obj_path = options.output;
  if (options.output == kStandardOutput)
    throw std::invalid_argument(
        "-o -: generate writes two files, OUT.obj and OUT.pc2 beside it; give OUT.obj");
  if (obj_path.extension() != ".obj")
    throw std::invalid_argument("output '" + options.output +
                                "' must end in .obj (the cache is written beside it, as .pc2)");
  std::filesystem::path pc2_path = obj_path;
  pc2_path.replace_extension(".pc2");
  check_outputs({{"-o", obj_path.string(), /*stdout_allowed=*/false},
                 {"-o's cache", pc2_path.string(), /*stdout_allowed=*/false}});
  if (!options.force && std::filesystem::exists(std::filesystem::symlink_status(pc2_path)))
    throw OutputRefused(pc2_path, "exists, and generate would replace it with the cache of " +
                                      obj_path.string() +
                                      "; pass --force to replace it, or choose another -o");

  const ClothGenerator generator(*kind, options.params);  // validates the parameters
  create_parent_directory(obj_path);
  std::vector<std::vector<glm::dvec3>> frames;
  frames.reserve(generator.num_frames());
  Progress progress("generate", generator.num_frames());
  for (std::size_t i = 0; i < generator.num_frames(); ++i) {
    frames.push_back(generator.frame(i).positions);
    progress.advance();
  }
  progress.finish();

  // PC2 stores scene frame numbers: with the readers' default scene rate, sample i must sit on scene frame
  // i * (scene_fps / fps) so that it plays at `fps`.
  write_pc2(pc2_path, frames, 0.0, kDefaultSceneFps / options.params.fps);
  write_obj(obj_path, generator.topology(), frames.front());

  const MeshTopology& topology = generator.topology();
  report() << "wrote " << obj_path.string() << " (" << cloth_kind_name(*kind) << ", " << topology.num_vertices
           << " vertices, " << topology.triangles.size() << " triangles, frame 0)\n"
           << "wrote " << pc2_path.string() << " (" << frames.size() << " frames at " << options.params.fps
           << " fps, seed " << options.params.seed << ")\n";
}

}  // namespace

void register_generate_command(CLI::App& app) {
  auto options = std::make_shared<GenerateOptions>();
  auto* cmd = app.add_subcommand(
      "generate",
      "Write an analytic animated cloth that is deeply folded and provably free of self-intersections: "
      "OUT.obj (frame 0) and OUT.pc2 (all frames).");
  cmd->add_option("kind", options->kind,
                  "curtain (pleats deepen and relax), roll (a sheet rolls into a spiral and unrolls; alias "
                  "spiral), flag (a travelling wave), sleeve (a tube with accordion folds; alias tube)")
      ->required();
  cmd->add_option("-o,--output", options->output,
                  "OUT.obj: writes frame 0 there (replacing it) and every frame to OUT.pc2 beside it")
      ->required();
  cmd->add_flag("--force", options->force,
                "replace an existing OUT.pc2 (without it, generate refuses to overwrite the cache it was not "
                "named)");
  cmd->add_option("--resolution", options->params.resolution,
                  "grid of N x N vertices (55: ~3k, 173: ~30k, 548: ~300k vertices)")
      ->capture_default_str()
      ->check(CLI::Range(3, 20000));
  cmd->add_option("--frames", options->params.frames, "number of frames (one motion cycle, loops)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--fps", options->params.fps, "frames per second")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--seed", options->params.seed, "0: nominal shape; other values jitter its proportions")
      ->capture_default_str();
  cmd->footer(
      "Example:\n"
      "  pleat generate curtain -o curtain.obj --resolution 55 --frames 60\n"
      "  pleat info curtain.obj --cache curtain.pc2 --check-intersections");
  cmd->callback([options] { on_rank_zero_alone([&] { run_generate(*options); }); });
}

}  // namespace pleat::cli
