#include "oracles/mesh_topology_oracle.hpp"

#include <algorithm>
#include <cstdint>
#include <map>
#include <numeric>

namespace pleat::test {

OracleEdges oracle_edges(const MeshTopology& topology) {
  OracleEdges out;
  std::vector<std::array<Index, 3>> keyed;  // (a, b, face*3+i)
  for (Index f = 0; f < topology.triangles.size(); ++f)
    for (Index i = 0; i < 3; ++i) {
      Index a = topology.triangles[f][i], b = topology.triangles[f][(i + 1) % 3];
      if (a > b) std::swap(a, b);
      keyed.push_back({a, b, f * 3 + i});
    }
  std::sort(keyed.begin(), keyed.end());
  out.of_face.assign(topology.triangles.size(), {0, 0, 0});
  for (std::size_t k = 0; k < keyed.size(); ++k) {
    if (k == 0 || keyed[k][0] != keyed[k - 1][0] || keyed[k][1] != keyed[k - 1][1]) {
      out.endpoints.push_back({keyed[k][0], keyed[k][1]});
      out.face_sides.push_back(0);
    }
    out.of_face[keyed[k][2] / 3][keyed[k][2] % 3] = static_cast<Index>(out.endpoints.size() - 1);
    ++out.face_sides.back();
  }
  out.neighbours.assign(topology.num_vertices, {});
  for (const auto& e : out.endpoints)
    if (e[0] != e[1]) {
      out.neighbours[e[0]].push_back(e[1]);
      out.neighbours[e[1]].push_back(e[0]);
    }
  for (auto& n : out.neighbours) std::sort(n.begin(), n.end());
  out.faces_around.assign(topology.num_vertices, {});
  for (Index f = 0; f < topology.triangles.size(); ++f)
    for (Index v : topology.triangles[f])
      if (out.faces_around[v].empty() || out.faces_around[v].back() != f) out.faces_around[v].push_back(f);
  return out;
}

namespace {

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

TopologyCounts oracle_count_topology(const MeshTopology& topology) {
  TopologyCounts counts;
  const Index n = topology.num_vertices;
  struct Use {
    std::uint64_t key;
    bool forward;
  };
  std::vector<Use> uses;
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

bool oracle_closed_fan(const MeshTopology& topology, Index v) {
  std::map<Index, Index> next;  // link edge a -> b of each face (v, a, b)
  std::size_t faces = 0;
  for (const Triangle& t : topology.triangles) {
    const int at = int(std::count(t.begin(), t.end(), v));
    if (at == 0) continue;
    if (at > 1 || t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return false;
    const int i = int(std::find(t.begin(), t.end(), v) - t.begin());
    const Index a = t[std::size_t((i + 1) % 3)], b = t[std::size_t((i + 2) % 3)];
    if (!next.emplace(a, b).second) return false;  // two faces leave a: a flipped or non-manifold edge
    ++faces;
  }
  if (faces == 0) return false;  // isolated
  // One cycle through every link vertex: follow it from any one.
  Index at = next.begin()->first;
  for (std::size_t step = 0; step < faces; ++step) {
    const auto it = next.find(at);
    if (it == next.end()) return false;  // the link is a path: v is on the boundary
    at = it->second;
    if (at == next.begin()->first && step + 1 < faces) return false;  // a shorter cycle: two fans
  }
  return at == next.begin()->first;
}

}  // namespace pleat::test
