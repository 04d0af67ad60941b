// The one place that owns the CGAL typedefs of static_core (and kinetic). Internal: CGAL types never appear
// in a public API (visibility.hpp, slicing_plan.hpp, visibility_cone.hpp).
//
// Kernel: Exact_predicates_inexact_constructions (filtered exact predicates on double coordinates). Every
// orientation decision on slice points is exact; constructions (the slice points themselves, crossing
// points of chains) are rounded doubles.
#pragma once

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Constrained_triangulation_face_base_2.h>
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_data_structure_2.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <array>
#include <cstdint>
#include <glm/vec2.hpp>
#include <type_traits>

#include "static_core/internal/filtered_predicates.hpp"

namespace pleat::cgal {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point2 = Kernel::Point_2;
/// The triangulations' geometric traits: EPICK with a cheaper filter in front of its orientation and
/// in-circle predicates (filtered_predicates.hpp; the same exact answers).
using TriangulationTraits = FilteredKernel;

/// Per CDT vertex: the slice vertex it was inserted for (-1: a crossing point of two chains).
struct VertexInfo {
  int slice_vertex = -1;
};

/// Per CDT face: the corner id of each of its vertices (its region is its corners'). With GCC a face takes 72
/// bytes: CGAL's links (48), its scratch flag and three constraint flags, and this info in the base's tail
/// padding. A slice has about two faces per slice vertex.
struct FaceInfo {
  std::array<int, 3> corner{-1, -1, -1};
  /// Scratch of the kinetic layer: the face's place in its compact copy (kept_triangulation), or which
  /// planned edge flip reserves it while a slice is certified (kinetic_slice.hpp's PlannedFlip).
  int index = -1;
};

using Vb = CGAL::Triangulation_vertex_base_with_info_2<VertexInfo, TriangulationTraits>;
using Fbb = CGAL::Triangulation_face_base_with_info_2<FaceInfo, TriangulationTraits>;
using Fb = CGAL::Constrained_triangulation_face_base_2<TriangulationTraits, Fbb>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
/// Crossing constraints (chains of a self-intersecting surface) are split at computed crossing points.
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<TriangulationTraits, Tds, CGAL::Exact_predicates_tag>;
static_assert(sizeof(Cdt::Face) <= 72, "a triangulation face grew");
/// The unconstrained Delaunay triangulation on the same data structure and base class: its point insertion
/// does no constraint bookkeeping, and Cdt::Triangulation::swap takes its result over in constant time.
using Delaunay = CGAL::Delaunay_triangulation_2<TriangulationTraits, Tds>;
static_assert(std::is_same_v<Delaunay::Triangulation, Cdt::Triangulation>);
using VertexHandle = Cdt::Vertex_handle;
using FaceHandle = Cdt::Face_handle;

inline Point2 to_point(const glm::dvec2& p) { return {p.x, p.y}; }
inline glm::dvec2 to_glm(const Point2& p) { return {p.x(), p.y()}; }

/// What insert_constraint did.
enum class ConstraintInsertion {
  existing,  ///< a -> b was a constrained edge already: nothing changed
  marked,    ///< a -> b was an unconstrained edge, now marked: no other edge or vertex changed
  inserted   ///< CGAL inserted it: it may have split other constraints, at new vertices or existing ones
};

/// Makes a -> b a constrained edge, as Cdt::insert_constraint(a, b) does. Where a -> b is an edge of a 2D
/// triangulation (nearly every chain edge: consecutive slice points are Delaunay neighbours), it is marked
/// here directly, which is all CGAL does there too; CGAL's call first builds a std::stack (a std::deque: two
/// heap allocations) per constraint, which was most of the triangulation's allocations (2.2 per slice
/// vertex). Otherwise CGAL inserts it (split at vertices on it and where it crosses other constraints).
inline ConstraintInsertion insert_constraint(Cdt& cdt, VertexHandle a, VertexHandle b) {
  FaceHandle f;
  int i = 0;
  if (cdt.dimension() == 2 && cdt.is_edge(a, b, f, i)) {
    if (f->is_constrained(i)) return ConstraintInsertion::existing;
    f->set_constraint(i, true);
    f->neighbor(i)->set_constraint(cdt.mirror_index(f, i), true);
    return ConstraintInsertion::marked;
  }
  cdt.insert_constraint(a, b);
  return ConstraintInsertion::inserted;
}

}  // namespace pleat::cgal
