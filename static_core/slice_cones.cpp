#include "static_core/slice_cones.hpp"

#include <CGAL/convex_hull_2.h>
#include <CGAL/number_utils.h>

#include <algorithm>
#include <glm/geometric.hpp>
#include <unordered_map>

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
  switch (CGAL::orientation(x, p, q)) {
    case CGAL::LEFT_TURN:
      return thin_wedge_between(dp, dq);
    case CGAL::RIGHT_TURN:
      return wedge_between(dp, dq);
    default:
      return {direction_angle(dp), CGAL::angle(p, x, q) == CGAL::ACUTE ? kTwoPi : kTwoPi / 2};
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

/// The constrained CDT edge leaving X towards Y (Y may lie beyond a vertex that splits the constraint).
VertexHandle first_constraint_vertex(const Cdt& cdt, VertexHandle x, const Point2& y) {
  auto ec = cdt.incident_edges(x), done = ec;
  do {
    if (!cdt.is_constrained(*ec)) continue;
    const FaceHandle f = ec->first;
    const int i = ec->second;
    const VertexHandle w = f->vertex(cdt.ccw(i)) == x ? f->vertex(cdt.cw(i)) : f->vertex(cdt.ccw(i));
    if (cdt.is_infinite(w)) continue;
    if (w->point() == y) return w;
    if (CGAL::orientation(x->point(), w->point(), y) == CGAL::COLLINEAR &&
        CGAL::collinear_are_ordered_along_line(x->point(), w->point(), y))
      return w;
  } while (++ec != done);
  return VertexHandle();
}

class RangeWalker {
 public:
  RangeWalker(const Cdt& cdt, const SliceConeScratch& scratch) : m_cdt(cdt), m_scratch(scratch) {}

  /// Appends the visible wedges of the range counter-clockwise from edge (x, w) (or the whole circle
  /// around x when w is null) up to the next chain edge.
  void collect_ccw(VertexHandle x, VertexHandle w, std::vector<Wedge>& out) const {
    FaceHandle f;
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
    } else {
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

/// The sector of a corner: counter-clockwise from its first edge to its last edge around its vertex.
Wedge corner_sector(const Cdt& cdt, FaceHandle f, int corner) {
  const VertexHandle x = f->vertex(f->info().corner[0] == corner ? 0 : f->info().corner[1] == corner ? 1 : 2);
  // Turn clockwise to the corner's first face.
  FaceHandle first = f;
  while (true) {
    const int i = first->index(x);
    if (is_separator(cdt, first, cdt.cw(i))) break;
    first = first->neighbor(cdt.cw(i));
    if (first == f) return {0.0, kTwoPi};
  }
  FaceHandle last = first;
  while (true) {
    const int i = last->index(x);
    if (is_separator(cdt, last, cdt.ccw(i))) break;
    last = last->neighbor(cdt.ccw(i));
  }
  const Point2& px = x->point();
  return exact_wedge(px, first->vertex(cdt.ccw(first->index(x)))->point(),
                     last->vertex(cdt.cw(last->index(x)))->point());
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
      s.region_corners.push_back(c);
    }
  for (const SliceWindow& window : region.windows) {
    grow_shortest_path_tree(st, window, false, s.parent_a, s.stack);
    grow_shortest_path_tree(st, window, true, s.parent_b, s.stack);
    for (int c : s.region_corners) {
      const Point2& x = st.corner_vertex(c)->point();
      const Point2& pa = st.corner_vertex(s.parent_a[c])->point();
      const Point2& pb = st.corner_vertex(s.parent_b[c])->point();
      if (CGAL::orientation(x, pa, pb) == CGAL::LEFT_TURN)
        s.corner_wedges[c].push_back(thin_wedge_between(direction(x, pa), direction(x, pb)));
    }
  }
}

/// Resets the per-corner scratch for a triangulation with `corners` corners.
void prepare_scratch(std::size_t corners, SliceConeScratch& s) {
  if (s.corner_wedges.size() < corners) s.corner_wedges.resize(corners);
  for (std::size_t c = 0; c < corners; ++c) s.corner_wedges[c].clear();
  s.parent_a.assign(corners, -1);
  s.parent_b.assign(corners, -1);
  s.corner_stamp.assign(corners, -1);
}

/// Appends the spans blocked, seen from x, by the given segments (those not incident to x).
void append_blocked_spans(VertexHandle xv, const std::vector<std::pair<VertexHandle, VertexHandle>>& segments,
                          std::vector<Wedge>& blocked) {
  const Point2& x = xv->point();
  for (const auto& [p, q] : segments) {
    if (p == xv || q == xv) continue;
    switch (CGAL::orientation(x, p->point(), q->point())) {
      case CGAL::LEFT_TURN:
        blocked.push_back(thin_wedge_between(direction(x, p->point()), direction(x, q->point())));
        break;
      case CGAL::RIGHT_TURN:
        blocked.push_back(thin_wedge_between(direction(x, q->point()), direction(x, p->point())));
        break;
      default:
        break;  // seen edge-on: blocks a single direction
    }
  }
}

/// A hole of a region: its chain edges and the convex hull of its vertices (counter-clockwise).
struct Hole {
  std::vector<std::pair<VertexHandle, VertexHandle>> segments;
  std::vector<Point2> hull;
};

/// Appends the span a hole blocks seen from x when x lies strictly outside the hole's convex hull: a
/// connected set seen from outside its hull spans exactly the wedge between its two extreme hull vertices
/// (found by exact orientation tests, no angles), so the hole's segments need not be swept. Returns false,
/// appending nothing, when x is not strictly outside (the caller sweeps the segments then).
bool append_hull_span(const Point2& x, const std::vector<Point2>& hull, std::vector<Wedge>& blocked) {
  const std::size_t m = hull.size();
  if (m < 3) return false;
  bool outside = false;
  for (std::size_t i = 0; i < m && !outside; ++i)
    outside = CGAL::orientation(hull[i], hull[(i + 1) % m], x) == CGAL::RIGHT_TURN;
  if (!outside) return false;
  // Seen from outside, the hull lies within less than a half-turn: "clockwise of" is a total order on it.
  const Point2* cw = &hull[0];
  const Point2* ccw = &hull[0];
  for (const Point2& p : hull) {
    if (CGAL::orientation(x, *cw, p) == CGAL::RIGHT_TURN) cw = &p;
    if (CGAL::orientation(x, *ccw, p) == CGAL::LEFT_TURN) ccw = &p;
  }
  if (CGAL::orientation(x, *cw, *ccw) == CGAL::LEFT_TURN)
    blocked.push_back(thin_wedge_between(direction(x, *cw), direction(x, *ccw)));
  return true;
}

/// Calls fn(face, index, corner) once per corner of the region, with one of the corner's faces.
template <class Fn>
void for_each_corner(const SliceTriangulation& st, const SliceRegion& region, Fn&& fn) {
  std::vector<char> done(st.num_corners(), 0);
  for (const FaceHandle f : region.faces)
    for (int k = 0; k < 3; ++k) {
      const int c = f->info().corner[k];
      if (done[c]) continue;
      done[c] = 1;
      fn(f, k, c);
    }
}

/// Exact angular sweep of the region's corners (all, or those not on component `skip_component`): the
/// corner's sector minus what the region's chain edges block. O(n) per corner.
void swept_cones(const Cdt& cdt, const SliceTriangulation& st, const SliceRegion& region,
                 const std::vector<std::pair<VertexHandle, VertexHandle>>& segments,
                 const std::unordered_map<const void*, int>* component_of, int skip_component,
                 SliceConeScratch& s) {
  std::vector<Wedge> blocked;
  for_each_corner(st, region, [&](FaceHandle f, int k, int c) {
    const VertexHandle xv = f->vertex(k);
    if (component_of && component_of->at(&*xv) == skip_component) return;
    blocked.clear();
    append_blocked_spans(xv, segments, blocked);
    const AngularSet visible =
        AngularSet::from_wedges({corner_sector(cdt, f, c)}).subtract(AngularSet::from_wedges(blocked));
    s.corner_wedges[c].assign(visible.wedges().begin(), visible.wedges().end());
  });
}

/// A region with holes (Stewart 1999 §2.3.2): the funnel trees run in the outer polygon with the holes
/// ignored — a triangulation of the outer boundary alone — and each hole's angular span, seen from an
/// outer corner, is subtracted from that corner's cone; corners on the holes get cones by the exact sweep.
/// Falls back to the sweep for every corner when the outer boundary is not one simple component (and
/// returns false then).
bool cones_of_region_with_holes(const SliceTriangulation& st, const SliceRegion& region,
                                SliceConeScratch& s) {
  const Cdt& cdt = st.cdt();
  // Boundary components of the region: chain edges and windows, joined at shared vertices.
  std::vector<std::pair<VertexHandle, VertexHandle>> segments;  // chain edges bounding the region
  std::unordered_map<const void*, int> index;
  std::vector<VertexHandle> vertices;
  std::vector<int> parent;
  auto id = [&](VertexHandle v) {
    auto [it, fresh] = index.emplace(&*v, static_cast<int>(vertices.size()));
    if (fresh) {
      vertices.push_back(v);
      parent.push_back(it->second);
    }
    return it->second;
  };
  auto root = [&](int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  auto join = [&](VertexHandle a, VertexHandle b) { parent[root(id(a))] = root(id(b)); };
  for (const FaceHandle f : region.faces)
    for (int i = 0; i < 3; ++i)
      if (f->is_constrained(i)) {
        segments.emplace_back(f->vertex(cdt.ccw(i)), f->vertex(cdt.cw(i)));
        join(segments.back().first, segments.back().second);
      } else {
        for (int k = 0; k < 3; ++k) id(f->vertex(k));  // isolated vertices are components too
      }
  for (const SliceWindow& w : region.windows)
    join(w.face->vertex(cdt.ccw(w.index)), w.face->vertex(cdt.cw(w.index)));
  const int outer = root(id(region.windows.front().face->vertex(cdt.ccw(region.windows.front().index))));
  std::unordered_map<const void*, int> component_of;
  for (std::size_t i = 0; i < vertices.size(); ++i) component_of[&*vertices[i]] = root(static_cast<int>(i));

  // The outer polygon alone, as a slice of its own.
  Slice outer_slice;
  std::vector<VertexHandle> original;  // outer_slice vertex -> original CDT vertex
  std::unordered_map<const void*, Index> outer_index;
  auto outer_id = [&](VertexHandle v) {
    auto [it, fresh] = outer_index.emplace(&*v, static_cast<Index>(original.size()));
    if (fresh) {
      original.push_back(v);
      SliceVertex sv;
      sv.point = cgal::to_glm(v->point());
      outer_slice.vertices.push_back(sv);
    }
    return it->second;
  };
  std::vector<Hole> holes;
  std::unordered_map<int, std::size_t> hole_of_component;
  for (const auto& [p, q] : segments) {
    const int component = component_of.at(&*p);
    if (component == outer) {
      outer_slice.edges.push_back({outer_id(p), outer_id(q), 0});
      continue;
    }
    const auto [it, fresh] = hole_of_component.emplace(component, holes.size());
    if (fresh) holes.emplace_back();
    holes[it->second].segments.emplace_back(p, q);
  }
  std::vector<Point2> hole_points;
  for (Hole& hole : holes) {
    hole_points.clear();
    for (const auto& [p, q] : hole.segments) {
      hole_points.push_back(p->point());
      hole_points.push_back(q->point());
    }
    CGAL::convex_hull_2(hole_points.begin(), hole_points.end(), std::back_inserter(hole.hull));
  }
  for (const SliceWindow& w : region.windows) {
    outer_id(w.face->vertex(cdt.ccw(w.index)));
    outer_id(w.face->vertex(cdt.cw(w.index)));
  }
  outer_slice.out_edge.assign(outer_slice.vertices.size(), -1);
  outer_slice.in_edge.assign(outer_slice.vertices.size(), -1);
  SliceTriangulation outer_st;
  outer_st.build(outer_slice);
  // The outer polygon is the sub-region on the inner side of the first window.
  int polygon = -1;
  if (outer_st.dimension() == 2) {
    const SliceWindow& w = region.windows.front();
    cgal::FaceHandle fr;
    int i = 0;
    const VertexHandle a = outer_st.vertex_of(outer_index.at(&*w.face->vertex(cdt.ccw(w.index))));
    const VertexHandle b = outer_st.vertex_of(outer_index.at(&*w.face->vertex(cdt.cw(w.index))));
    if (outer_st.cdt().is_edge(a, b, fr, i)) {
      // fr is on the right of a->b; the region is on the left of its windows (a, b).
      const FaceHandle inside = fr->neighbor(i);
      if (!outer_st.cdt().is_infinite(inside)) polygon = inside->info().region;
    }
  }
  if (polygon < 0 || outer_st.regions()[polygon].has_holes ||
      outer_st.regions()[polygon].windows.size() != region.windows.size()) {
    swept_cones(cdt, st, region, segments, nullptr, -1, s);
    return false;
  }
  SliceConeScratch sub;
  prepare_scratch(outer_st.num_corners(), sub);
  cones_of_simple_region(outer_st, outer_st.regions()[polygon], polygon, sub);

  // Each outer corner: the cone of the outer polygon's corner holding it, minus the holes' spans.
  std::vector<Wedge> blocked;
  for_each_corner(st, region, [&](FaceHandle f, int k, int c) {
    const VertexHandle xv = f->vertex(k);
    if (component_of.at(&*xv) != outer) return;
    // The same corner in the outer polygon's triangulation, found exactly: both begin, turning
    // counter-clockwise about x, at the chain or hull edge (x, w) that bounds the corner clockwise.
    cgal::FaceHandle first = f;
    for (int turns = 0; !is_separator(cdt, first, cdt.cw(first->index(xv))); ++turns) {
      PLEAT_ASSERT(turns < 1000000, "a corner of an outer vertex has no bounding edge");
      first = first->neighbor(cdt.cw(first->index(xv)));
    }
    const VertexHandle w = first->vertex(cdt.ccw(first->index(xv)));
    int sub_corner = -1;
    const auto w_index = outer_index.find(&*w);
    if (w_index != outer_index.end()) {
      cgal::FaceHandle fr;
      int i = 0;
      const VertexHandle x2 = outer_st.vertex_of(outer_index.at(&*xv)),
                         w2 = outer_st.vertex_of(w_index->second);
      if (outer_st.cdt().is_edge(x2, w2, fr, i)) {
        const cgal::FaceHandle g = fr->neighbor(i);  // left of x2 -> w2: the face that begins at (x, w)
        if (!outer_st.cdt().is_infinite(g) && g->info().region == polygon)
          sub_corner = g->info().corner[g->index(x2)];
      }
    }
    PLEAT_ASSERT(sub_corner >= 0, "an outer corner is not inside the outer polygon");
    blocked.clear();
    for (const Hole& hole : holes)
      if (!append_hull_span(xv->point(), hole.hull, blocked)) append_blocked_spans(xv, hole.segments, blocked);
    const AngularSet visible =
        AngularSet::from_wedges(sub.corner_wedges[sub_corner]).subtract(AngularSet::from_wedges(blocked));
    s.corner_wedges[c].assign(visible.wedges().begin(), visible.wedges().end());
  });
  // Corners on the holes: the exact sweep against every chain edge of the region.
  swept_cones(cdt, st, region, segments, &component_of, outer, s);
  return true;
}

/// Collinear or tiny slices (dimension < 2): nothing lies off the line, so a side sees its whole range:
/// the open half-plane where the chain continues on both sides of X, the whole circle at a chain's end.
void collinear_slice_cones(const Slice& slice, const SliceTriangulation& st, SliceCones& out) {
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
    for (Side side : kBothSides) {
      if (d == glm::dvec2(0.0) || !(forward && backward))
        out.wedges.push_back({0.0, kTwoPi});
      else
        out.wedges.push_back({direction_angle(side == Side::Front ? d : -d), kTwoPi / 2});
      out.offsets.push_back(static_cast<std::uint32_t>(out.wedges.size()));
    }
  }
}

}  // namespace

void compute_slice_cones(const Slice& slice, const SliceTriangulation& st, SliceConeScratch& s,
                         SliceCones& out) {
  out.wedges.clear();
  out.offsets.assign(1, 0);
  out.windows = out.regions = out.regions_with_holes = out.holes_swept = 0;
  if (st.dimension() < 2) {
    collinear_slice_cones(slice, st, out);
    return;
  }
  const Cdt& cdt = st.cdt();
  prepare_scratch(st.num_corners(), s);
  out.regions = st.regions().size();
  for (std::size_t r = 0; r < st.regions().size(); ++r) {
    const SliceRegion& region = st.regions()[r];
    if (region.windows.empty()) continue;
    out.windows += region.windows.size();
    if (region.has_holes) {
      ++out.regions_with_holes;
      if (!cones_of_region_with_holes(st, region, s)) ++out.holes_swept;
    } else {
      cones_of_simple_region(st, region, static_cast<int>(r), s);
    }
  }

  const RangeWalker walker(cdt, s);
  for (Index x = 0; x < slice.vertices.size(); ++x) {
    const VertexHandle xv = st.vertex_of(x);
    const int next = next_distinct(slice, st, x, true), prev = next_distinct(slice, st, x, false);
    const VertexHandle w_out =
        next >= 0 ? first_constraint_vertex(cdt, xv, cgal::to_point(slice.vertices[next].point))
                  : VertexHandle();
    const VertexHandle w_in =
        prev >= 0 ? first_constraint_vertex(cdt, xv, cgal::to_point(slice.vertices[prev].point))
                  : VertexHandle();
    for (Side side : kBothSides) {
      // Front: counter-clockwise of the outgoing edge (or clockwise of the incoming one); back: mirrored.
      const VertexHandle ccw_of = side == Side::Front ? w_out : w_in;
      const VertexHandle cw_of = side == Side::Front ? w_in : w_out;
      s.range_wedges.clear();
      if (ccw_of != VertexHandle())
        walker.collect_ccw(xv, ccw_of, s.range_wedges);
      else if (cw_of != VertexHandle())
        walker.collect_ccw(xv, walker.clockwise_boundary(xv, cw_of), s.range_wedges);
      else
        walker.collect_ccw(xv, VertexHandle(), s.range_wedges);
      unite_wedges(s.range_wedges, s.intervals, out.wedges);
      out.offsets.push_back(static_cast<std::uint32_t>(out.wedges.size()));
    }
  }
}

}  // namespace pleat
