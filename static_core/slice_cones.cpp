#include "static_core/internal/slice_cones.hpp"

#include <CGAL/number_utils.h>

#include <algorithm>
#include <glm/geometric.hpp>

#include "static_core/assert.hpp"

namespace pleat {
namespace {

using cgal::Cdt;
using cgal::FaceHandle;
using cgal::Point2;
using cgal::VertexHandle;

glm::dvec2 direction(const Point2& from, const Point2& to) { return {to.x() - from.x(), to.y() - from.y()}; }

/// The counter-clockwise wedge at x from the direction of p to the direction of q, its kind (thin, half or
/// reflex, or a full turn when p and q lie in the same direction) decided by exact predicates.
Wedge exact_wedge(const Point2& x, const Point2& p, const Point2& q) {
  const glm::dvec2 dp = direction(x, p), dq = direction(x, q);
  switch (cgal::orientation(x, p, q)) {
    case CGAL::LEFT_TURN:
      return thin_wedge_between(dp, dq);
    case CGAL::RIGHT_TURN:
      return wedge_between(dp, dq);
    default:
      if (CGAL::angle(p, x, q) == CGAL::ACUTE) return {direction_angle(dp), kTwoPi};
      return {direction_angle(dp), kTwoPi / 2, float(glm::length(dp)), float(glm::length(dq))};
  }
}

/// The next slice vertex along the chain (forward or backward) that is at another CDT vertex, or -1.
int next_distinct(const Slice& slice, const SliceTriangulation& st, Index x, bool forward) {
  const VertexHandle at = st.vertex_of(x);
  Index y = x;
  for (std::size_t steps = 0; steps <= slice.vertices.size(); ++steps) {
    const std::int32_t e = forward ? slice.out_edge[y] : slice.in_edge[y];
    if (e < 0) return -1;
    y = forward ? slice.edges[e].to : slice.edges[e].from;
    if (st.vertex_of(y) != at) return static_cast<int>(y);
  }
  return -1;  // a closed chain collapsed onto one point
}

/// A chain edge at a CDT vertex x: the CDT vertex w at its other end (the first one, where collinear
/// vertices split the constraint) and the face on its left, counter-clockwise of x->w; null when none.
struct ChainEdge {
  VertexHandle w;
  FaceHandle left;
};

/// The constrained CDT edge leaving X towards Y (Y may lie beyond a vertex that splits the constraint).
ChainEdge first_constraint_edge(const Cdt& cdt, VertexHandle x, const Point2& y) {
  auto ec = cdt.incident_edges(x), done = ec;
  do {
    if (!cdt.is_constrained(*ec)) continue;
    const FaceHandle f = ec->first;
    const int i = ec->second;
    // f's vertices counter-clockwise are i, ccw(i), cw(i): f is left of ccw(i) -> cw(i).
    const bool x_first = f->vertex(cdt.ccw(i)) == x;
    const VertexHandle w = x_first ? f->vertex(cdt.cw(i)) : f->vertex(cdt.ccw(i));
    if (cdt.is_infinite(w)) continue;
    if (w->point() == y || (cgal::orientation(x->point(), w->point(), y) == CGAL::COLLINEAR &&
                            CGAL::collinear_are_ordered_along_line(x->point(), w->point(), y)))
      return {w, x_first ? f : f->neighbor(i)};
  } while (++ec != done);
  return {};
}

class RangeWalker {
 public:
  RangeWalker(const Cdt& cdt, const SliceConeScratch& scratch) : m_cdt(cdt), m_scratch(scratch) {}

