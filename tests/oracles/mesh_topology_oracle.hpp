// Brute-force topology of a triangle list, the oracle of static_core/mesh_connectivity.hpp: the sorted-key
// edge extraction the engines used before the half-edge structure (MeshEdges), the union-find counts `pleat
// info` used (count_topology), and a vertex's fan read off its link. O(F log F); no OpenMesh.
#pragma once

#include <array>
#include <vector>

#include "sim_io/mesh_report.hpp"
#include "static_core/mesh.hpp"

namespace pleat::test {

struct OracleEdges {
  std::vector<std::array<Index, 2>> endpoints;   ///< (a, b) with a <= b, sorted
  std::vector<std::array<Index, 3>> of_face;     ///< of_face[f][i] = edge (t[i], t[(i+1)%3])
  std::vector<std::vector<Index>> neighbours;    ///< sorted, without the vertex itself
  std::vector<unsigned> face_sides;              ///< per edge: the (face, corner) slots on it
  std::vector<std::vector<Index>> faces_around;  ///< per vertex: the faces having it as a corner, sorted
};
OracleEdges oracle_edges(const MeshTopology& topology);

/// The counts by sorted directed edge uses and union-find, as count_topology computed them before.
TopologyCounts oracle_count_topology(const MeshTopology& topology);

/// Whether v's faces close around it into one consistently wound fan: v is a corner of each once, and the
/// link edges (a, b) of its faces (v, a, b) form one directed cycle through distinct link vertices.
bool oracle_closed_fan(const MeshTopology& topology, Index v);

}  // namespace pleat::test
