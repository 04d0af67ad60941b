#include "sim_io/mesh_validation.hpp"

#include "sim_io/input_error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

namespace pleat {
namespace {

std::string number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", x);
  return text;
}

std::string frame_place(const Frame& frame) {
  char text[48];
  std::snprintf(text, sizeof text, "frame at t=%g", frame.time);
  return text;
}

/// False for NaN and +-inf; branch-free so that the loop over a frame vectorizes.
inline bool finite(double x) { return std::abs(x) <= std::numeric_limits<double>::max(); }

}  // namespace

void validate_topology(const MeshTopology& topology, const char* who) {
  Index largest = 0;
  for (const Triangle& t : topology.triangles) largest = std::max({largest, t[0], t[1], t[2]});
  if (topology.triangles.empty() || largest < topology.num_vertices) return;
  for (std::size_t f = 0; f < topology.triangles.size(); ++f)
    for (Index v : topology.triangles[f])
      if (v >= topology.num_vertices)
        throw InputError(who, "triangle " + std::to_string(f),
                         "vertex index " + std::to_string(v) + " out of range (" +
                             std::to_string(topology.num_vertices) + " vertices)");
}

void validate_frame(const MeshTopology& topology, const Frame& frame, const char* who) {
  const std::size_t count = frame.positions.size();
  if (count != topology.num_vertices)
    throw InputError(who, frame_place(frame),
                     std::string(count < topology.num_vertices ? "too few" : "too many") + " positions: " +
                         std::to_string(count) + " for " + std::to_string(topology.num_vertices) + " vertices");
  bool all_finite = true;
  for (const glm::dvec3& p : frame.positions) all_finite &= finite(p.x) & finite(p.y) & finite(p.z);
  if (all_finite) return;
  for (std::size_t v = 0; v < count; ++v) {
    const glm::dvec3& p = frame.positions[v];
    if (!(finite(p.x) && finite(p.y) && finite(p.z)))
      throw InputError(who, frame_place(frame) + ", vertex " + std::to_string(v),
                       "non-finite position (" + number(p.x) + ", " + number(p.y) + ", " + number(p.z) + ")");
  }
}

void validate_mesh(const MeshTopology& topology, const Frame& frame, const char* who) {
  validate_topology(topology, who);
  validate_frame(topology, frame, who);
}

}  // namespace pleat