  /// Appends the visible wedges of the range counter-clockwise from chain edge (x, w) (or the whole circle
  /// around x when w is null) up to the next chain edge. `left` is the face counter-clockwise of x->w, or
  /// null to look it up.
  void collect_ccw(VertexHandle x, VertexHandle w, FaceHandle left, std::vector<Wedge>& out) const {
    FaceHandle f = left;
    if (w == VertexHandle()) {
      // No chain edge at x: the whole circle. Start just after the exterior, if x is on the hull, so
      // that the exterior wedge is entered and left along its hull edges.
      f = x->face();
      auto fc = m_cdt.incident_faces(x), done = fc;
      do {
        const FaceHandle g = fc;
        if (!m_cdt.is_infinite(g) && m_cdt.is_infinite(g->neighbor(m_cdt.cw(g->index(x))))) {
          f = g;
          break;
        }
      } while (++fc != done);
    } else if (f == FaceHandle()) {
      FaceHandle fr;
      int i = 0;
      const bool found = m_cdt.is_edge(x, w, fr, i);
      PLEAT_ASSERT(found, "chain edge missing from the triangulation");
      f = fr->neighbor(i);  // fr is on the right of x->w; its neighbour is on the left (counter-clockwise)
    }
    const FaceHandle start = f;
    const Point2& px = x->point();
    bool outside = m_cdt.is_infinite(f);
    VertexHandle outside_from = w;
    int last_corner = -1;
    while (true) {
      const int i = f->index(x);
      if (!m_cdt.is_infinite(f)) {
        const int corner = f->info().corner[i];
        if (corner != last_corner) {
          const auto& wedges = m_scratch.corner_wedges[corner];
          out.insert(out.end(), wedges.begin(), wedges.end());
          last_corner = corner;
        }
      }
      // The edge to the next face counter-clockwise is (x, f->vertex(cw(i))), index ccw(i) in f.
      const VertexHandle next_vertex = f->vertex(m_cdt.cw(i));
      const FaceHandle g = f->neighbor(m_cdt.ccw(i));
      const bool stop = f->is_constrained(m_cdt.ccw(i)) || g == start;
      const bool g_outside = m_cdt.is_infinite(g);
      if (outside && (stop || !g_outside)) {
        // Leaving the exterior (or ending in it) along the hull edge (x, next_vertex).
        out.push_back(exact_wedge(px, outside_from->point(), next_vertex->point()));
        outside = false;
      }
      if (stop) break;
      if (!outside && g_outside) {
        outside = true;
        outside_from = next_vertex;
      }
      f = g;
    }
  }

  /// The chain edge at x found by turning clockwise from edge (x, w) (the start of the range that ends
  /// at (x, w)); w itself when it is the only chain edge at x.
  VertexHandle clockwise_boundary(VertexHandle x, VertexHandle w) const {
    FaceHandle f;
    int i = 0;
    m_cdt.is_edge(x, w, f, i);  // f is on the right of x->w: clockwise of the edge
    while (true) {
      const int ix = f->index(x);
      // The edge to the next face clockwise is (x, f->vertex(ccw(ix))), index cw(ix) in f.
      if (f->is_constrained(m_cdt.cw(ix))) return f->vertex(m_cdt.ccw(ix));
      f = f->neighbor(m_cdt.cw(ix));
    }
  }

