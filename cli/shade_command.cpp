// `pleat shade`: visibility cones per frame, then shading under any number of lights (or several lighting
// setups from the same cones), written as an animated flipbook .glb with sRGB vertex colours for both cloth
// sides, and optionally rendered to PNG images.
//
// Per frame: compute_visibility with a slicing plan (cli_options.hpp; the paper's diffuse plan by default)
// made once for the whole sequence (the planes stay fixed while the cloth moves), or the frame's cones
// read from a cone cache (--cones, shading/cone_cache.hpp), then shade_frame
// for each lighting setup (shading/shade.hpp), to_srgb, and the setup's glb writer (sim_io/gltf_writer.hpp)
// and renderer (shading/render.hpp). The cones are computed once per frame whatever the number of setups:
// relighting costs only the shading pass.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <glm/geometric.hpp>
#include <iostream>
#include <limits>
#include <memory>
#include <new>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

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
#include "shading/cone_cache.hpp"
#include "shading/embree_scene.hpp"
#include "shading/lights.hpp"
#include "shading/render.hpp"
#include "shading/scene_render.hpp"
#include "shading/shade.hpp"
#include "sim_io/gltf_writer.hpp"
#include "sim_io/mesh_sequence.hpp"
#include "sim_io/up_axis.hpp"
#include "static_core/plan_codec.hpp"
#include "static_core/slicing_plan.hpp"
#include "static_core/visibility.hpp"
#include "support/atomic_file.hpp"
#include "support/byte_stream.hpp"
#include "support/fingerprint.hpp"

