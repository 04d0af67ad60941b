// A slice's constrained triangulation as a kinetic slice keeps it between frames: its combinatorics only, in
// flat arrays of indices, not pointers; no per-node heap objects (docs/method.md §11.5).
//
// Each frame a kinetic slice restores its kept triangulation into the thread's CGAL triangulation, carries
// it to the next frame there (certificates, edits, CGAL's removals and insertions), grows the cones on it,
// and keeps the result again. The flat form takes about a third of the memory of a CGAL triangulation kept
// per slice; restoring and keeping cost what working in the thread's warm triangulation saves
// (bench/results/kinetic_micro.md, docs/benchmarks.md). Restoring creates the faces and vertices with CGAL's
// own data-structure operations, as CGAL's file input does: no geometric predicate, no point location.
// Internal header (CGAL types): kinetic only.
#pragma once

#include <cstdint>
#include <vector>

#include "static_core/internal/cgal_types.hpp"
#include "static_core/mesh_slicer.hpp"

namespace pleat::kinetic {

struct KeptTriangulation {
  /// Per face, its three vertices as slice vertices (-1: the infinite vertex), in CGAL's order.
  std::vector<std::int32_t> vertices;
  /// Per face, its three neighbours (face indices); neighbour i is across the edge opposite vertex i.
  std::vector<std::int32_t> neighbors;
  /// Per face, bit i set when the edge opposite vertex i is constrained.
  std::vector<std::uint8_t> constrained;

  std::size_t num_faces() const { return constrained.size(); }
  bool empty() const { return constrained.empty(); }
  /// Forgets the triangulation and frees its memory (a slice that keeps none).
  void release();
};

/// Stores the 2D triangulation `cdt`, every finite vertex of which names a distinct slice vertex in its info,
/// into `out` (uses the faces' FaceInfo::index as scratch).
void keep_triangulation(cgal::Cdt& cdt, KeptTriangulation& out);

/// Memory of restore_triangulation (per thread: no allocation per call once warmed up).
struct RestoreScratch {
  std::vector<cgal::FaceHandle> faces;
  std::vector<cgal::VertexHandle> vertices;
};

/// Replaces `cdt` by the kept triangulation, its vertices at the points of `slice` (the slice it was kept
/// for: one vertex per slice vertex, info = the slice vertex).
void restore_triangulation(const KeptTriangulation& kept, const Slice& slice, cgal::Cdt& cdt,
                           RestoreScratch& scratch);

}  // namespace pleat::kinetic