 private:
  const Cdt& m_cdt;
  const SliceConeScratch& m_scratch;
};

/// Whether a CDT vertex's cones are wanted (SliceConeScratch::vertex_needed; crossing points never are).
bool is_needed(VertexHandle v, const SliceConeScratch& s) {
  const int x = v->info().slice_vertex;
  return x >= 0 && s.vertex_needed[x];
}

/// The funnel trees of a region without holes of `t`, window by window: `visible(i, x, pa, pb)` for each
/// corner corners[i] (at x) whose shortest paths to the window's ends leave it towards pa and pb turning
/// left, the window being seen from x between those two rays.
template <class Visible>
void for_each_visible_window(const SliceTriangulation& t, std::span<const SliceWindow> windows,
                             std::span<const int> corners, std::vector<int>& parent_a,
                             std::vector<int>& parent_b, FunnelScratch& funnel, Visible&& visible) {
  for (const SliceWindow& window : windows) {
    grow_shortest_path_tree(t, window, false, parent_a, funnel);
    grow_shortest_path_tree(t, window, true, parent_b, funnel);
    for (std::size_t i = 0; i < corners.size(); ++i) {
      const int c = corners[i];
      const Point2& x = t.corner_vertex(c)->point();
      const Point2& pa = t.corner_vertex(parent_a[c])->point();
      const Point2& pb = t.corner_vertex(parent_b[c])->point();
      if (cgal::orientation(x, pa, pb) == CGAL::LEFT_TURN) visible(i, x, pa, pb);
    }
  }
}

/// Funnel-tree cones of every corner of a region without holes: for each window, the wedge between the
/// first segments of the shortest paths to its two endpoints, when they turn the right way.
void cones_of_simple_region(const SliceTriangulation& st, const SliceRegion& region, int region_index,
                            SliceConeScratch& s) {
  s.region_corners.clear();
  for (const FaceHandle f : region.faces)
    for (int k = 0; k < 3; ++k) {
      const int c = f->info().corner[k];
      if (s.corner_stamp[c] == region_index) continue;
      s.corner_stamp[c] = region_index;
      if (is_needed(f->vertex(k), s)) s.region_corners.push_back(c);
    }
  if (s.region_corners.empty()) return;
  for_each_visible_window(st, region.windows, s.region_corners, s.parent_a, s.parent_b, s.funnel,
                          [&](std::size_t i, const Point2& x, const Point2& pa, const Point2& pb) {
                            s.corner_wedges[s.region_corners[i]].push_back(
                                thin_wedge_between(direction(x, pa), direction(x, pb)));
                          });
}

/// Resets the per-corner scratch for a triangulation with `corners` corners.
void prepare_scratch(std::size_t corners, SliceConeScratch& s) {
  if (s.corner_wedges.size() < corners) s.corner_wedges.resize(corners);
  for (std::size_t c = 0; c < corners; ++c) s.corner_wedges[c].clear();
  s.parent_a.assign(corners, -1);
  s.parent_b.assign(corners, -1);
  s.corner_stamp.assign(corners, -1);
}

/// Regions with holes: every window's sleeves (see_window_through_sleeves); each corner that sees the window
/// through a sleeve gets the wedge between its paths' first segments, as in a region without holes.
void cones_by_sleeves(const SliceTriangulation& st, const SliceRegion& region, SliceConeScratch& s) {
  for (const SliceWindow& window : region.windows) {
    s.sights.clear();
    see_window_through_sleeves(st, window, region.faces.size(), s.sleeves, s.sights);
    s.sleeve_sights += s.sights.size();
    for (const SleeveSight& sight : s.sights) {
      const VertexHandle x = st.corner_vertex(sight.corner);
      if (!is_needed(x, s)) continue;
      const Point2& px = x->point();
      s.corner_wedges[sight.corner].push_back(
          thin_wedge_between(direction(px, st.corner_vertex(sight.from_a)->point()),
                             direction(px, st.corner_vertex(sight.from_b)->point())));
    }
  }
}

/// Collinear or tiny slices (dimension < 2): nothing lies off the line, so a side sees its whole range:
/// the open half-plane where the chain continues on both sides of X, the whole circle at a chain's end.
void collinear_slice_cones(const Slice& slice, const SliceTriangulation& st, std::span<const char> needed,
                           SliceCones& out) {
  // Chain directions leaving each CDT vertex (several slice vertices may share one).
  std::vector<std::pair<cgal::VertexHandle, glm::dvec2>> leaving;
  for (Index x = 0; x < slice.vertices.size(); ++x)
    for (bool forward : {true, false}) {
      const int y = next_distinct(slice, st, x, forward);
      if (y >= 0) leaving.emplace_back(st.vertex_of(x), slice.vertices[y].point - slice.vertices[x].point);
    }
  std::sort(leaving.begin(), leaving.end(),
            [](const auto& a, const auto& b) { return &*a.first < &*b.first; });
  for (Index x = 0; x < slice.vertices.size(); ++x) {
    const int next = next_distinct(slice, st, x, true), prev = next_distinct(slice, st, x, false);
    const glm::dvec2 d = next >= 0   ? slice.vertices[next].point - slice.vertices[x].point
                         : prev >= 0 ? slice.vertices[x].point - slice.vertices[prev].point
                                     : glm::dvec2(0.0);
    // Both directions along the line leave X as chain edges: X is inside a chain.
    bool forward = false, backward = false;
    auto it = std::lower_bound(leaving.begin(), leaving.end(), st.vertex_of(x),
                               [](const auto& a, const cgal::VertexHandle& v) { return &*a.first < &*v; });
    for (; it != leaving.end() && it->first == st.vertex_of(x); ++it) {
      (glm::dot(it->second, d) > 0 ? forward : backward) = true;
    }
    const bool wanted = needed.empty() || needed[x];  // an unwanted vertex gets empty cones
    for (Side side : kBothSides) {
      if (wanted && (d == glm::dvec2(0.0) || !(forward && backward)))
        out.wedges.push_back({0.0, kTwoPi});
      else if (wanted)
        out.wedges.push_back({direction_angle(side == Side::Front ? d : -d), kTwoPi / 2});
      out.offsets.push_back(static_cast<std::uint32_t>(out.wedges.size()));
    }
  }
}

}  // namespace

void compute_slice_cones(const Slice& slice, const SliceTriangulation& st, SliceConeScratch& s,
                         SliceCones& out, std::span<const char> needed) {
  out.wedges.clear();
  out.offsets.assign(1, 0);
  out.windows = out.regions = out.regions_with_holes = 0;
  if (st.dimension() < 2) {
    collinear_slice_cones(slice, st, needed, out);
    return;
  }
  // Needed CDT vertices, by the slice vertex each one was inserted for (coincident slice vertices share one).
  s.vertex_needed.assign(slice.vertices.size(), needed.empty() ? 1 : 0);
  if (!needed.empty())
    for (Index x = 0; x < slice.vertices.size(); ++x)
      if (needed[x]) s.vertex_needed[st.vertex_of(x)->info().slice_vertex] = 1;
  const Cdt& cdt = st.cdt();
  prepare_scratch(st.num_corners(), s);
  out.regions = st.num_regions();
  for (std::size_t r = 0; r < st.num_regions(); ++r) {
    const SliceRegion region = st.region(r);
    if (region.windows.empty()) continue;
    out.windows += region.windows.size();
    if (region.has_holes) {
      ++out.regions_with_holes;
      cones_by_sleeves(st, region, s);
    } else {
      cones_of_simple_region(st, region, static_cast<int>(r), s);
    }
  }

  const RangeWalker walker(cdt, s);
  for (Index x = 0; x < slice.vertices.size(); ++x) {
    if (!needed.empty() && !needed[x]) {
      out.offsets.push_back(static_cast<std::uint32_t>(out.wedges.size()));
      out.offsets.push_back(static_cast<std::uint32_t>(out.wedges.size()));
      continue;
    }
    const VertexHandle xv = st.vertex_of(x);
    const int next = next_distinct(slice, st, x, true), prev = next_distinct(slice, st, x, false);
    // The chain edge towards slice vertex y: as the corner assignment recorded it, else looked up (a
    // constraint split by a vertex on it, a vertex with more than two chain edges).
    auto chain_edge = [&](int y) -> ChainEdge {
      if (y < 0) return {};
      const VertexHandle w = st.vertex_of(y);
      if (const FaceHandle left = st.left_of_constrained_edge(xv, w); left != FaceHandle()) return {w, left};
      return first_constraint_edge(cdt, xv, cgal::to_point(slice.vertices[y].point));
    };
    const ChainEdge out_edge = chain_edge(next), in_edge = chain_edge(prev);
    for (Side side : kBothSides) {
      // Front: counter-clockwise of the outgoing edge (or clockwise of the incoming one); back: mirrored.
      const ChainEdge& ccw_of = side == Side::Front ? out_edge : in_edge;
      const ChainEdge& cw_of = side == Side::Front ? in_edge : out_edge;
      s.range_wedges.clear();
      if (ccw_of.w != VertexHandle())
        walker.collect_ccw(xv, ccw_of.w, ccw_of.left, s.range_wedges);
      else if (cw_of.w != VertexHandle())
        walker.collect_ccw(xv, walker.clockwise_boundary(xv, cw_of.w), FaceHandle(), s.range_wedges);
      else
        walker.collect_ccw(xv, VertexHandle(), FaceHandle(), s.range_wedges);
      unite_wedges(s.range_wedges, s.intervals, out.wedges);
      out.offsets.push_back(static_cast<std::uint32_t>(out.wedges.size()));
    }
  }
}

}  // namespace pleat