namespace pleat::cli {

namespace {

struct ShadeOptions {
  JobOptions job;  // the input, frames, scene, plan and chunking
  std::string output;
  std::string glb_layout = "sides";
  std::vector<std::string> light_specs;
  std::string lights_file;
  std::string relight_file;
  std::string cones;  // shade from this cone cache instead of computing cones
  double albedo = 0.6;
  double exposure = 1.0;
  bool no_interreflection = false;
  std::string render_dir;
  int width = 800;
  int height = 600;
  std::string camera;
  std::string up = "auto";
  std::string render_mode = "shaded";
  int render_every = 1;
  int turntable = 0;
  bool hide_occluders = false;
};

/// OUT.glb -> OUT_NAME.glb
std::filesystem::path setup_output(const std::filesystem::path& output, const std::string& name) {
  std::filesystem::path p = output;
  p.replace_filename(output.stem().string() + "_" + name + output.extension().string());
  return p;
}

/// One side's cones as the glb's vertex attributes: A, and the bent normal with the cosine of the half-angle
/// of the circular cone of the same solid angle (omega = 2 pi (1 - cos)).
void side_visibility(const FrameVisibility& visibility, Side side, SideVisibility& out) {
  const std::vector<ConeMeasures>& measures = visibility.measures[int(side)];
  out.sky_visibility.resize(measures.size());
  out.bent_cone.resize(measures.size());
  for (std::size_t v = 0; v < measures.size(); ++v) {
    const ConeMeasures& m = measures[v];
    out.sky_visibility[v] = float(m.sky_visibility);
    const double cosine = std::clamp(1.0 - m.solid_angle / (2.0 * M_PI), -1.0, 1.0);
    out.bent_cone[v] = glm::vec4(glm::vec3(m.bent_normal), float(cosine));
  }
}

/// --render-mode sky-visibility: each side's A through viridis (0 dark blue, 1 yellow).
std::array<std::vector<glm::vec3>, 2> sky_colours(const std::array<SideVisibility, 2>& sides) {
  std::array<std::vector<glm::vec3>, 2> colours;
  for (int s = 0; s < 2; ++s)
    for (float a : sides[s].sky_visibility) colours[s].push_back(viridis(a));
  return colours;
}

std::vector<Lighting> gather_lightings(const ShadeOptions& options) {
  std::vector<Lighting> setups;
  if (!options.relight_file.empty()) {
    if (!options.light_specs.empty() || !options.lights_file.empty())
      throw std::invalid_argument(
          "--relight replaces --light/--lights: give the lights inside the setups file");
    setups = load_lighting_setups(options.relight_file);
  } else {
    Lighting lighting;
    if (!options.lights_file.empty()) lighting = load_lighting(options.lights_file);
    for (const std::string& spec : options.light_specs) add_light_spec(lighting, spec);
    if (lighting.empty()) add_light_spec(lighting, "sky:1");
    setups.push_back(std::move(lighting));
  }
  return setups;
}

/// Where --render writes setup `s`'s images: DIR, or DIR/<setup> with --relight.
std::filesystem::path render_directory(const ShadeOptions& options, const Lighting& setup, bool relight) {
  return relight ? std::filesystem::path(options.render_dir) / setup.name
                 : std::filesystem::path(options.render_dir);
}

/// Refuses, before any work, outputs that cannot be written or that are inputs (check_outputs): one glb per
/// setup with --relight.
void check_shade_outputs(const ShadeOptions& options, const std::vector<Lighting>& setups, bool relight) {
  std::vector<OutputFile> files;
  if (options.output == kStandardOutput)
    files.push_back({"-o", options.output, /*stdout_allowed=*/!relight});  // --relight: one file per setup
  else
    for (const Lighting& setup : setups)
      files.push_back({"-o", relight ? setup_output(options.output, setup.name).string() : options.output});
  files.push_back(options.job.plan.output());
  std::vector<InputFile> inputs = options.job.in.files();
  for (const auto& more : {options.job.scene.files(), options.job.plan.files()})
    inputs.insert(inputs.end(), more.begin(), more.end());
  for (const auto& [option, path] : {std::pair{"--cones", &options.cones},
                                     {"--lights", &options.lights_file},
                                     {"--relight", &options.relight_file}})
    if (!path->empty()) inputs.push_back({option, *path});
  for (const Lighting& setup : setups)
    for (const auto& [option, file] : setup.files()) inputs.push_back({option, file.string()});
  std::vector<OutputDirectory> directories = {
      {"--checkpoint", options.job.chunking.checkpoint, {"chunk_*.pleatchunk"}}};
  if (!options.render_dir.empty())
    for (const Lighting& setup : setups)
      directories.push_back({"--render",
                             render_directory(options, setup, relight).string(),
                             {"frame_*.png", "turntable_*.png"}});
  check_outputs(files, directories, inputs);
}

/// The exact float bounds of every selected frame, for the glb's header: one pass over the frames, each rank
/// over its share, so rank 0 writes the glb without reading any frame itself. Collective.
std::vector<PositionBounds> selected_frame_bounds(const MeshSequence& sequence, std::size_t first,
                                                  std::size_t last) {
  const std::size_t count = last - first;
  std::vector<float> lows(3 * count, std::numeric_limits<float>::max());
  std::vector<float> highs(3 * count, std::numeric_limits<float>::lowest());
  together([&] {
    const auto [a, b] = share_of(first, last, World::rank(), World::size());
    for (std::size_t i = a; i < b; ++i) {
      const PositionBounds bounds = position_bounds(sequence.frame(i));
      for (int k = 0; k < 3; ++k)
        lows[3 * (i - first) + k] = bounds.lo[k], highs[3 * (i - first) + k] = bounds.hi[k];
    }
  });
  all_reduce_bounds(lows, highs);
  std::vector<PositionBounds> frame_bounds(count);
  for (std::size_t j = 0; j < count; ++j)
    for (int k = 0; k < 3; ++k)
      frame_bounds[j].lo[k] = lows[3 * j + k], frame_bounds[j].hi[k] = highs[3 * j + k];
  return frame_bounds;
}

/// Where --render writes (a directory per setup with --relight) and from where: --camera, or auto-framed on
/// the whole sequence (the camera stays put while the cloth moves, and a frame's image is the same from any
/// range or split).
struct RenderTargets {
  std::vector<std::filesystem::path> directories;
  Camera camera;
};

RenderTargets render_targets(const ShadeOptions& options, const std::vector<Lighting>& setups, bool relight,
                             const MeshSequence& sequence, const glm::dvec3& up) {
  RenderTargets targets;
  for (const Lighting& setup : setups)
    targets.directories.push_back(render_directory(options, setup, relight));
  if (!options.camera.empty()) {
    targets.camera = parse_camera(options.camera);
  } else {
    AutoFrameParams framing;
    framing.up = up;
    framing.aspect = double(options.width) / options.height;
    targets.camera = auto_frame(sequence.bounds(), framing);
  }
  return targets;
}

/// What shading a chunk of frames reads (run_shade's state).
struct ShadeJob {
  const ShadeOptions& options;
  const MeshSequence& sequence;
  const Scene& world;
  const std::vector<Lighting>& setups;
  const SlicingPlan& plan;
  ConeCacheReader* cache;                  ///< the cones from a cone cache, else null: computed with `plan`
  const std::vector<std::size_t>& cached;  ///< per selected frame: its frame in the cache
  std::size_t first = 0, count = 0;        ///< the selected frames
  ShadeParams shade;
  ToneMapParams tone;
  const RenderTargets* render = nullptr;  ///< null: no images
  const UpChoice& up;                     ///< the input's up (choose_up)
  FrameWork* work = nullptr;              ///< progress within long frames
};

/// Frame `f`'s images under one setup (its sRGB colours; `sides`: A, for --render-mode sky-visibility), as
/// PNG files in memory: (name, bytes). They travel with the frame to rank 0, which stages them (StagedFiles).
std::vector<std::pair<std::string, std::string>> images_of(const ShadeJob& job, const SceneRenderer& renderer,
                                                           std::int64_t number,
                                                           const std::vector<glm::vec3>& front,
                                                           const std::vector<glm::vec3>& back,
                                                           const std::array<SideVisibility, 2>& sides) {
  const ShadeOptions& options = job.options;
  const Camera& camera = job.render->camera;
  char name[64];
  std::snprintf(name, sizeof name, "frame_%04lld.png", static_cast<long long>(number));
  if (options.render_mode == "sky-visibility") {  // A itself, with a legend
    const auto [sky_front, sky_back] = sky_colours(sides);
    return {{name, encode_png(with_legend(
                       renderer.render(sky_front, sky_back, camera, options.width, options.height), 0.0, 1.0,
                       "SKY VISIBILITY A: 0 CLOSED IN, 1 OPEN SKY"))}};
  }
  if (options.turntable > 0 && job.count == 1) {
    std::vector<std::pair<std::string, std::string>> turns;
    const std::vector<Image> images =
        renderer.turntable_images(front, back, camera, options.turntable, options.width, options.height);
    for (std::size_t i = 0; i < images.size(); ++i) {
      std::snprintf(name, sizeof name, "turntable_%03zu.png", i);
      turns.emplace_back(name, encode_png(images[i]));
    }
    return turns;
  }
  return {{name, encode_png(renderer.render(front, back, camera, options.width, options.height))}};
}

/// Frame `f`'s cones from the engine, with progress in job.work and an out-of-memory error that says what
/// the frame needs.
const FrameVisibility& computed_cones(const ShadeJob& job, StaticVisibility& engine, const Frame& world_frame,
                                      std::size_t f) {
  job.work->counters.reset();
  job.work->frame.store(std::int64_t(f));
  try {
    const FrameVisibility& visibility = compute_frame(
        [&]() -> const FrameVisibility& { return engine.compute(world_frame); }, job.options.job.in, f);
    job.work->frame.store(-1);
    return visibility;
  } catch (const std::bad_alloc&) {
    job.work->frame.store(-1);
    throw out_of_memory_in_frame(job.world.topology(), world_frame, job.plan, f, run_threads());
  }
}

/// One chunk: the cones of each frame, then every setup's shading (and images, the scene drawn as
/// SceneRenderer draws it unless --hide-occluders); the colours and the visibility attributes go to rank 0
/// as bytes (consume_shaded reads them).
void shade_chunk(const ShadeJob& job, std::size_t chunk_first, std::size_t chunk_last,
                 const EmitFrame& emit) {
  const ShadeOptions& options = job.options;
  std::optional<StaticVisibility> engine;  // reused across the chunk's frames
  if (!job.cache)
    engine.emplace(job.world.topology(), job.plan, VisibilityParams{true, {}, &job.work->counters});
  FrameVisibility from_cache;
  std::array<SideVisibility, 2> sides;
  const bool occluded = job.world.num_occluders() > 0;
  std::optional<SceneRenderer> renderer;
  if (job.render) renderer.emplace(job.world.topology(), job.up.up, !options.hide_occluders);
  for (std::size_t f = chunk_first; f < chunk_last; ++f) {
    const Frame frame = job.sequence.frame(f);
    const Frame in_scene = occluded ? job.world.with_occluders(f, frame) : Frame{};
    const Frame& world_frame = occluded ? in_scene : frame;
    const auto t0 = std::chrono::steady_clock::now();
    if (job.cache) job.cache->read_frame(job.cached[f - job.first], frame, from_cache);
    const FrameVisibility& visibility = job.cache ? from_cache : computed_cones(job, *engine, world_frame, f);
    const auto t1 = std::chrono::steady_clock::now();
    for (Side side : kBothSides) side_visibility(visibility, side, sides[int(side)]);
    // Source frame numbers, not positions in the range: the same frames are rendered however the shot is
    // split, under the names the artist's scene gives them.
    const std::int64_t number = job.sequence.source_frame(f);
    const bool render_this = job.render && number % options.render_every == 0;
    if (render_this) renderer->set_frame(world_frame);
    ByteWriter bytes;
    bytes.put(std::chrono::duration<double>(t1 - t0).count());
    bytes.put<std::uint64_t>(visibility.stats.penetrating_vertices)
        .put(visibility.stats.deepest_penetration)
        .put<std::uint32_t>(input_vertex(job.sequence, visibility.stats.deepest_vertex));
    bytes.put_array(std::vector<glm::vec3>(frame.positions.begin(), frame.positions.end()));
    for (const SideVisibility& side : sides) bytes.put_array(side.sky_visibility).put_array(side.bent_cone);
    for (std::size_t s = 0; s < job.setups.size(); ++s) {
      const auto s0 = std::chrono::steady_clock::now();
      const ShadedFrame shaded =
          shade_frame(job.sequence.topology(), frame, visibility, job.setups[s], job.shade);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - s0).count();
      const std::vector<glm::vec3> front = to_srgb(shaded.front(), job.tone);
      const std::vector<glm::vec3> back = to_srgb(shaded.back(), job.tone);
      bytes.put(seconds).put_array(front).put_array(back);
      const auto images = render_this ? images_of(job, *renderer, number, front, back, sides)
                                      : std::vector<std::pair<std::string, std::string>>{};
      bytes.put<std::uint64_t>(images.size());
      for (const auto& [name, png] : images) bytes.put_string(name).put_string(png);
    }
    emit(f, bytes.take());
  }
}

/// Rank 0: frame f's bytes from shade_chunk into every setup's glb and its images into the setup's staged
/// render directory (`renders`, empty without --render); adds up the cone and shading times and the vertices
/// sunk deeper than the contact tolerance.
void consume_shaded(std::size_t f, std::string_view payload,
                    std::vector<std::unique_ptr<ShadedGlbWriter>>& writers,
                    std::vector<std::unique_ptr<StagedFiles>>& renders, double& cone_seconds,
                    double& shade_seconds, ContactWarning& contact) {
  ByteReader bytes(payload);
  cone_seconds += bytes.get<double>();
  const auto penetrating = bytes.get<std::uint64_t>();
  const auto deepest = bytes.get<double>();
  contact.add(f, penetrating, deepest, bytes.get<std::uint32_t>());
  const auto positions = bytes.get_array<glm::vec3>();
  std::array<SideVisibility, 2> sides;
  for (SideVisibility& side : sides) {
    side.sky_visibility = bytes.get_array<float>();
    side.bent_cone = bytes.get_array<glm::vec4>();
  }
  for (std::size_t s = 0; s < writers.size(); ++s) {
    shade_seconds += bytes.get<double>();
    const auto front = bytes.get_array<glm::vec3>();
    const auto back = bytes.get_array<glm::vec3>();
    writers[s]->add_frame(positions, front, back, sides[0], sides[1]);
    const auto images = bytes.get<std::uint64_t>();
    for (std::uint64_t i = 0; i < images; ++i) {
      const std::string name(bytes.get_string());
      renders.at(s)->add(name, bytes.get_string());
    }
  }
}

/// What was shaded and written, for report().
std::string shade_summary(const ShadeJob& job, const ChunkJob& chunks,
                          const std::vector<std::filesystem::path>& outputs, double cone_seconds,
                          double shade_seconds) {
  std::ostringstream out;
  const double n = double(job.count);
  out << "shaded " << job.count << " frames of " << job.sequence.topology().num_vertices
      << " vertices: cones " << (job.cache ? "read from " + job.options.cones + " in " : std::string())
      << 1e3 * cone_seconds / n << " ms/frame, shading " << 1e3 * shade_seconds / (n * job.setups.size())
      << " ms/frame per setup\n";
  if (chunks.bounds.size() > 2 || World::distributed())
    out << "  " << chunks.bounds.size() - 1 << " chunks over " << World::size() << " ranks"
        << (chunks.kept_chunks ? ", " + std::to_string(chunks.kept_chunks) + " kept from the checkpoint" : "")
        << "\n";
  for (std::size_t s = 0; s < job.setups.size(); ++s) {
    out << "wrote " << outputs[s].string();
    if (!job.up.turn.identity())
      out << " (up " << job.up.name << ", from " << job.up.source << ", turned to glTF's +y)";
    if (job.render) out << " and images in " << job.render->directories[s].string();
    out << (job.setups[s].name.empty() ? "" : " (setup " + job.setups[s].name + ")") << '\n';
    std::istringstream lights(job.setups[s].describe());
    for (std::string line; std::getline(lights, line);) out << "  " << line << '\n';
  }
  return out.str();
}

/// What decides the outputs' bytes: the checkpoint's job key (with --render, a chunk holds its images).
std::uint64_t shade_key(const ShadeOptions& options, const SlicingPlan& plan,
                        const std::vector<Lighting>& setups, const RenderTargets* render) {
  Fingerprint key;
  key.add("shade, contact counted")
      .add_value(plan_fingerprint(plan))
      .add(options.cones)
      .add(options.job.scene.describe());
  if (!options.cones.empty()) {  // a rewritten cone cache: its size and time of last write change
    key.add_value(std::uint64_t(std::filesystem::file_size(options.cones)));
    key.add_value(std::filesystem::last_write_time(options.cones).time_since_epoch().count());
  }
  for (const Lighting& setup : setups) key.add(setup.name).add(setup.describe());
  key.add_value(options.albedo).add_value(options.exposure).add_value(options.no_interreflection);
  if (render)
    key.add("render")
        .add_value(render->camera.eye)
        .add_value(render->camera.target)
        .add_value(render->camera.up)
        .add_value(render->camera.fov_y_degrees)
        .add_value(options.width)
        .add_value(options.height)
        .add_value(options.render_every)
        .add_value(options.turntable)
        .add_value(options.hide_occluders)
        .add(options.render_mode)
        .add(options.up);
  return key.value();
}

/// Every glb written out and closed (a full disk fails here, replacing nothing), then the glbs and the staged
/// images put in place together.
void commit_together(std::vector<std::unique_ptr<ShadedGlbWriter>>& writers,
                     std::vector<std::unique_ptr<StagedFiles>>& renders) {
  for (auto& writer : writers) writer->close();
  const CommitWindow window;
  for (auto& writer : writers) writer->commit();
  for (auto& staged : renders) staged->commit();
}

/// What `pleat shade` prepares besides the job (JobSteps::before_plan, collective): the input's up, the cone
/// cache when the cones are read, and where and from where --render draws.
struct ShadePreparation {
  UpChoice up;
  std::optional<ConeCacheReader> cache;
  std::vector<std::size_t> cached;  ///< per selected frame: its frame in the cache
  std::optional<RenderTargets> render;

