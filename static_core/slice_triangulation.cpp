#include "static_core/internal/slice_triangulation.hpp"

#include <CGAL/spatial_sort.h>

#include <numeric>
#include <string>

#include "static_core/assert.hpp"

namespace pleat {

void SliceTriangulation::build(const Slice& slice) {
  m_cdt.clear();
  clear_derived();
  const std::size_t n = slice.vertices.size();
  m_vertex_of_slice_vertex.assign(n, cgal::VertexHandle());

  // Insert points in spatial order with a hint; coincident points (slice vertices of edges that meet at a
  // mesh vertex lying on the plane) become one CDT vertex. They go into an unconstrained Delaunay
  // triangulation, taken over by the CDT afterwards: CGAL's CDT insertion of a point also checks for and
  // splits constrained edges and flips with constraint tests, which a slice's points do not need before
  // its chains are added (a Delaunay triangulation of the points as before, the real sequences' output
  // unchanged; docs/benchmarks.md has the cost).
  std::vector<std::ptrdiff_t>& order = m_order;
  order.resize(n);
  std::iota(order.begin(), order.end(), 0);
  std::vector<cgal::Point2>& points = m_points;
  points.resize(n);
  for (std::size_t i = 0; i < n; ++i) points[i] = cgal::to_point(slice.vertices[i].point);
  using Traits = CGAL::Spatial_sort_traits_adapter_2<cgal::Kernel, cgal::Point2*>;
  // Hilbert leaves of up to 16 points rather than CGAL's 4: a leaf's points lie close together in any order,
  // and the sort makes fewer median splits (output unchanged).
  CGAL::spatial_sort(order.begin(), order.end(), Traits(points.data()), std::ptrdiff_t(16));
  m_delaunay.clear();
  cgal::FaceHandle hint;
  for (std::ptrdiff_t i : order) {
    cgal::VertexHandle v = m_delaunay.insert(points[i], hint);
    if (v->info().slice_vertex < 0) v->info().slice_vertex = static_cast<int>(i);
    m_vertex_of_slice_vertex[i] = v;
    hint = v->face();
  }
  m_cdt.cgal::Cdt::Triangulation::swap(m_delaunay);  // handles stay valid
  const std::size_t vertices_before = m_cdt.number_of_vertices();
  for (const SliceEdge& e : slice.edges) {
    const cgal::VertexHandle a = m_vertex_of_slice_vertex[e.from], b = m_vertex_of_slice_vertex[e.to];
    if (a != b) cgal::insert_constraint(m_cdt, a, b);
  }
  m_crossings = m_cdt.number_of_vertices() - vertices_before;
  if (m_cdt.dimension() < 2) return;
  assign_corners();
  flood_regions();
}

void SliceTriangulation::map_vertices(const Slice& slice) {
  m_vertex_of_slice_vertex.assign(slice.vertices.size(), cgal::VertexHandle());
  for (auto v = m_cdt.finite_vertices_begin(); v != m_cdt.finite_vertices_end(); ++v) {
    const int x = v->info().slice_vertex;
    PLEAT_ASSERT(x >= 0 && std::size_t(x) < slice.vertices.size(), "a CDT vertex without a slice vertex");
    PLEAT_ASSERT(m_vertex_of_slice_vertex[x] == cgal::VertexHandle(),
                 "two CDT vertices for one slice vertex");
    m_vertex_of_slice_vertex[x] = v;
  }
  PLEAT_ASSERT(m_cdt.number_of_vertices() == slice.vertices.size(), "a slice vertex without a CDT vertex");
}

void SliceTriangulation::adopt_edits(const Slice& slice) {
  map_vertices(slice);
  clear_derived();
  if (m_cdt.dimension() < 2) return;
  assign_corners();
  flood_regions();
}

void SliceTriangulation::clear_derived() {
  m_regions.clear();
  m_region_faces.clear();
  m_region_windows.clear();
  m_corner_vertex.clear();
  m_corner_region.clear();
  m_constrained_count.clear();
  m_crossings = 0;
}

void SliceTriangulation::assign_corners() {
  // A corner is a maximal run of finite faces around a vertex between separators. From each (face, vertex)
  // not yet in a corner, the run is numbered from that face counter-clockwise up to a separator, then
  // clockwise up to one: each face of the run is visited once. The constrained edges met on the way are
  // recorded with their counter-clockwise faces: at a run's clockwise end, and at its counter-clockwise end
  // where the face beyond is infinite (no run starts there).
  m_constrained_count.assign(m_vertex_of_slice_vertex.size(), 0);
  m_constrained_at.resize(2 * m_vertex_of_slice_vertex.size());
  for (auto f = m_cdt.finite_faces_begin(); f != m_cdt.finite_faces_end(); ++f)
    f->info().corner = {-1, -1, -1};
  for (auto f = m_cdt.finite_faces_begin(); f != m_cdt.finite_faces_end(); ++f)
    for (int i = 0; i < 3; ++i) {
      if (f->info().corner[i] >= 0) continue;
      const cgal::VertexHandle v = f->vertex(i);
      const int corner = static_cast<int>(m_corner_vertex.size());
      m_corner_vertex.push_back(v);
      const cgal::FaceHandle start = f;
      start->info().corner[i] = corner;
      // Counter-clockwise: the edge to the next face is (g, ccw(index of v)).
      bool closed = false;
      cgal::FaceHandle g = start;
      int k = i;
      while (true) {
        if (is_separator(m_cdt, g, m_cdt.ccw(k))) {
          const cgal::FaceHandle beyond = g->neighbor(m_cdt.ccw(k));
          if (g->is_constrained(m_cdt.ccw(k)) && m_cdt.is_infinite(beyond))
            record_constrained_edge(v, g->vertex(m_cdt.cw(k)), beyond);
          break;
        }
        g = g->neighbor(m_cdt.ccw(k));
        if (g == start) {  // no separator around v: one corner of every face
          closed = true;
          break;
        }
        k = g->index(v);
        g->info().corner[k] = corner;
      }
      if (closed) continue;
      // Clockwise from the start: the edge to the next face is (g, cw(index of v)).
      g = start;
      k = i;
      while (true) {
        if (is_separator(m_cdt, g, m_cdt.cw(k))) {
          if (g->is_constrained(m_cdt.cw(k))) record_constrained_edge(v, g->vertex(m_cdt.ccw(k)), g);
          break;
        }
        g = g->neighbor(m_cdt.cw(k));
        k = g->index(v);
        g->info().corner[k] = corner;
      }
    }
  m_corner_region.assign(m_corner_vertex.size(), -1);
}

void SliceTriangulation::record_constrained_edge(cgal::VertexHandle x, cgal::VertexHandle w,
                                                 cgal::FaceHandle left) {
  const int s = x->info().slice_vertex;
  if (s < 0) return;
  std::uint8_t& count = m_constrained_count[s];
  if (count < 2) m_constrained_at[2 * s + count] = {w, left};
  if (count <= 2) ++count;
}

void SliceTriangulation::flood_regions() {
  // Depth-first from each face not yet in a region; a face is marked by its TDS scratch flag (tds_data, free
  // in a constrained triangulation) while the flood runs. One region's faces and windows are found together,
  // so they are laid out region by region as they come.
  std::vector<cgal::FaceHandle>& stack = m_stack;
  stack.clear();
  // On an exception (allocation), no face stays marked: a kept triangulation is flooded again later.
  struct Unmark {
    cgal::Cdt& cdt;
    bool done = false;
    ~Unmark() {
      if (!done)
        for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->tds_data().clear();
    }
  } unmark{m_cdt};
  for (auto seed = m_cdt.finite_faces_begin(); seed != m_cdt.finite_faces_end(); ++seed) {
    if (seed->tds_data().processed()) continue;
    const int id = static_cast<int>(m_regions.size());
    const std::size_t first_face = m_region_faces.size();
    m_regions.push_back(
        {static_cast<std::uint32_t>(first_face), static_cast<std::uint32_t>(m_region_windows.size()), false});
    std::size_t interior_edges = 0;  // counted from both sides
    seed->tds_data().mark_processed();
    stack.push_back(seed);
    while (!stack.empty()) {
      const cgal::FaceHandle f = stack.back();
      stack.pop_back();
      m_region_faces.push_back(f);
      for (int i = 0; i < 3; ++i) {
        m_corner_region[f->info().corner[i]] = id;
        const cgal::FaceHandle g = f->neighbor(i);
        if (m_cdt.is_infinite(g)) {
          if (!f->is_constrained(i))
            m_region_windows.push_back({f, i, f->info().corner[m_cdt.ccw(i)], f->info().corner[m_cdt.cw(i)]});
          continue;
        }
        if (f->is_constrained(i)) continue;
        ++interior_edges;
        if (!g->tds_data().processed()) {
          g->tds_data().mark_processed();
          stack.push_back(g);
        }
      }
    }
    // A connected set of F triangles is simply connected iff its dual graph is a tree: F - 1 edges.
    m_regions.back().has_holes = interior_edges / 2 != m_region_faces.size() - first_face - 1;
  }
  m_regions.push_back({static_cast<std::uint32_t>(m_region_faces.size()),
                       static_cast<std::uint32_t>(m_region_windows.size()), false});
  for (const cgal::FaceHandle f : m_region_faces) f->tds_data().clear();
  unmark.done = true;
}

bool SliceTriangulation::check_invariants(std::string* why) const {
  auto fail = [&](const std::string& message) {
    if (why) *why = message;
    return false;
  };
  if (m_cdt.dimension() < 2) return true;
  // The triangulation and constraint checks of CGAL, without the Delaunay property: the kinetic layer keeps
  // a valid constrained triangulation that is not Delaunay in general.
  if (!m_cdt.cgal::Cdt::Ctr::is_valid()) return fail("CGAL's constrained triangulation check fails");
  for (auto f = m_cdt.finite_faces_begin(); f != m_cdt.finite_faces_end(); ++f) {
    if (!f->tds_data().is_clear()) return fail("a face left marked by the region flood");
    for (int i = 0; i < 3; ++i) {
      if (f->info().corner[i] < 0) return fail("a finite face has no corner");
      if (m_corner_vertex[f->info().corner[i]] != f->vertex(i)) return fail("corner of the wrong vertex");
      const cgal::FaceHandle g = f->neighbor(i);
      if (m_cdt.is_infinite(g) || f->is_constrained(i)) continue;
      // Across an unconstrained edge, both endpoints keep their corners (so both faces share a region).
      for (int k : {m_cdt.ccw(i), m_cdt.cw(i)})
        if (g->info().corner[g->index(f->vertex(k))] != f->info().corner[k])
          return fail("corner changes across an unconstrained edge");
    }
  }
  // Every recorded constrained edge x -> w is one, with its recorded face counter-clockwise of it; and every
  // constrained edge at a vertex with at most two is recorded.
  for (auto v = m_cdt.finite_vertices_begin(); v != m_cdt.finite_vertices_end(); ++v) {
    std::size_t constrained = 0;
    auto e = m_cdt.incident_edges(v), done = e;
    do {
      if (!m_cdt.is_constrained(*e)) continue;
      ++constrained;
      // f is left of its edge (ccw(i) -> cw(i)); the face left of v -> w is f or its neighbour.
      const cgal::FaceHandle f = e->first;
      const int i = e->second;
      const bool v_first = f->vertex(m_cdt.ccw(i)) == cgal::VertexHandle(v);
      const cgal::VertexHandle w = v_first ? f->vertex(m_cdt.cw(i)) : f->vertex(m_cdt.ccw(i));
      const cgal::FaceHandle left = v_first ? f : f->neighbor(i);
      const cgal::FaceHandle recorded = left_of_constrained_edge(v, w);
      if (recorded != cgal::FaceHandle() && recorded != left)
        return fail("a constrained edge recorded with the wrong face");
      if (recorded == cgal::FaceHandle() && v->info().slice_vertex >= 0 &&
          m_constrained_count[v->info().slice_vertex] <= 2)
        return fail("a constrained edge not recorded");
    } while (++e != done);
    if (v->info().slice_vertex >= 0 &&
        std::min<std::size_t>(constrained, 3) != m_constrained_count[v->info().slice_vertex])
      return fail("constrained edges at a vertex miscounted");
  }
  // Every finite face in exactly one region, the one of its corners; every window on a face of its region.
  std::size_t listed = 0;
  for (std::size_t r = 0; r < num_regions(); ++r) {
    const SliceRegion region_r = region(r);
    listed += region_r.faces.size();
    for (const cgal::FaceHandle f : region_r.faces)
      for (int k = 0; k < 3; ++k)
        if (m_corner_region[f->info().corner[k]] != static_cast<int>(r))
          return fail("a face listed in a region its corners are not in");
    for (const SliceWindow& w : region_r.windows) {
      if (m_corner_region[w.face->info().corner[0]] != static_cast<int>(r))
        return fail("a window listed in another region than its face");
      if (w.face->is_constrained(w.index) || !m_cdt.is_infinite(w.face->neighbor(w.index)))
        return fail("a window is not an unconstrained hull edge");
    }
  }
  if (listed != m_cdt.number_of_faces()) return fail("finite faces and region faces differ in number");
  return true;
}

}  // namespace pleat
