// The connectivity of a cloth, built once per sequence: OpenMesh's half-edge structure over its triangles,
// and the flat index arrays the hot loops read (edges, each face's edges, each vertex's neighbours and
// faces).
//
// Positions stay in Frame's flat arrays; the half-edge structure holds no geometry
// (OpenMesh::TriConnectivity, kept behind a pointer so that no OpenMesh header reaches the engines). Every
// topological fact comes from it: the edges are its edges, a vertex's neighbours and faces its circulators',
// the number of faces on an edge its halfedges' faces, boundary vertices and edges its is_boundary, and the
// loops and components are walks over those. Cost: O(F log d) for F triangles and largest vertex degree d,
// once per sequence (a small fraction of one frame: docs/benchmarks.md, "Speed of the static core"). The
// queries below are O(1) or spans into flat arrays.
//
// Non-manifold input. The engines take any triangle list whose indices are in range (degenerate faces, a
// third face on an edge, bow-ties, flipped winding, repeated or isolated vertices): they only need edges and
// faces. A half-edge structure cannot link every such face, so the faces are added in triangle order and a
// face that OpenMesh's add_face refuses — it would put a third face on an edge or a second face on an edge
// in the same direction (flipped winding), or close a vertex's fan while the vertex has another fan (a
// "complex" edge or vertex) — or that repeats a corner (which add_face cannot represent) is linked in on
// copies of its three corners, as a separate piece. So every triangle f is face f of the structure, nothing
// is dropped, and each copy maps back to its vertex: edges, neighbours and face counts are over the input's
// vertices, as if every face were linked (an edge is counted once however many copies carry it). What the
// copies change is only what depends on how faces join around a vertex: a vertex touched by a split face
// has no closed fan (has_closed_fan() is false, so the kinetic layer counts its plane crossings as
// critical), as a vertex on the boundary. split_faces() lists them. A manifold mesh has none, and then the
// structure is the mesh.
//
// Edge numbering: edges are sorted by (smaller endpoint, larger endpoint), as the slicer's scratch arrays
// and the kinetic layer's keys expect them to be stable for a sequence. A face with a repeated corner (a, a,
// b) has the edge (a, a); it is never cut by a plane and is no one's neighbour.
// Thread safety: built by one thread; the const queries may then run on any number at once.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "static_core/mesh.hpp"

namespace pleat {

/// How the faces of the input meet at an edge (counted over face sides: a face (a, b, a) has two on (a, b)).
enum class EdgeKind : std::uint8_t {
  Boundary,     ///< one face side
  Interior,     ///< two face sides in opposite directions
  Flipped,      ///< two face sides in the same direction: the faces' windings disagree
  NonManifold,  ///< three or more face sides
  Degenerate,   ///< (a, a): an edge of a face with a repeated corner
};

class MeshConnectivity {
 public:
  /// Validates the indices first (validate_topology: InputError naming `who` and the triangle).
  explicit MeshConnectivity(const MeshTopology& topology, const char* who = "MeshConnectivity");
  ~MeshConnectivity();
  MeshConnectivity(MeshConnectivity&&) noexcept;
  MeshConnectivity& operator=(MeshConnectivity&&) noexcept;

  Index num_vertices() const { return static_cast<Index>(m_first_neighbour.size() - 1); }
  std::size_t num_edges() const { return m_endpoints.size(); }

  // Flat arrays for the hot loops.
  /// (a, b) with a <= b, sorted.
  const std::vector<std::array<Index, 2>>& endpoints() const { return m_endpoints; }
  /// of_face()[f][i] = the edge (t[i], t[(i+1)%3]) of triangle t = topology.triangles[f].
  const std::vector<std::array<Index, 3>>& of_face() const { return m_of_face; }
  /// The vertices sharing an edge with v, sorted, without v.
  std::span<const Index> neighbours(Index v) const {
    return {m_neighbours.data() + m_first_neighbour[v], m_neighbours.data() + m_first_neighbour[v + 1]};
  }
  /// The edges (v, neighbours(v)[i]), aligned with neighbours(v).
  std::span<const Index> incident_edges(Index v) const {
    return {m_incident_edges.data() + m_first_neighbour[v],
            m_incident_edges.data() + m_first_neighbour[v + 1]};
  }
  /// The faces having v as a corner, each once: counter-clockwise around v where v has a closed fan; in
  /// general fan by fan, in OpenMesh's circulation order.
  std::span<const Index> faces_around(Index v) const {
    return {m_faces_around.data() + m_first_face[v], m_faces_around.data() + m_first_face[v + 1]};
  }

  // Half-edge topology.
  EdgeKind kind(Index edge) const { return m_kind[edge]; }
  /// Face sides on the edge (1 on the boundary, 2 inside, 3 or more at a non-manifold edge).
  std::uint32_t face_sides(Index edge) const { return m_face_sides[edge]; }
  /// v's faces form one fan closed around v, every face linked: v is an interior vertex of a manifold piece.
  /// False on the boundary, at isolated vertices, bow-ties and every corner of a split face.
  bool has_closed_fan(Index v) const { return m_closed_fan[v] != 0; }
  /// v is a corner of no face.
  bool is_isolated(Index v) const { return m_first_face[v] == m_first_face[v + 1]; }
  /// Triangles linked in on copies of their corners (see the header comment), increasing.
  const std::vector<Index>& split_faces() const { return m_split_faces; }
  /// Connected components of the Boundary edges; loops that touch at a vertex are one.
  std::size_t boundary_loops() const { return m_boundary_loops; }
  /// Connected components of faces, two faces being connected when they share a vertex.
  std::size_t components() const { return m_components; }

 private:
  struct HalfEdges;      // the OpenMesh structure (mesh_connectivity.cpp)
  struct EdgeNumbering;  // the edges' ids while the constructor runs (mesh_connectivity.cpp)
  /// The constructor's steps, in order (see its comments in mesh_connectivity.cpp).
  void build_half_edges(const MeshTopology& topology);
  void list_neighbours(EdgeNumbering& numbering);
  void number_edges(const MeshTopology& topology, EdgeNumbering& numbering);
  void classify_edges(const EdgeNumbering& numbering);
  void list_fans();
  void count_loops_and_components();
  std::unique_ptr<HalfEdges> m_half_edges;
  std::vector<std::array<Index, 2>> m_endpoints;
  std::vector<std::array<Index, 3>> m_of_face;
  std::vector<std::uint32_t> m_first_neighbour;  // CSR over vertices: neighbours and incident edges
  std::vector<Index> m_neighbours;
  std::vector<Index> m_incident_edges;
  std::vector<std::uint32_t> m_first_face;  // CSR over vertices: faces around
  std::vector<Index> m_faces_around;
  std::vector<EdgeKind> m_kind;
  std::vector<std::uint32_t> m_face_sides;
  std::vector<char> m_closed_fan;
  std::vector<Index> m_split_faces;
  std::size_t m_boundary_loops = 0;
  std::size_t m_components = 0;
};

}  // namespace pleat
