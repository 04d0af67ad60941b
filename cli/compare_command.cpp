// `pleat compare`: how close is pleat's cone shading to a path-traced reference? One frame, one lighting:
// (left) the Stewart–Langer shading from the frame's visibility cones (shading/shade.hpp), (middle) an
// Embree path-traced reference of the same frame, lights and albedo (shading/path_trace.hpp, per vertex and
// side, in the same units), both tone-mapped alike and rendered from the same camera, and (right) the
// per-vertex absolute difference of their luminances as a colour map with a legend. One summary line on
// stdout (on stderr when the image goes to standard output; none with --quiet): the mean and 95th percentile
// of |cone - reference| over every vertex and both sides, relative to the reference's mean luminance, the
// mean signed difference (bias), and the reference's own Monte-Carlo noise (estimated from two independent
// halves of the paths, so the floor under which a difference means nothing is printed beside it).
//
// Luminance: Rec. 709 weights of linear RGB radiance (the tone mapping's Y). Cost: one compute_visibility,
// one shade_frame, and paths x (mean depth ~ 1/(1 - albedo)) rays per vertex and side.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <glm/common.hpp>
#include <iostream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli/cli_options.hpp"
#include "cli/commands.hpp"
#include "cli/global_options.hpp"
#include "cli/input_warnings.hpp"
#include "cli/job_error.hpp"
#include "shading/embree_scene.hpp"
#include "shading/lights.hpp"
#include "shading/path_trace.hpp"
#include "shading/render.hpp"
#include "shading/scene_render.hpp"
#include "shading/shade.hpp"
#include "sim_io/load_sequence.hpp"
#include "sim_io/mesh_sequence.hpp"
#include "static_core/visibility.hpp"
#include "support/atomic_file.hpp"

