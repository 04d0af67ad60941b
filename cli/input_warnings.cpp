#include "cli/input_warnings.hpp"

#include <iostream>
#include <string>
#include <vector>

#include "sim_io/mesh_report.hpp"
#include "sim_io/self_intersections.hpp"

namespace pleat::cli {

namespace {

/// "36, 37 and 40", or the first `shown` and "... (N in all)".
std::string list_of(const std::vector<std::size_t>& items, std::size_t shown = 5) {
  std::string text;
  for (std::size_t i = 0; i < items.size() && i < shown; ++i) {
    if (i > 0) text += i + 1 == items.size() ? " and " : ", ";
    text += std::to_string(items[i]);
  }
  if (items.size() > shown) text += ", ... (" + std::to_string(items.size()) + " in all)";
  return text;
}

void warn_about_isolated(const MeshSequence& sequence) {
  const std::vector<Index> isolated = isolated_vertices(sequence.topology());
  if (isolated.empty()) return;
  std::vector<char> no_surface(sequence.topology().num_vertices, 0);
  for (Index w : isolated) no_surface[w] = 1;
  std::vector<std::size_t> inputs;
  const std::vector<Index>& welded = sequence.welded_of_input();
  for (std::size_t v = 0; v < welded.size(); ++v)
    if (no_surface[welded[v]]) inputs.push_back(v);
  std::cerr << "pleat: warning: " << sequence.name() << ": " << (inputs.size() == 1 ? "vertex " : "vertices ")
            << list_of(inputs) << (inputs.size() == 1 ? " belongs" : " belong")
            << " to no triangle: no surface, so no visibility (their CSV fields are left empty)\n";
}

void warn_about_degenerate(const MeshSequence& sequence, const MeshTopology& topology, const Frame& frame,
                           std::size_t index) {
  const std::size_t degenerate = count_degenerate_faces(topology, frame);
  if (degenerate == 0) return;
  const std::size_t faces = topology.triangles.size();
  std::cerr << "pleat: warning: " << sequence.name() << ": frame " << index << ": "
            << (degenerate == faces
                    ? "every triangle"
                    : std::to_string(degenerate) + " of " + std::to_string(faces) + " triangles")
            << (degenerate == 1 && faces == 1 ? " is" : " are")
            << " degenerate (collinear corners: no area, they block nothing"
            << (degenerate == faces ? "; the cloth has no surface" : "")
            << "; `pleat info` counts every frame's)\n";
}

}  // namespace

void warn_about_cloth(const MeshSequence& sequence, std::size_t index) {
  warn_about_isolated(sequence);
  const MeshTopology& topology = sequence.topology();
  const Frame frame = sequence.frame(index);
  warn_about_degenerate(sequence, topology, frame, index);
  if (const std::size_t pairs = self_intersecting_faces(topology, frame).size(); pairs > 0)
    std::cerr << "pleat: warning: frame " << index << " self-intersects (" << pairs
              << (pairs == 1 ? " face pair" : " face pairs")
              << "); visibility near the intersections is unreliable (`pleat info "
                 "--check-intersections` lists every frame's)\n";
}

}  // namespace pleat::cli