  /// Returns whether cones are computed (no cone cache).
  bool prepare(const ShadeOptions& options, const std::vector<Lighting>& setups, const MeshSequence& sequence,
               std::size_t first, std::size_t last) {
    // The input's up: the camera's, and the turn that stands the glb up in glTF's Y-up space.
    together([&] { up = choose_up(options.up, options.job.scene.ground, sequence); });
    if (!up.warning.empty() && World::root()) std::cerr << "pleat: warning: " << up.warning << '\n';
    // The cones from a cone cache (checked against the mesh and every selected frame before anything is
    // written; each rank opens it and reads its own frames), or computed with the job's plan.
    together([&] {
      if (options.cones.empty()) return;
      cache.emplace(options.cones);
      cache->check_mesh(sequence.topology(), sequence.welded_of_input());
      for (std::size_t i = first; i < last; ++i) cached.push_back(cache->index_of_frame(i));
    });
    if (!options.render_dir.empty())
      together([&] {
        render.emplace(render_targets(options, setups, !options.relight_file.empty(), sequence, up.up));
      });
    return !cache;
  }
};

/// Rank 0's outputs: one glb per setup (streamed frame by frame) and the staged images of each.
struct ShadeOutputs {
  std::vector<std::filesystem::path> paths;
  std::vector<std::unique_ptr<ShadedGlbWriter>> writers;
  std::vector<std::unique_ptr<StagedFiles>> renders;  // staged until every output is complete

