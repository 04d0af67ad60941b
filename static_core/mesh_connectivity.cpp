#include "static_core/mesh_connectivity.hpp"

#include <OpenMesh/Core/Mesh/TriConnectivity.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <algorithm>
#include <mutex>

#include "static_core/assert.hpp"
#include "static_core/mesh_validation.hpp"

namespace pleat {

struct MeshConnectivity::HalfEdges {
  OpenMesh::TriConnectivity mesh;         ///< vertex i < num_vertices is vertex i; the others are copies
  std::vector<Index> original;            ///< per structure vertex: the input vertex it stands for
  std::vector<std::uint32_t> first_copy;  ///< CSR over input vertices: their copies (structure vertices)
  std::vector<Index> copies;

  /// Calls `f(r)` for the structure vertices standing for input vertex v that are in a face: itself, then
  /// its copies (OpenMesh's circulators must not start at an isolated vertex).
  template <class F>
  void for_each_copy(Index v, F&& f) const {
    if (!mesh.is_isolated(OpenMesh::VertexHandle(int(v)))) f(OpenMesh::VertexHandle(int(v)));
    for (std::uint32_t i = first_copy[v]; i < first_copy[v + 1]; ++i)
      f(OpenMesh::VertexHandle(int(copies[i])));
  }
};

struct MeshConnectivity::EdgeNumbering {
  std::vector<char> self_edge;             ///< per vertex: it has an edge (v, v)
  std::vector<std::uint32_t> first_edge;   ///< edges (v, b) with b >= v: first_edge[v]..
  std::vector<std::uint32_t> first_above;  ///< the first neighbour of v above v
};

namespace {

/// OpenMesh reports a refused face on its global error stream; we handle refusals ourselves, so the stream
/// is muted while faces are added (one construction at a time: the flag is process-wide).
class MutedOpenMeshErrors {
 public:
  MutedOpenMeshErrors() : m_lock(mutex()), m_was_enabled(::omerr().is_enabled()) { ::omerr().disable(); }
  ~MutedOpenMeshErrors() {
    if (m_was_enabled) ::omerr().enable();
  }
  MutedOpenMeshErrors(const MutedOpenMeshErrors&) = delete;
  MutedOpenMeshErrors& operator=(const MutedOpenMeshErrors&) = delete;