namespace pleat::cli {

namespace {

struct CompareOptions {
  InputOptions in;
  std::string frame = "0";
  std::vector<std::string> light_specs;
  std::string lights_file;
  std::string output;
  int paths = 1024;
  double albedo = 0.6;
  double exposure = 1.0;
  std::uint64_t seed = 1;
  int width = 480;
  int height = 360;
  std::string camera;
  std::string up = "0,1,0";
  PlanOptions plan;
  SceneOptions scene;
};

double luminance(const glm::vec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

glm::dvec3 parse_up(const std::string& text) {
  glm::dvec3 v;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%lf,%lf,%lf%c", &v.x, &v.y, &v.z, &tail) != 3)
    throw std::invalid_argument("--up: expected x,y,z, got '" + text + "'");
  return v;
}

/// The smallest of 1, 2, 2.5, 5 x 10^k that is >= x (a legend's end value).
double nice_ceiling(double x) {
  if (!(x > 0.0)) return 1.0;
  const double p = std::pow(10.0, std::floor(std::log10(x)));
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0})
    if (m * p >= x * (1 - 1e-12)) return m * p;
  return 10.0 * p;
}

std::string format_number(double x) {
  std::ostringstream s;
  s.precision(3);
  s << x;
  return s.str();
}

double percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  const std::size_t k =
      std::min(values.size() - 1, static_cast<std::size_t>(std::ceil(q * values.size())) - 1);
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

/// The cones' shading against the path-traced reference, per vertex and side, in luminance.
struct Comparison {
  std::array<std::vector<glm::vec3>, 2> reference;  ///< the mean of the two halves of the paths
  std::array<std::vector<double>, 2> difference;    ///< |cones - reference|
  double reference_mean = 0.0;                      ///< over every vertex and side
  double mean_difference = 0.0, p95 = 0.0, p99 = 0.0;
  double bias = 0.0;   ///< mean of cones - reference
  double noise = 0.0;  ///< the reference's rms Monte-Carlo noise, from the halves' difference
};

Comparison compare_luminance(const ShadedFrame& shaded, const PathTracedFrame& half_a,
                             const PathTracedFrame& half_b, std::size_t n) {
  Comparison c;
  std::vector<double> all_differences;
  all_differences.reserve(2 * n);
  double reference_sum = 0.0, signed_sum = 0.0, noise_squares = 0.0;
  for (int s = 0; s < 2; ++s) {
    c.reference[s].resize(n);
    c.difference[s].resize(n);
    for (std::size_t v = 0; v < n; ++v) {
      c.reference[s][v] = 0.5f * (half_a.radiance[s][v] + half_b.radiance[s][v]);
      const double ref = luminance(c.reference[s][v]);
      const double ours = luminance(shaded.radiance[s][v]);
      const double half_gap = 0.5 * (luminance(half_a.radiance[s][v]) - luminance(half_b.radiance[s][v]));
      c.difference[s][v] = std::abs(ours - ref);
      all_differences.push_back(c.difference[s][v]);
      reference_sum += ref;
      signed_sum += ours - ref;
      noise_squares += half_gap * half_gap;  // E[(a - b)^2 / 4] = variance of the mean of a and b
    }
  }
  const double count = 2.0 * double(n);
  c.reference_mean = reference_sum / count;
  for (double d : all_differences) c.mean_difference += d;
  c.mean_difference /= count;
  c.p95 = percentile(all_differences, 0.95);
  c.p99 = percentile(all_differences, 0.99);
  c.bias = signed_sum / count;
  c.noise = std::sqrt(noise_squares / count);
  return c;
}

// The lighting, after the outputs are checked (before any work: not an input, a file pleat may replace).
Lighting lighting_of(const CompareOptions& options) {
  Lighting lighting;
  if (!options.lights_file.empty()) lighting = load_lighting(options.lights_file);
  for (const std::string& spec : options.light_specs) add_light_spec(lighting, spec);
  std::vector<InputFile> inputs = options.in.files();
  for (const auto& more : {options.scene.files(), options.plan.files()})
    inputs.insert(inputs.end(), more.begin(), more.end());
  if (!options.lights_file.empty()) inputs.push_back({"--lights", options.lights_file});
  for (const auto& [option, file] : lighting.files()) inputs.push_back({option, file.string()});
  check_outputs({{"-o", options.output}, options.plan.output()}, {}, inputs);
  if (lighting.empty()) throw std::invalid_argument("give at least one --light (or --lights FILE)");
  if (options.output != kStandardOutput && std::filesystem::path(options.output).extension() != ".png")
    throw std::invalid_argument("-o: the comparison is a .png image, got '" + options.output + "'");
  return lighting;
}

void run_compare(const CompareOptions& options) {
  const Lighting lighting = lighting_of(options);

  const MeshSequence sequence = load_sequence(options.in.input, options.in.cache);
  const MeshTopology& topology = sequence.topology();
  const Scene world = options.scene.make(sequence);  // the cloth in its scene: occluders block, get no cones
  std::size_t first = 0, last = 0;
  parse_frame_range(options.frame, sequence.num_frames(), first, last, "--frame");
  if (last != first + 1)
    throw std::invalid_argument("--frame: give one frame N, got '" + options.frame + "'");
  const Frame frame = sequence.frame(first);

  // pleat: cones, then the shading pass.
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const SlicingPlan plan = options.plan.make(sequence);
  warn_about_cloth(sequence, first);
  const Frame world_frame = world.with_occluders(first, frame);
  const FrameVisibility visibility = compute_visibility(world.topology(), world_frame, plan);
  const auto t1 = Clock::now();
  ShadeParams shade_params;
  shade_params.albedo = options.albedo;
  ShadedFrame shaded;
  double shade_seconds = 1e300;  // the fastest of three passes (the first also starts TBB's threads)
  for (int pass = 0; pass < 3; ++pass) {
    const auto s0 = Clock::now();
    shade_frame(topology, frame, visibility, lighting, shade_params, shaded);
    shade_seconds = std::min(shade_seconds, std::chrono::duration<double>(Clock::now() - s0).count());
  }
  const auto t2 = Clock::now();

  // The reference: two independent halves of the paths (their difference measures the noise), averaged.
  EmbreeScene scene(world.topology(), world_frame);  // occluders scatter paths as grey Lambertian surfaces
  PathTraceParams trace;
  trace.albedo = options.albedo;
  trace.paths_per_vertex = std::max(1, options.paths / 2);
  trace.seed = options.seed;
  const PathTracedFrame half_a =
      path_trace_vertices(scene, world.topology(), world_frame, visibility.normals, lighting, trace);
  trace.seed = options.seed + 0x9e3779b97f4a7c15ULL;
  const PathTracedFrame half_b =
      path_trace_vertices(scene, world.topology(), world_frame, visibility.normals, lighting, trace);
  const auto t3 = Clock::now();

  const std::size_t n = topology.num_vertices;
  const Comparison c = compare_luminance(shaded, half_a, half_b, n);
  const double scale = c.reference_mean > 0.0 ? c.reference_mean : 1.0;

  // Images: same camera, same tone mapping; the difference map from 0 to a round value above its p99.
  Camera camera;
  if (!options.camera.empty()) {
    camera = parse_camera(options.camera);
  } else {
    AutoFrameParams framing;
    framing.up = parse_up(options.up);
    framing.aspect = double(options.width) / options.height;
    camera = auto_frame(frame, framing);
  }
  ToneMapParams tone;
  tone.exposure = options.exposure;
  // The cloth in its scene, drawn as shade draws it.
  SceneRenderer renderer(world.topology(), parse_up(options.up));
  renderer.set_frame(world_frame);
  const Image ours_image = renderer.render(to_srgb(shaded.front(), tone), to_srgb(shaded.back(), tone),
                                           camera, options.width, options.height);
  const Image reference_image = renderer.render(to_srgb(c.reference[0], tone), to_srgb(c.reference[1], tone),
                                                camera, options.width, options.height);
  const double top = nice_ceiling(std::max(c.p99, 1e-12));
  std::array<std::vector<glm::vec3>, 2> heat;
  for (int s = 0; s < 2; ++s) {
    heat[s].resize(n);
    for (std::size_t v = 0; v < n; ++v) heat[s][v] = viridis(c.difference[s][v] / top);
  }
  const Image heat_image =
      with_legend(renderer.render(heat[0], heat[1], camera, options.width, options.height), 0.0, top,
                  "LUMINANCE, REF MEAN " + format_number(c.reference_mean));
  char pt_label[64];
  std::snprintf(pt_label, sizeof pt_label, "PATH TRACED (%d PATHS)", 2 * trace.paths_per_vertex);
  const std::array<LabeledImage, 3> panels = {LabeledImage{&ours_image, "PLEAT CONES"},
                                              LabeledImage{&reference_image, pt_label},
                                              LabeledImage{&heat_image, "ABS DIFFERENCE"}};
  const std::filesystem::path output(options.output);
  create_parent_directory(output);
  write_png(output, side_by_side(panels));

  {
    const double ms = 1e3;
    char line[512];
    std::snprintf(
        line, sizeof line,
        "frame %zu, %zu vertices x 2 sides: |cones - path traced| mean %.1f%%, p95 %.1f%% of the "
        "reference mean %.4g (bias %+.1f%%, reference noise %.1f%% rms at %d paths); cones %.0f ms, "
        "shading %.2f ms, path tracing %.1f s; wrote %s\n",
        first, n, 100 * c.mean_difference / scale, 100 * c.p95 / scale, c.reference_mean,
        100 * c.bias / scale, 100 * c.noise / scale, 2 * trace.paths_per_vertex,
        ms * std::chrono::duration<double>(t1 - t0).count(), ms * shade_seconds,
        std::chrono::duration<double>(t3 - t2).count(), output.string().c_str());
    report() << line;
  }
}

}  // namespace