  /// Collective: the frames' bounds measured by every rank, the writers opened on rank 0.
  void open(const ShadeOptions& options, const std::vector<Lighting>& setups, const PreparedJob& job,
            const ShadePreparation& prepared) {
    const MeshSequence& sequence = job.sequence();
    const std::vector<PositionBounds> frame_bounds = selected_frame_bounds(sequence, job.first, job.last);
    std::vector<std::size_t> frame_ids;
    for (std::size_t i = job.first; i < job.last; ++i) frame_ids.push_back(i);
    const std::filesystem::path output(options.output);
    const bool relight = !options.relight_file.empty();
    const double fps = sequence.frame_rate() > 0.0 ? sequence.frame_rate() : kDefaultSceneFps;
    for (const Lighting& setup : setups) paths.push_back(relight ? setup_output(output, setup.name) : output);
    together([&] {
      if (!World::root()) return;
      create_parent_directory(output);
      for (const auto& path : paths)
        writers.push_back(std::make_unique<ShadedGlbWriter>(
            path, sequence, frame_ids, fps,
            /*with_visibility=*/true, frame_bounds,
            options.glb_layout == "input" ? GlbLayout::Input : GlbLayout::Sides, prepared.up.turn));
    });
    together([&] {
      if (World::root() && prepared.render)
        for (const std::filesystem::path& directory : prepared.render->directories)
          renders.push_back(std::make_unique<StagedFiles>(directory));
    });
  }
};

void run_shade(const ShadeOptions& options) {
  std::vector<Lighting> setups;
  together([&] { setups = gather_lightings(options); });
  ShadePreparation prepared;
  JobSteps steps;
  steps.check_outputs = [&] { check_shade_outputs(options, setups, !options.relight_file.empty()); };
  steps.before_plan = [&](const MeshSequence& sequence, std::size_t first, std::size_t last) {
    return prepared.prepare(options, setups, sequence, first, last);
  };
  steps.key = [&](const SlicingPlan& plan) {
    return shade_key(options, plan, setups, prepared.render ? &*prepared.render : nullptr);
  };
  const std::unique_ptr<PreparedJob> job = prepare(options.job, steps);
  ShadeOutputs outputs;
  outputs.open(options, setups, *job, prepared);

  ShadeParams shade;
  shade.albedo = options.albedo;
  shade.exposure = options.exposure;
  shade.interreflection = !options.no_interreflection;
  ToneMapParams tone;
  tone.exposure = options.exposure;
  FrameWork work;
  work.vertices = job->sequence().topology().num_vertices;
  const ShadeJob shading{options,
                         job->sequence(),
                         *job->scene,
                         setups,
                         job->plan,
                         prepared.cache ? &*prepared.cache : nullptr,
                         prepared.cached,
                         job->first,
                         job->last - job->first,
                         shade,
                         tone,
                         prepared.render ? &*prepared.render : nullptr,
                         prepared.up,
                         &work};
  double cone_seconds = 0.0, shade_seconds = 0.0;
  ContactWarning contact;
  run_frames(
      *job, "shade",
      [&](std::size_t a, std::size_t b, const EmitFrame& emit) { shade_chunk(shading, a, b, emit); },
      [&](std::size_t f, std::string_view payload) {
        consume_shaded(f, payload, outputs.writers, outputs.renders, cone_seconds, shade_seconds, contact);
      },
      &work);
  if (!World::root()) return;
  contact.warn(shading.world.topology().contact_tolerance, std::cerr);
  commit_together(outputs.writers, outputs.renders);
  report() << shade_summary(shading, job->chunks, outputs.paths, cone_seconds, shade_seconds);
}

}  // namespace