 private:
  static std::mutex& mutex() {
    static std::mutex m;
    return m;
  }
  std::lock_guard<std::mutex> m_lock;
  bool m_was_enabled;
};

bool repeats_a_corner(const Triangle& t) { return t[0] == t[1] || t[1] == t[2] || t[0] == t[2]; }

}  // namespace

MeshConnectivity::MeshConnectivity(const MeshTopology& topology, const char* who)
    : m_half_edges(std::make_unique<HalfEdges>()) {
  validate_topology(topology, who);
  build_half_edges(topology);
  EdgeNumbering numbering;
  list_neighbours(numbering);
  number_edges(topology, numbering);
  classify_edges(numbering);
  list_fans();
  count_loops_and_components();
}

/// 1. The half-edge structure: every triangle, in order, on its own corners or else on copies of them (the
///    refused ones listed in m_split_faces); the copies of each input vertex.
void MeshConnectivity::build_half_edges(const MeshTopology& topology) {
  const Index n = topology.num_vertices;
  const std::size_t faces = topology.triangles.size();
  HalfEdges& he = *m_half_edges;
  OpenMesh::TriConnectivity& mesh = he.mesh;
  mesh.reserve(n, 3 * faces / 2 + 3, faces);
  he.original.resize(n);
  for (Index v = 0; v < n; ++v) {
    mesh.new_vertex();
    he.original[v] = v;
  }
  {
    const MutedOpenMeshErrors muted;
    for (Index f = 0; f < faces; ++f) {
      const Triangle& t = topology.triangles[f];
      OpenMesh::FaceHandle added;
      if (!repeats_a_corner(t))
        added = mesh.add_face(OpenMesh::VertexHandle(int(t[0])), OpenMesh::VertexHandle(int(t[1])),
                              OpenMesh::VertexHandle(int(t[2])));
      if (!added.is_valid()) {  // refused (add_face leaves the structure as it was): a piece of its own
        OpenMesh::VertexHandle corners[3];
        for (int i = 0; i < 3; ++i) {
          corners[i] = mesh.new_vertex();
          he.original.push_back(t[std::size_t(i)]);
        }
        added = mesh.add_face(corners[0], corners[1], corners[2]);
        m_split_faces.push_back(f);
      }
      PLEAT_ASSERT(added.is_valid() && Index(added.idx()) == f,
                   "a face of the half-edge structure per triangle");
    }
  }
  he.first_copy.assign(n + 1, 0);
  for (std::size_t c = n; c < he.original.size(); ++c) ++he.first_copy[he.original[c] + 1];
  for (Index v = 0; v < n; ++v) he.first_copy[v + 1] += he.first_copy[v];
  he.copies.resize(he.original.size() - n);
  std::vector<std::uint32_t> cursor(he.first_copy.begin(), he.first_copy.end() - 1);
  for (std::size_t c = n; c < he.original.size(); ++c) he.copies[cursor[he.original[c]]++] = Index(c);
}

/// 2. Neighbours: the far ends of the outgoing halfedges of v and its copies, as input vertices, without v
///    (numbering.self_edge: whether v was among them).
void MeshConnectivity::list_neighbours(EdgeNumbering& numbering) {
  const HalfEdges& he = *m_half_edges;
  const Index n = Index(he.first_copy.size() - 1);
  m_first_neighbour.assign(n + 1, 0);
  numbering.self_edge.assign(n, 0);
  std::vector<Index> around;
  for (int pass = 0; pass < 2; ++pass) {
    if (pass == 1) {
      for (Index v = 0; v < n; ++v) m_first_neighbour[v + 1] += m_first_neighbour[v];
      m_neighbours.resize(m_first_neighbour[n]);
    }
    for (Index v = 0; v < n; ++v) {
      around.clear();
      he.for_each_copy(v, [&](OpenMesh::VertexHandle r) {
        for (const OpenMesh::HalfedgeHandle h : he.mesh.voh_range(r))
          around.push_back(he.original[std::size_t(he.mesh.to_vertex_handle(h).idx())]);
      });
      std::sort(around.begin(), around.end());
      around.erase(std::unique(around.begin(), around.end()), around.end());
      const auto self = std::find(around.begin(), around.end(), v);
      numbering.self_edge[v] = self != around.end();
      if (self != around.end()) around.erase(self);
      if (pass == 0)
        m_first_neighbour[v + 1] = std::uint32_t(around.size());
      else
        std::copy(around.begin(), around.end(), m_neighbours.begin() + m_first_neighbour[v]);
    }
  }
}

namespace {
/// The id of edge (a, b) under `numbering`: vertex by vertex by the smaller endpoint, its self edge first.
template <class Numbering, class Neighbours>
Index edge_id(const Numbering& numbering, Neighbours&& neighbours, Index a, Index b) {
  if (b < a) std::swap(a, b);
  if (a == b) return numbering.first_edge[a];
  const auto nb = neighbours(a);
  const auto at = std::lower_bound(nb.begin() + numbering.first_above[a], nb.end(), b);
  PLEAT_ASSERT(at != nb.end() && *at == b, "an edge of the half-edge structure");
  return numbering.first_edge[a] + numbering.self_edge[a] +
         Index(at - (nb.begin() + numbering.first_above[a]));
}
}  // namespace

/// 2, continued. The edges numbered by (smaller, larger) endpoint: vertex by vertex, its self edge (a, a)
///    first if any; their endpoints, each vertex's incident edges and each face's edges.
void MeshConnectivity::number_edges(const MeshTopology& topology, EdgeNumbering& numbering) {
  const Index n = topology.num_vertices;
  numbering.first_edge.assign(n + 1, 0);
  numbering.first_above.assign(n, 0);
  for (Index v = 0; v < n; ++v) {
    const auto nb = neighbours(v);
    numbering.first_above[v] = std::uint32_t(std::upper_bound(nb.begin(), nb.end(), v) - nb.begin());
    numbering.first_edge[v + 1] = numbering.first_edge[v] + numbering.self_edge[v] +
                                  std::uint32_t(nb.size() - numbering.first_above[v]);
  }
  m_endpoints.resize(numbering.first_edge[n]);
  for (Index v = 0; v < n; ++v) {
    std::uint32_t e = numbering.first_edge[v];
    if (numbering.self_edge[v]) m_endpoints[e++] = {v, v};
    const auto nb = neighbours(v);
    for (std::size_t i = numbering.first_above[v]; i < nb.size(); ++i) m_endpoints[e++] = {v, nb[i]};
  }
  auto id = [&](Index a, Index b) {
    return edge_id(
        numbering, [&](Index v) { return neighbours(v); }, a, b);
  };
  m_incident_edges.resize(m_neighbours.size());
  for (Index v = 0; v < n; ++v)
    for (std::uint32_t i = m_first_neighbour[v]; i < m_first_neighbour[v + 1]; ++i)
      m_incident_edges[i] = id(v, m_neighbours[i]);
  const std::size_t faces = topology.triangles.size();
  m_of_face.resize(faces);
  for (Index f = 0; f < faces; ++f)
    for (int i = 0; i < 3; ++i)
      m_of_face[f][std::size_t(i)] =
          id(topology.triangles[f][std::size_t(i)], topology.triangles[f][std::size_t((i + 1) % 3)]);
}

/// 3. Face sides per edge: the halfedges that have a face, over all copies of the edge; each edge's kind.
void MeshConnectivity::classify_edges(const EdgeNumbering& numbering) {
  const HalfEdges& he = *m_half_edges;
  m_face_sides.assign(m_endpoints.size(), 0);
  std::vector<std::uint32_t> forward(m_endpoints.size(), 0);  // sides running from the smaller endpoint
  for (const OpenMesh::HalfedgeHandle h : he.mesh.halfedges()) {
    if (he.mesh.is_boundary(h)) continue;
    const Index a = he.original[std::size_t(he.mesh.from_vertex_handle(h).idx())];
    const Index b = he.original[std::size_t(he.mesh.to_vertex_handle(h).idx())];
    const Index e = edge_id(
        numbering, [&](Index v) { return neighbours(v); }, a, b);
    ++m_face_sides[e];
    forward[e] += a < b;
  }
  m_kind.resize(m_endpoints.size());
  for (std::size_t e = 0; e < m_endpoints.size(); ++e) {
    const std::uint32_t sides = m_face_sides[e];
    m_kind[e] = m_endpoints[e][0] == m_endpoints[e][1] ? EdgeKind::Degenerate
                : sides == 1                           ? EdgeKind::Boundary
                : sides == 2 ? (forward[e] == 1 ? EdgeKind::Interior : EdgeKind::Flipped)
                             : EdgeKind::NonManifold;
  }
}

/// 4. Fans: the faces around v and its copies; a closed fan where v has no copy and is not on the boundary
///    of the structure (OpenMesh counts an isolated vertex as a boundary one).
void MeshConnectivity::list_fans() {
  const HalfEdges& he = *m_half_edges;
  const Index n = Index(he.first_copy.size() - 1);
  m_first_face.assign(n + 1, 0);
  m_closed_fan.assign(n, 0);
  for (Index v = 0; v < n; ++v) {
    const OpenMesh::VertexHandle vh{int(v)};
    m_closed_fan[v] = he.first_copy[v] == he.first_copy[v + 1] && !he.mesh.is_boundary(vh);
    const std::size_t begin = m_faces_around.size();
    he.for_each_copy(v, [&](OpenMesh::VertexHandle r) {
      for (const OpenMesh::FaceHandle f : he.mesh.vf_ccw_range(r)) m_faces_around.push_back(Index(f.idx()));
    });
    if (he.first_copy[v] != he.first_copy[v + 1]) {  // a face with a repeated corner is around v twice
      std::sort(m_faces_around.begin() + std::ptrdiff_t(begin), m_faces_around.end());
      m_faces_around.erase(std::unique(m_faces_around.begin() + std::ptrdiff_t(begin), m_faces_around.end()),
                           m_faces_around.end());
    }
    m_first_face[v + 1] = std::uint32_t(m_faces_around.size());
  }
}

/// 5. Boundary loops and components: flood fills over the Boundary edges and over all edges.
void MeshConnectivity::count_loops_and_components() {
  const Index n = Index(m_first_neighbour.size() - 1);
  std::vector<char> seen(n, 0);
  std::vector<Index> stack;
  auto flood = [&](Index start, auto&& follows) {
    seen[start] = 1;
    stack.assign(1, start);
    while (!stack.empty()) {
      const Index v = stack.back();
      stack.pop_back();
      const auto nb = neighbours(v);
      const auto edges = incident_edges(v);
      for (std::size_t i = 0; i < nb.size(); ++i)
        if (!seen[nb[i]] && follows(edges[i])) {
          seen[nb[i]] = 1;
          stack.push_back(nb[i]);
        }
    }
  };
  for (Index v = 0; v < n; ++v)
    if (!seen[v] && !is_isolated(v)) {
      ++m_components;
      flood(v, [](Index) { return true; });
    }
  std::fill(seen.begin(), seen.end(), 0);
  const auto on_boundary = [&](Index e) { return m_kind[e] == EdgeKind::Boundary; };
  for (Index v = 0; v < n; ++v) {
    if (seen[v]) continue;
    const auto edges = incident_edges(v);
    if (std::any_of(edges.begin(), edges.end(), on_boundary)) {
      ++m_boundary_loops;
      flood(v, on_boundary);
    }
  }
}

MeshConnectivity::~MeshConnectivity() = default;
MeshConnectivity::MeshConnectivity(MeshConnectivity&&) noexcept = default;
MeshConnectivity& MeshConnectivity::operator=(MeshConnectivity&&) noexcept = default;

}  // namespace pleat
