#include "sim_io/mesh_report.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <glm/common.hpp>
#include <limits>
#include <vector>

#include "static_core/mesh_connectivity.hpp"

namespace pleat {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

}  // namespace

TopologyCounts count_topology(const MeshTopology& topology) {
  const MeshConnectivity connectivity(topology, "count_topology");
  TopologyCounts counts;
  for (Index e = 0; e < connectivity.num_edges(); ++e) {
    const EdgeKind kind = connectivity.kind(e);
    if (kind == EdgeKind::Degenerate) continue;  // (a, a), of a face with a repeated corner: not an edge here
    ++counts.edges;
    counts.boundary_edges += kind == EdgeKind::Boundary;
    counts.non_manifold_edges += kind == EdgeKind::NonManifold;
    counts.inconsistent_edges += kind == EdgeKind::Flipped;
  }
  for (Index v = 0; v < connectivity.num_vertices(); ++v)
    counts.isolated_vertices += connectivity.is_isolated(v);
  counts.boundary_loops = connectivity.boundary_loops();
  counts.components = connectivity.components();
  return counts;
}

std::size_t count_degenerate_faces(const MeshTopology& topology, const Frame& frame) {
  std::size_t count = 0;
  for (const Triangle& t : topology.triangles) {
    const glm::dvec3 &a = frame.positions[t[0]], &b = frame.positions[t[1]], &c = frame.positions[t[2]];
    if (CGAL::collinear(Kernel::Point_3(a.x, a.y, a.z), Kernel::Point_3(b.x, b.y, b.z),
                        Kernel::Point_3(c.x, c.y, c.z)))
      ++count;
  }
  return count;
}

std::size_t count_far_flung(const MeshTopology& topology, const Frame& frame, Index& worst, double& ratio) {
  std::vector<char> used(topology.num_vertices, 0);
  for (const Triangle& t : topology.triangles)
    for (const Index v : t) used[v] = 1;
  std::vector<Index> vertices;
  for (Index v = 0; v < topology.num_vertices; ++v)
    if (used[v]) vertices.push_back(v);
  if (vertices.empty()) return 0;
  const auto median = [](std::vector<double> values) {
    std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(values.size() / 2), values.end());
    return values[values.size() / 2];
  };
  glm::dvec3 centre;  // the median point, coordinate by coordinate
  for (int a = 0; a < 3; ++a) {
    std::vector<double> c;
    for (const Index v : vertices) c.push_back(frame.positions[v][a]);
    centre[a] = median(std::move(c));
  }
  std::vector<double> distance;
  for (const Index v : vertices) distance.push_back(glm::distance(frame.positions[v], centre));
  const double radius = median(distance);
  if (!(radius > 0)) return 0;
  std::size_t count = 0, farthest = 0;
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    if (distance[i] > kFarFlung * radius) ++count;
    if (distance[i] > distance[farthest]) farthest = i;
  }
  if (count == 0) return 0;
  worst = vertices[farthest];
  ratio = distance[farthest] / radius;
  return count;
}

std::vector<Index> isolated_vertices(const MeshTopology& topology) {
  std::vector<char> used(topology.num_vertices, 0);
  for (const Triangle& t : topology.triangles)
    for (Index v : t) used[v] = 1;
  std::vector<Index> isolated;
  for (Index v = 0; v < topology.num_vertices; ++v)
    if (!used[v]) isolated.push_back(v);
  return isolated;
}

MeshReport report_mesh(const MeshSequence& sequence,
                       const std::function<void(std::size_t, const Frame&)>& per_frame) {
  MeshReport r;
  r.input_vertices = sequence.num_input_vertices();
  r.welded_vertices = sequence.topology().num_vertices;
  r.welded_duplicates = sequence.welded_duplicates();
  r.input_faces = sequence.input_triangles().size();
  r.faces = sequence.topology().triangles.size();
  r.removed_faces = sequence.removed_faces();
  r.frames = sequence.num_frames();
  r.frame_rate = sequence.frame_rate();
  r.start_time = sequence.frame_time(0);
  r.duration = sequence.duration();
  r.topology = count_topology(sequence.topology());
  r.bbox_min = glm::dvec3(std::numeric_limits<double>::infinity());
  r.bbox_max = glm::dvec3(-std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < sequence.num_frames(); ++i) {
    const Frame frame = sequence.frame(i);
    for (const glm::dvec3& p : frame.positions) {
      r.bbox_min = glm::min(r.bbox_min, p);
      r.bbox_max = glm::max(r.bbox_max, p);
    }
    const std::size_t degenerate = count_degenerate_faces(sequence.topology(), frame);
    if (i == 0) r.degenerate_faces_first_frame = degenerate;
    r.degenerate_faces_max = std::max(r.degenerate_faces_max, degenerate);
    if (degenerate > 0) ++r.frames_with_degenerate_faces;
    Index worst = 0;
    double ratio = 0.0;
    if (const std::size_t far = count_far_flung(sequence.topology(), frame, worst, ratio); far > 0) {
      if (r.frames_with_far_flung++ == 0) {
        r.far_flung_first_frame = i;
        r.far_flung_first_count = far;
        r.far_flung_vertex = worst;
        r.far_flung_ratio = ratio;
      }
      r.far_flung_max = std::max(r.far_flung_max, far);
    }
    if (per_frame) per_frame(i, frame);
  }
  return r;
}

}  // namespace pleat
