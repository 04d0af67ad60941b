// The counts `pleat info` reports about a cloth sequence: vertices (input and welded), faces, frames, frame
// rate, duration, bounding box over all frames, boundary loops, non-manifold edges, degenerate faces and
// welded duplicates.
//
// Topology counts come from the welded mesh's MeshConnectivity (OpenMesh's half-edge structure; the faces
// it cannot link count as they are, see static_core/mesh_connectivity.hpp), O(F log F). Degenerate
// (zero-area) faces are decided exactly (CGAL's collinear predicate on the three corners, no epsilon), per
// frame, O(F) each. report_mesh streams every frame once.
#pragma once

#include <cstddef>
#include <functional>
#include <glm/vec3.hpp>
#include <vector>

#include "sim_io/mesh_sequence.hpp"
#include "static_core/mesh.hpp"

namespace pleat {

struct TopologyCounts {
  std::size_t edges = 0;           ///< undirected edges
  std::size_t boundary_edges = 0;  ///< edges of exactly one face
  std::size_t boundary_loops =
      0;  ///< connected components of the boundary edges (loops touching at a vertex count once)
  std::size_t non_manifold_edges = 0;  ///< edges of three or more faces
  std::size_t inconsistent_edges =
      0;  ///< edges of two faces that traverse it in the same direction (flipped winding)
  std::size_t isolated_vertices = 0;  ///< vertices of no face
  std::size_t components = 0;         ///< connected components of faces (sharing a vertex connects)
};

TopologyCounts count_topology(const MeshTopology& topology);

/// Faces whose three corners are collinear (or coincide) in `frame`, exactly.
std::size_t count_degenerate_faces(const MeshTopology& topology, const Frame& frame);

/// The vertices no triangle uses, in increasing order: they have no surface, so no visibility (the CSV
/// leaves their fields empty, the Python module gives NaN; docs/method.md §12). O(V + F).
std::vector<Index> isolated_vertices(const MeshTopology& topology);

struct MeshReport {
  Index input_vertices = 0;
  Index welded_vertices = 0;
  std::size_t welded_duplicates = 0;  ///< input vertices merged into another
  std::size_t input_faces = 0;        ///< input triangles (polygons fan-triangulated)
  std::size_t faces = 0;              ///< triangles of the welded mesh
  std::size_t removed_faces = 0;      ///< collapsed or repeated after welding (MeshSequence::removed_faces)
  std::size_t frames = 0;
  double frame_rate = 0.0;                  ///< frames per second (0 for one frame)
  double start_time = 0.0;                  ///< seconds
  double duration = 0.0;                    ///< seconds
  glm::dvec3 bbox_min{0.0}, bbox_max{0.0};  ///< over all frames
  TopologyCounts topology;
  std::size_t degenerate_faces_first_frame = 0;
  std::size_t degenerate_faces_max = 0;  ///< over frames
  std::size_t frames_with_degenerate_faces = 0;
  /// Far-flung vertices: farther from the frame's median point than kFarFlung times the median distance of
  /// the mesh's vertices from it (an exploded simulation, a stray triangle), which stretch a frame's planes
  /// (slicing_plan.hpp).
  std::size_t frames_with_far_flung = 0;
  std::size_t far_flung_max = 0;                                     ///< over frames
  std::size_t far_flung_first_frame = 0, far_flung_first_count = 0;  ///< the first frame with any
  Index far_flung_vertex = 0;                                        ///< there, the farthest
  double far_flung_ratio = 0.0;  ///< its distance over the median distance
};

inline constexpr double kFarFlung = 20.0;

/// The far-flung vertices of `frame` among those some triangle uses (MeshReport): their count, the farthest
/// in `worst` and its distance over the median distance in `ratio`. O(V).
std::size_t count_far_flung(const MeshTopology& topology, const Frame& frame, Index& worst, double& ratio);

/// Reads every frame once; `per_frame(i, frame)` (optional) sees each frame as it passes, e.g. for a
/// self-intersection check, so the sequence is streamed a single time.
MeshReport report_mesh(const MeshSequence& sequence,
                       const std::function<void(std::size_t, const Frame&)>& per_frame = {});

}  // namespace pleat