void register_shade_command(CLI::App& app) {
  auto options = std::make_shared<ShadeOptions>();
  auto* cmd = app.add_subcommand(
      "shade",
      "Shade an animated cloth from its visibility cones (both sides, Stewart-Langer inter-reflection) under "
      "any lights, and write an animated .glb with sRGB vertex colours (and PNG renders).");
  options->job.add_to(*cmd, /*engine_options=*/false);
  cmd->add_option("-o,--output", options->output,
                  "output .glb (with --relight: OUT_<setup>.glb per setup); - for standard output")
      ->required();
  cmd->add_option("--glb-layout", options->glb_layout,
                  "sides: per frame the welded mesh with a front and a back primitive (what `pleat view` "
                  "shows); input: per frame your mesh as given (its vertex order, UVs and normals), front "
                  "colour in COLOR_0, back in COLOR_1")
      ->check(CLI::IsMember({"sides", "input"}))
      ->capture_default_str();
  add_light_option(*cmd, options->light_specs, "Default: sky:1");
  cmd->add_option(
      "--lights", options->lights_file,
      "JSON lighting file: {\"lights\": [\"sky:0.5\", {\"type\": \"point\", \"position\": [0,2,1], "
      "\"intensity\": 10}, ...]} (combined with --light)");
  cmd->add_option(
      "--relight", options->relight_file,
      "JSON file of several setups, {\"setups\": [{\"name\": \"noon\", \"lights\": [...]}, ...]}: one cone "
      "computation per frame, one output per setup");
  cmd->add_option(
      "--cones", options->cones,
      "shade from a cone cache written by `pleat visibility --cones` (no visibility is computed; the "
      "plan options are ignored)");
  cmd->add_option("--albedo", options->albedo, "cloth albedo rho in [0, 1)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 0.999));
  cmd->add_option("--exposure", options->exposure,
                  "multiplies the radiance before tone mapping (Reinhard, white 4)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--no-interreflection", options->no_interreflection, "direct light only: B = rho E / pi");
  cmd->add_option("--render", options->render_dir,
                  "also write PNG images of the shaded frames into DIR (with --relight: DIR/<setup>/), as "
                  "frame_NNNN.png, NNNN the source frame number (PC2 scene frame, OBJ-sequence file number)");
  cmd->add_option(
         "--render-mode", options->render_mode,
         "what the images show: shaded (the lit cloth) or sky-visibility (A of the side seen, through "
         "the viridis colour map, with a legend)")
      ->check(CLI::IsMember({"shaded", "sky-visibility"}))
      ->capture_default_str();
  cmd->add_option("--width", options->width, "image width")
      ->capture_default_str()
      ->check(CLI::Range(16, 16384));
  cmd->add_option("--height", options->height, "image height")
      ->capture_default_str()
      ->check(CLI::Range(16, 16384));
  cmd->add_option("--camera", options->camera,
                  "ex,ey,ez,tx,ty,tz,ux,uy,uz[,fov] (default: auto-framed 3/4 view)");
  cmd->add_option(
         "--up", options->up,
         "the input's up: x, y, z, -x, -y, -z, a vector X,Y,Z, or auto (the side of --ground, else the way "
         "the cloth falls, else y). The glb is turned so that it stands up in glTF's Y-up space (a "
         "Blender Z-up cache imports upright); the auto-framed camera and the renders' occluders use it")
      ->capture_default_str();
  cmd->add_option("--render-every", options->render_every,
                  "render the frames whose source frame number is a multiple of N")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--hide-occluders", options->hide_occluders,
                "--render: draw the cloth alone (the occluders still block its sky)");
  cmd->add_option("--turntable", options->turntable,
                  "with a single frame: N images turning about the up axis")
      ->check(CLI::NonNegativeNumber);
  options->job.chunking.add_to(*cmd);
  cmd->footer(
      "Examples:\n"
      "  pleat shade curtain.obj --cache curtain.pc2 -o curtain.glb --light cloudy:1,up=0,1,0 --render "
      "renders/\n"
      "  pleat shade curtain.obj --cache curtain.pc2 -o lit.glb --light sky:0.15 --light "
      "point:0.6,-0.8,1.2,I=3 \\\n"
      "      --light 'area:-0.5,-1.5,2;0.5,-1.5,2;0.5,-0.5,2;-0.5,-0.5,2,L=4' --albedo 0.5 --frames 0:30\n"
      "  pleat shade flag.glb -o flag.glb --light env:studio.hdr,up=0,1,0,scale=1.5 --render renders/ --up "
      "y\n"
      "  pleat shade curtain.obj --cache curtain.pc2 -o curtain.glb --relight setups.json   # "
      "curtain_<name>.glb\n"
      "  pleat visibility curtain.obj --cache curtain.pc2 -o A.csv --cones curtain.cones   # cones once, "
      "then\n"
      "  pleat shade curtain.obj --cache curtain.pc2 -o dusk.glb --cones curtain.cones --light "
      "dir:0.3,-1,0.2,E=2\n"
      "Radiance: B = rho (E/pi) / (1 - rho (1 - A)) per vertex and side, E the direct irradiance through the "
      "cone, A its sky visibility; colours are Reinhard-tone-mapped sRGB.");
  cmd->callback([options] { run_shade(*options); });
}

}  // namespace pleat::cli
