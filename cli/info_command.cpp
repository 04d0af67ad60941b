// `pleat info`: what pleat sees in an input — vertices (input and welded), faces, frames, frame rate,
// duration, bounding box, boundary loops, non-manifold edges, degenerate faces, welded duplicates, and with
// --check-intersections the self-intersecting face pairs of every frame (pleat's algorithm requires none).
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli/cli_options.hpp"
#include "cli/commands.hpp"
#include "cli/job_error.hpp"
#include "cli/progress.hpp"
#include "sim_io/load_sequence.hpp"
#include "sim_io/mesh_report.hpp"
#include "sim_io/mesh_sequence.hpp"
#include "sim_io/self_intersections.hpp"

namespace pleat::cli {

namespace {

struct InfoOptions {
  InputOptions in;
  bool check_intersections = false;
  bool json = false;
  double fps = kDefaultSceneFps;
};

std::string number(double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.6g", v + 0.0);  // + 0.0: print -0 as 0
  return buffer;
}

std::string vec(const glm::dvec3& v) {
  return "(" + number(v.x) + ", " + number(v.y) + ", " + number(v.z) + ")";
}

void run_info(const InfoOptions& options) {
  LoadOptions load;
  load.scene_fps = options.fps;
  const MeshSequence sequence = load_sequence(options.in.input, options.in.cache, load);

  std::vector<std::size_t> intersecting_pairs;  // per frame, when checked
  Progress progress("info", sequence.num_frames());
  const MeshReport report = report_mesh(sequence, [&](std::size_t, const Frame& frame) {
    if (options.check_intersections)
      intersecting_pairs.push_back(self_intersecting_faces(sequence.topology(), frame).size());
    progress.advance();
  });
  progress.finish();
  auto input_of = [&](Index welded) {  // the first input vertex welded into `welded`
    const auto& of_input = sequence.welded_of_input();
    return static_cast<Index>(std::find(of_input.begin(), of_input.end(), welded) - of_input.begin());
  };
  std::size_t frames_with_intersections = 0, max_pairs = 0, max_frame = 0;
  for (std::size_t i = 0; i < intersecting_pairs.size(); ++i) {
    if (intersecting_pairs[i] > 0) ++frames_with_intersections;
    if (intersecting_pairs[i] > max_pairs) {
      max_pairs = intersecting_pairs[i];
      max_frame = i;
    }
  }
  const TopologyCounts& t = report.topology;

  if (options.json) {
    nlohmann::json j = {
        {"input", options.in.input},
        {"cache", options.in.cache},
        {"input_vertices", report.input_vertices},
        {"welded_vertices", report.welded_vertices},
        {"welded_duplicates", report.welded_duplicates},
        {"input_faces", report.input_faces},
        {"faces", report.faces},
        {"removed_faces", report.removed_faces},
        {"frames", report.frames},
        {"frame_rate", report.frame_rate},
        {"start_time", report.start_time},
        {"duration", report.duration},
        {"bbox_min", {report.bbox_min.x, report.bbox_min.y, report.bbox_min.z}},
        {"bbox_max", {report.bbox_max.x, report.bbox_max.y, report.bbox_max.z}},
        {"edges", t.edges},
        {"boundary_edges", t.boundary_edges},
        {"boundary_loops", t.boundary_loops},
        {"non_manifold_edges", t.non_manifold_edges},
        {"inconsistent_edges", t.inconsistent_edges},
        {"isolated_vertices", t.isolated_vertices},
        {"components", t.components},
        {"degenerate_faces_first_frame", report.degenerate_faces_first_frame},
        {"degenerate_faces_max", report.degenerate_faces_max},
        {"frames_with_degenerate_faces", report.frames_with_degenerate_faces},
        {"far_flung",
         {{"frames", report.frames_with_far_flung},
          {"max_vertices", report.far_flung_max},
          {"first_frame",
           report.frames_with_far_flung ? nlohmann::json(report.far_flung_first_frame) : nlohmann::json()},
          {"first_count", report.far_flung_first_count},
          {"vertex", input_of(report.far_flung_vertex)},
          {"distance_over_median", report.far_flung_ratio}}},
    };
    if (options.check_intersections) {
      j["self_intersections"] = {{"frames_with_intersections", frames_with_intersections},
                                 {"max_pairs", max_pairs},
                                 {"pairs_per_frame", intersecting_pairs}};
    }
    std::cout << j.dump(2) << '\n';
    return;
  }

  std::ostringstream out;
  out << "input               " << options.in.input << '\n';
  if (!options.in.cache.empty()) out << "cache               " << options.in.cache << '\n';
  out << "vertices            " << report.welded_vertices << " welded, " << report.input_vertices
      << " input (" << report.welded_duplicates << " welded duplicates)\n";
  out << "faces               " << report.faces << " triangles (" << report.input_faces
      << " input triangles, " << report.removed_faces << " removed by welding)\n";
  out << "frames              " << report.frames;
  if (report.frames > 1)
    out << " at " << number(report.frame_rate) << " fps, duration " << number(report.duration) << " s (from "
        << number(report.start_time) << " s)";
  out << '\n';
  out << "bounding box        min " << vec(report.bbox_min) << "  max " << vec(report.bbox_max)
      << "  (all frames)\n";
  out << "edges               " << t.edges << " (" << t.boundary_edges << " on the boundary)\n";
  out << "boundary loops      " << t.boundary_loops << '\n';
  out << "non-manifold edges  " << t.non_manifold_edges << '\n';
  out << "flipped edges       " << t.inconsistent_edges << " (neighbouring faces with opposite winding)\n";
  out << "degenerate faces    " << report.degenerate_faces_first_frame << " in frame 0, at most "
      << report.degenerate_faces_max << " per frame (" << report.frames_with_degenerate_faces
      << " frames with any)\n";
  out << "far-flung vertices  ";
  if (report.frames_with_far_flung == 0)
    out << "none (none over " << kFarFlung << "x the median distance from the median point)\n";
  else
    out << report.frames_with_far_flung << " frames, at most " << report.far_flung_max
        << " vertices; first frame " << report.far_flung_first_frame << ": " << report.far_flung_first_count
        << ", vertex " << input_of(report.far_flung_vertex) << " at " << number(report.far_flung_ratio)
        << "x the median distance from the median point (an exploded simulation?)\n";
  out << "components          " << t.components << " (" << t.isolated_vertices << " isolated vertices)\n";
  if (options.check_intersections) {
    out << "self-intersections  " << frames_with_intersections << " of " << report.frames
        << " frames intersect";
    if (max_pairs > 0) out << ", at most " << max_pairs << " face pairs (frame " << max_frame << ")";
    out << '\n';
    std::size_t listed = 0;
    for (std::size_t i = 0; i < intersecting_pairs.size(); ++i) {
      if (intersecting_pairs[i] == 0) continue;
      if (listed++ == 20) {
        out << "  ... " << (frames_with_intersections - 20) << " more frames\n";
        break;
      }
      out << "  frame " << i << ": " << intersecting_pairs[i] << " intersecting face pairs\n";
    }
  }
  std::cout << out.str();
}

}  // namespace

void register_info_command(CLI::App& app) {
  auto options = std::make_shared<InfoOptions>();
  auto* cmd = app.add_subcommand(
      "info", "Describe a cloth mesh or sequence: counts, frame rate, bounds, topology checks.");
  options->in.add_to(*cmd);
  cmd->add_flag("--check-intersections", options->check_intersections,
                "also count self-intersecting face pairs in every frame (the algorithm requires none)");
  cmd->add_flag("--json", options->json, "print the report as JSON");
  cmd->add_option("--fps", options->fps,
                  "scene frame rate for inputs that store frame numbers, not seconds (PC2, OBJ sequences)")
      ->default_val(kDefaultSceneFps)
      ->check(CLI::PositiveNumber);
  cmd->footer(
      "Examples:\n"
      "  pleat info cloth.obj --cache cloth.pc2 --check-intersections\n"
      "  pleat info 'frames/cloth_%04d.obj' --json\n"
      "  pleat info cloth.glb");
  cmd->callback([options] { on_rank_zero_alone([&] { run_info(*options); }); });
}

}  // namespace pleat::cli
