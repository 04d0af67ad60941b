// The planar structure of one slice (Stewart 1999 §2.2; docs/method.md §4): the convex hull of the slice
// points and a constrained Delaunay triangulation of it with the chains as constraints (CGAL, exact
// predicates), visibility regions by flood fill up to chain edges, windows, and corners.
//
// A *region* is a maximal set of finite triangles connected across edges that are neither chain edges
// nor hull edges. A *window* is a hull edge of a region that is not a chain edge. A *corner* is one
// occurrence of a vertex on a region's boundary: the run of the vertex's incident triangles between two
// chain (or hull) edges. A vertex on a dangling chain has two corners in the same region; shortest-path
// trees are trees over corners. A region *has holes* when its dual graph is not a tree (an island chain, an
// isolated point, or a chain loop inside it).
// Internal header (CGAL types): used by static_core and kinetic only.
// Cost: O(n log n) expected for n slice vertices.
// Thread safety: a SliceTriangulation is used by one thread at a time.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "static_core/internal/cgal_types.hpp"
#include "static_core/mesh_slicer.hpp"

namespace pleat {

struct SliceWindow {
  cgal::FaceHandle face;  ///< the region's triangle on the window
  int index = 0;          ///< the window is the edge of `face` opposite this index
  int corner_a = -1;      ///< endpoint on the right, seen from inside (face->vertex(ccw(index)))
  int corner_b = -1;      ///< endpoint on the left (face->vertex(cw(index)))
};

/// One region: views into its triangulation's flat arrays (valid until the triangulation changes).
struct SliceRegion {
  std::span<const cgal::FaceHandle> faces;
  std::span<const SliceWindow> windows;
  bool has_holes = false;
};

class SliceTriangulation {
 public:
  /// Builds everything for `slice` (replacing any previous content).
  void build(const Slice& slice);

  const cgal::Cdt& cdt() const { return m_cdt; }
  int dimension() const { return m_cdt.dimension(); }
  cgal::VertexHandle vertex_of(Index slice_vertex) const { return m_vertex_of_slice_vertex[slice_vertex]; }
  std::size_t num_regions() const { return m_regions.empty() ? 0 : m_regions.size() - 1; }
  SliceRegion region(std::size_t r) const {
    const RegionStart& a = m_regions[r];
    const RegionStart& b = m_regions[r + 1];
    return {{m_region_faces.data() + a.face, m_region_faces.data() + b.face},
            {m_region_windows.data() + a.window, m_region_windows.data() + b.window},
            a.has_holes};
  }
  std::size_t num_corners() const { return m_corner_vertex.size(); }
  cgal::VertexHandle corner_vertex(int corner) const { return m_corner_vertex[corner]; }
  int corner_region(int corner) const { return m_corner_region[corner]; }
  /// The face counter-clockwise of the constrained edge x -> w (infinite for a chain edge on the hull), as
  /// the corner assignment found it; null when x -> w is not a constrained edge, or x is a crossing point or
  /// has more than two constrained edges (callers look those up in the triangulation).
  cgal::FaceHandle left_of_constrained_edge(cgal::VertexHandle x, cgal::VertexHandle w) const {
    const int s = x->info().slice_vertex;
    if (s < 0 || std::size_t(s) >= m_constrained_count.size()) return {};
    const std::uint8_t count = m_constrained_count[s];
    if (count > 2) return {};
    for (std::uint8_t j = 0; j < count; ++j)
      if (m_constrained_at[2 * s + j].w == w) return m_constrained_at[2 * s + j].left;
    return {};
  }
  /// Points inserted where chains cross (self-intersecting input); 0 for a valid surface.
  std::size_t crossings() const { return m_crossings; }

  /// The kinetic layer keeps only the constrained triangulation of a slice between frames, compactly
  /// (kinetic/kept_triangulation.hpp): everything else here is derived from it. To carry a slice it restores
  /// its triangulation here, maps the vertices, edits the triangulation in place (moves points, removes and
  /// inserts vertices and constraints), adopts the edits, grows the cones, and keeps the triangulation
  /// again. Every finite CDT vertex must name a distinct slice vertex of `slice` in its info, and every slice
  /// vertex must have one (no merged points, no crossing points).
  cgal::Cdt& cdt_for_editing() { return m_cdt; }
  /// Rebuilds the slice-vertex map from the CDT vertices' info.
  void map_vertices(const Slice& slice);
  /// map_vertices, then corners, regions and windows (they depend only on the triangulation's combinatorics
  /// and constraints).
  void adopt_edits(const Slice& slice);

  SliceTriangulation() = default;
  SliceTriangulation(const SliceTriangulation&) = delete;  // handles would point into the source
  SliceTriangulation& operator=(const SliceTriangulation&) = delete;

  /// Checks the invariants (every finite face has a region and corners; windows are unconstrained hull
  /// edges; corner ids are consistent across unconstrained edges). Returns false and explains in `why`.
  bool check_invariants(std::string* why) const;

 private:
  /// Forgets regions, windows, corners and crossings (not the triangulation or the vertex map).
  void clear_derived();
  void assign_corners();
  void flood_regions();
  void record_constrained_edge(cgal::VertexHandle x, cgal::VertexHandle w, cgal::FaceHandle left);

  /// Where region r's faces and windows start in the flat arrays; one more entry ends the last region.
  struct RegionStart {
    std::uint32_t face = 0, window = 0;
    bool has_holes = false;
  };

  cgal::Cdt m_cdt;
  cgal::Delaunay m_delaunay;  ///< build's point insertion (then swapped into m_cdt); empty between builds
  // Scratch of build and flood_regions, kept so that a slice allocates nothing once warmed up.
  std::vector<std::ptrdiff_t> m_order;
  std::vector<cgal::Point2> m_points;
  std::vector<cgal::FaceHandle> m_stack;
  std::vector<cgal::VertexHandle> m_vertex_of_slice_vertex;
  // Flat, region by region (a kinetic slice keeps these between frames: no heap object per region).
  std::vector<RegionStart> m_regions;
  std::vector<cgal::FaceHandle> m_region_faces;
  std::vector<SliceWindow> m_region_windows;
  std::vector<cgal::VertexHandle> m_corner_vertex;
  std::vector<int> m_corner_region;
  /// Per CDT vertex, by the slice vertex in its info: up to two constrained edges x -> w and the face
  /// counter-clockwise of each (left_of_constrained_edge); a count above 2 means "more: not recorded".
  struct ConstrainedEdgeAt {
    cgal::VertexHandle w;
    cgal::FaceHandle left;
  };
  std::vector<ConstrainedEdgeAt> m_constrained_at;
  std::vector<std::uint8_t> m_constrained_count;
  std::size_t m_crossings = 0;
};

/// True when the edge (f, i) separates corners and regions: a chain edge, or an edge to outside the hull.
inline bool is_separator(const cgal::Cdt& cdt, cgal::FaceHandle f, int i) {
  return f->is_constrained(i) || cdt.is_infinite(f) || cdt.is_infinite(f->neighbor(i));
}

}  // namespace pleat
