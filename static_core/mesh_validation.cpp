#include "static_core/mesh_validation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <string>
#include <vector>

#include "support/input_error.hpp"

namespace pleat {
namespace {

std::string number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", x);
  return text;
}

/// Whether every coordinate is finite, in one branch-free pass: x * 0 is (+-)0 for a finite x and NaN for a
/// NaN or an infinity, and a NaN survives any sum. Four independent sums let the compiler use SIMD and hide
/// the adds' latency (cheaper than a loop of std::isfinite tests).
bool all_finite(const std::vector<glm::dvec3>& positions) {
  glm::dvec3 sum[4] = {glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0)};
  const std::size_t n = positions.size();
  std::size_t v = 0;
  for (; v + 4 <= n; v += 4)
    for (int k = 0; k < 4; ++k) sum[k] += positions[v + k] * 0.0;
  for (; v < n; ++v) sum[0] += positions[v] * 0.0;
  const glm::dvec3 total = (sum[0] + sum[1]) + (sum[2] + sum[3]);
  return total.x + total.y + total.z == 0.0;
}

/// 2^53: beyond it doubles skip integers.
constexpr double kExactIntegers = 9007199254740992.0;

/// Whether every coordinate lies within [-limit, limit] (finite ones), in one branch-free pass.
bool all_within(const std::vector<glm::dvec3>& positions, double limit) {
  double largest = 0.0;
  for (const glm::dvec3& p : positions)
    largest = std::max({largest, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  return largest <= limit;
}

}  // namespace

void validate_topology(const MeshTopology& topology, const char* who) {
  if (topology.num_occluder_vertices > topology.num_vertices)
    throw ArgumentError(who, "",
                        std::to_string(topology.num_occluder_vertices) + " occluder vertices of " +
                            std::to_string(topology.num_vertices));
  if (topology.num_plane_triangles > topology.triangles.size())
    throw ArgumentError(who, "",
                        std::to_string(topology.num_plane_triangles) + " plane triangles of " +
                            std::to_string(topology.triangles.size()));
  for (std::size_t i = 0; i < topology.planes.size(); ++i) {
    const OccludingPlane& p = topology.planes[i];
    if (!(std::abs(glm::length(p.normal) - 1.0) < 1e-9) || !std::isfinite(p.offset))
      throw ArgumentError(who, "occluding plane " + std::to_string(i),
                          "needs a unit normal and a finite offset");
  }
  if (!(std::isfinite(topology.contact_tolerance) && topology.contact_tolerance >= 0.0))
    throw ArgumentError(who, "contact tolerance", "must be a finite distance >= 0");
  Index largest = 0;
  for (const Triangle& t : topology.triangles) largest = std::max({largest, t[0], t[1], t[2]});
  if (topology.triangles.empty() || largest < topology.num_vertices) {
    // The cloth's triangles first, over the cloth's vertices; then the occluders', over theirs.
    const Index receivers = topology.num_receivers();
    bool occluders = false;
    for (std::size_t f = 0; f < topology.triangles.size(); ++f) {
      const Triangle& t = topology.triangles[f];
      const int of_occluders = (t[0] >= receivers) + (t[1] >= receivers) + (t[2] >= receivers);
      if (of_occluders % 3 != 0)
        throw ArgumentError(who, "triangle " + std::to_string(f), "joins cloth and occluder vertices");
      if (of_occluders == 0 && occluders)
        throw ArgumentError(who, "triangle " + std::to_string(f), "a cloth triangle after an occluder's");
      occluders = occluders || of_occluders == 3;
    }
    return;
  }
  for (std::size_t f = 0; f < topology.triangles.size(); ++f)
    for (Index v : topology.triangles[f])
      if (v >= topology.num_vertices)
        throw ArgumentError(who, "triangle " + std::to_string(f),
                            "vertex index " + std::to_string(v) + " out of range (" +
                                std::to_string(topology.num_vertices) + " vertices)");
}

std::string frame_place(const Frame& frame) {
  char text[48];
  std::snprintf(text, sizeof text, "frame at t=%g", frame.time);
  return text;
}

void validate_frame(const MeshTopology& topology, const Frame& frame, const char* who) {
  const std::size_t count = frame.positions.size();
  if (count != topology.num_vertices)
    throw ArgumentError(who, frame_place(frame),
                        std::string(count < topology.num_vertices ? "too few" : "too many") +
                            " positions: " + std::to_string(count) + " for " +
                            std::to_string(topology.num_vertices) + " vertices");
  if (all_finite(frame.positions) && all_within(frame.positions, kExactIntegers)) return;
  for (std::size_t v = 0; v < count; ++v) {
    const glm::dvec3& p = frame.positions[v];
    const std::string place = frame_place(frame) + ", vertex " + std::to_string(v);
    const std::string at = "(" + number(p.x) + ", " + number(p.y) + ", " + number(p.z) + ")";
    if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)))
      throw ArgumentError(who, place, "non-finite position " + at);
    if (!all_within({p}, kExactIntegers))
      throw InputError(who, place,  // a position far out: bad input, not a bad call
                       "position " + at +
                           " beyond +-2^53, where doubles stop holding every integer (an exploded "
                           "simulation, or a transform far from the origin?)");
  }
}

void validate_mesh(const MeshTopology& topology, const Frame& frame, const char* who) {
  validate_topology(topology, who);
  validate_frame(topology, frame, who);
}

}  // namespace pleat