void register_compare_command(CLI::App& app) {
  auto options = std::make_shared<CompareOptions>();
  auto* cmd =
      app.add_subcommand("compare",
                         "Side-by-side PNG of pleat's cone shading, an Embree path-traced reference of the "
                         "same frame and lights, "
                         "and their per-vertex difference; prints the mean and 95th-percentile difference.");
  options->in.add_to(*cmd);
  cmd->add_option("--frame", options->frame, "the frame to compare (negative counts from the end)")
      ->capture_default_str();
  add_light_option(*cmd, options->light_specs, "At least one (or --lights).");
  cmd->add_option("--lights", options->lights_file, "JSON lighting file (combined with --light)");
  cmd->add_option("-o,--output", options->output, "output .png; - for standard output")->required();
  cmd->add_option("--paths", options->paths, "path-traced samples per vertex and side")
      ->capture_default_str()
      ->check(CLI::Range(2, 1 << 20));
  cmd->add_option("--albedo", options->albedo, "cloth albedo rho in [0, 1), for both")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 0.999));
  cmd->add_option("--exposure", options->exposure, "multiplies the radiance before tone mapping")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--seed", options->seed, "path tracer seed")->capture_default_str();
  cmd->add_option("--width", options->width, "width of each panel")
      ->capture_default_str()
      ->check(CLI::Range(16, 8192));
  cmd->add_option("--height", options->height, "height of each panel")
      ->capture_default_str()
      ->check(CLI::Range(16, 8192));
  cmd->add_option("--camera", options->camera,
                  "ex,ey,ez,tx,ty,tz,ux,uy,uz[,fov] (default: auto-framed 3/4 view)");
  cmd->add_option("--up", options->up, "world up for the auto-framed camera")->capture_default_str();
  options->plan.add_to(*cmd);
  options->scene.add_to(*cmd);
  cmd->footer(
      "Examples:\n"
      "  pleat compare data/drape/drape.obj --cache data/drape/drape.pc2 --frame 60 --light "
      "cloudy:1,up=0,1,0 "
      "-o compare.png\n"
      "  pleat compare curtain.obj --cache curtain.pc2 --frame 20 --light sky:0.2 --light "
      "point:0.3,-0.8,1.2,I=3 "
      "--paths 4096 -o lamp.png");
  cmd->callback([options] { on_rank_zero_alone([&] { run_compare(*options); }); });
}

}  // namespace pleat::cli
