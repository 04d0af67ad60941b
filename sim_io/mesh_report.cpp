#include "sim_io/mesh_report.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <glm/common.hpp>
#include <limits>
#include <numeric>
#include <vector>

namespace pleat {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

class UnionFind {
 public:
  explicit UnionFind(std::size_t n) : m_parent(n) { std::iota(m_parent.begin(), m_parent.end(), Index(0)); }
  Index find(Index v) {
    while (m_parent[v] != v) v = m_parent[v] = m_parent[m_parent[v]];
    return v;
  }
  void unite(Index a, Index b) {
    a = find(a);
    b = find(b);
    if (a != b) m_parent[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<Index> m_parent;
};

}  // namespace

TopologyCounts count_topology(const MeshTopology& topology) {
  TopologyCounts counts;
  const Index n = topology.num_vertices;
  // Directed edges as (undirected key, direction), sorted so each undirected edge's uses are adjacent.
  struct Use {
    std::uint64_t key;
    bool forward;  // traversed from the smaller to the larger index
  };
  std::vector<Use> uses;
  uses.reserve(3 * topology.triangles.size());
  std::vector<bool> used(n, false);
  UnionFind faces(n);
  for (const Triangle& t : topology.triangles) {
    for (int k = 0; k < 3; ++k) {
      const Index a = t[std::size_t(k)], b = t[std::size_t((k + 1) % 3)];
      used[a] = true;
      if (a == b) continue;
      uses.push_back({(std::uint64_t(std::min(a, b)) << 32) | std::max(a, b), a < b});
    }
    faces.unite(t[0], t[1]);
    faces.unite(t[0], t[2]);
  }
  std::sort(uses.begin(), uses.end(), [](const Use& x, const Use& y) { return x.key < y.key; });
  UnionFind boundary(n);
  std::vector<bool> on_boundary(n, false);
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    std::size_t forward = 0;
    while (j < uses.size() && uses[j].key == uses[i].key) forward += uses[j++].forward ? 1 : 0;
    const std::size_t count = j - i;
    ++counts.edges;
    if (count == 1) {
      ++counts.boundary_edges;
      const auto a = Index(uses[i].key >> 32), b = Index(uses[i].key & 0xFFFFFFFFu);
      boundary.unite(a, b);
      on_boundary[a] = on_boundary[b] = true;
    } else if (count == 2) {
      if (forward != 1) ++counts.inconsistent_edges;
    } else {
      ++counts.non_manifold_edges;
    }
    i = j;
  }
  for (Index v = 0; v < n; ++v) {
    if (!used[v])
      ++counts.isolated_vertices;
    else if (faces.find(v) == v)
      ++counts.components;
    if (on_boundary[v] && boundary.find(v) == v) ++counts.boundary_loops;
  }
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
    if (per_frame) per_frame(i, frame);
  }
  return r;
}

}  // namespace pleat
