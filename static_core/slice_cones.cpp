#include "static_core/slice_cones.hpp"

#include <CGAL/convex_hull_2.h>
#include <CGAL/number_utils.h>

#include <algorithm>
#include <glm/geometric.hpp>
#include <iterator>
#include <tuple>

#include "static_core/assert.hpp"
#include "static_core/union_find.hpp"

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

/// Triangular expansion (Bungiu, Hemmer, Hershberger, Huang and Kroeller 2014), for regions with holes:
/// the cone of a corner at x is the set of directions whose ray from x leaves the hull through a window
/// before it meets a chain edge. From each of the corner's triangles the range of directions through the edge
/// opposite x is carried across unconstrained edges, split where a triangle's third vertex lies inside it,
/// dropped at chain edges and emitted at windows. Ranges are bounded by rays from x through triangulation
/// vertices and every split is an exact orientation test, so the visible set is exact; only the wedges'
/// angles are rounded. Cost: the triangles seen from x (each once per range piece that reaches it), not the
/// region's size — no angular sweep over all its chain edges.
void cones_by_expansion(const SliceTriangulation& st, const SliceRegion& region, SliceConeScratch& s,
                        const std::vector<char>* only) {
  const Cdt& cdt = st.cdt();
  for (const FaceHandle f : region.faces)
    for (int k = 0; k < 3; ++k) {
      const VertexHandle x = f->vertex(k);
      if (!is_needed(x, s) || (only != nullptr && !(*only)[f->info().corner[k]])) continue;
      const Point2& px = x->point();
      std::vector<Wedge>& out = s.corner_wedges[f->info().corner[k]];
      // The edge opposite x, from its right end a to its left end b seen from x: the range (a, b).
      s.expansion.push_back({f, k, f->vertex(cdt.ccw(k)), f->vertex(cdt.cw(k))});
      while (!s.expansion.empty()) {
        ExpansionTask task = s.expansion.back();
        s.expansion.pop_back();
        // Follow the range from ray x->right to ray x->left across edge (task.face, task.index); where it
        // splits, one part waits on the stack and the loop goes on with the other.
        while (!task.face->is_constrained(task.index)) {
          const FaceHandle g = task.face->neighbor(task.index);
          if (cdt.is_infinite(g)) {
            out.push_back(
                thin_wedge_between(direction(px, task.right->point()), direction(px, task.left->point())));
            break;
          }
          // Seen from x, g's vertices are a (right end of the crossed edge), b (left end) and c beyond it;
          // edge (a, c) is opposite b = vertex(ccw(j)), edge (c, b) opposite a = vertex(cw(j)).
          const int j = g->index(task.face);
          const VertexHandle c = g->vertex(j);
          if (cgal::orientation(px, task.right->point(), c->point()) != CGAL::LEFT_TURN) {
            task = {g, cdt.cw(j), task.right, task.left};  // c on or beyond the right ray
          } else if (cgal::orientation(px, c->point(), task.left->point()) != CGAL::LEFT_TURN) {
            task = {g, cdt.ccw(j), task.right, task.left};  // c on or beyond the left ray
          } else {  // c strictly inside the range: split it at the ray x->c
            s.expansion.push_back({g, cdt.cw(j), c, task.left});
            task = {g, cdt.ccw(j), task.right, c};
          }
        }
      }
    }
}

/// Stewart's §2.3.2 for a region R with holes, on the corners of its outer boundary: a ray from such a
/// corner x leaves through a window iff it does so in the polygon P bounded by R's outer boundary alone (R
/// with its holes filled) and meets no hole. P is simple, so funnel trees give the first (exact); a hole is
/// connected, so the directions from x that meet it form one range, the one between its convex hull's
/// tangents when x lies outside that hull (the second). P is triangulated afresh from the chains of R's
/// outer boundary (a SliceTriangulation of them: R's windows are hull edges of any subset of the slice that
/// keeps their ends). Every decision is an exact orientation test; the visible ranges are bounded by rays
/// through triangulation vertices, as the expansion's are, so the cones are the expansion's up to the
/// rounding of their angles. Corners on holes, corners inside or on a hole's hull and corners with no
/// counterpart in P are left to the expansion (flagged in by_expansion). Measured: at 1,024 triangles and
/// more it pays (the 300k curtain's frame 4-5% cheaper, the 30k curtain's 2-3%); below, building P costs
/// more than the expansion it saves (regions of 256 triangles and more: the layered cloth 27% slower).
/// Returns false, leaving everything to the expansion, where the method does not apply (crossing points,
/// degenerate polygons).
bool cones_by_outer_polygon(const SliceTriangulation& st, const SliceRegion& region, SliceConeScratch& s) {
  const Cdt& cdt = st.cdt();
  OuterPolygonScratch& o = s.outer;
  auto id = [](VertexHandle v) { return v->info().slice_vertex; };
  const std::size_t n = s.vertex_needed.size();
  if (o.root.size() < n) {
    o.root.resize(n, -1);
    o.sub_index.resize(n, -1);
  }
  for (int v : o.touched) o.root[v] = o.sub_index[v] = -1;
  o.touched.clear();
  auto find = [&](int v) { return find_root(o.root, v); };
  // Boundary components: vertices joined by R's separators (chain edges and windows).
  for (const FaceHandle f : region.faces)
    for (int k = 0; k < 3; ++k) {
      const int v = id(f->vertex(k));
      if (v < 0) return false;  // a crossing point of chains: no slice vertex to key on
      if (o.root[v] < 0) {
        o.root[v] = v;
        o.touched.push_back(v);
      }
    }
  for (const FaceHandle f : region.faces)
    for (int i = 0; i < 3; ++i)
      if (is_separator(cdt, f, i)) o.root[find(id(f->vertex(cdt.ccw(i))))] = find(id(f->vertex(cdt.cw(i))));
  const SliceWindow& first_window = region.windows.front();
  const int outer_root = find(id(st.corner_vertex(first_window.corner_a)));
  for (const SliceWindow& w : region.windows)
    if (find(id(st.corner_vertex(w.corner_a))) != outer_root) return false;

  // The outer boundary's chains, as a slice of their own, and its triangulation.
  o.outer.clear();
  o.vertex_of_sub.clear();
  for (int v : o.touched)
    if (find(v) == outer_root) {
      o.sub_index[v] = static_cast<int>(o.outer.vertices.size());
      SliceVertex sv;
      sv.point = cgal::to_glm(st.vertex_of(static_cast<Index>(v))->point());
      o.outer.vertices.push_back(sv);
      o.vertex_of_sub.push_back(st.vertex_of(static_cast<Index>(v)));
    }
  for (const FaceHandle f : region.faces)
    for (int i = 0; i < 3; ++i) {
      if (!f->is_constrained(i)) continue;
      const int a = o.sub_index[id(f->vertex(cdt.ccw(i)))], b = o.sub_index[id(f->vertex(cdt.cw(i)))];
      if (a >= 0 && b >= 0) o.outer.edges.push_back({static_cast<Index>(a), static_cast<Index>(b), 0});
    }
  if (!o.triangulation) o.triangulation = std::make_unique<SliceTriangulation>();
  SliceTriangulation& polygon = *o.triangulation;
  polygon.build(o.outer);
  if (polygon.dimension() < 2 || polygon.crossings() > 0) return false;
  // P: the region of the new triangulation on R's first window; it must have R's windows and no holes.
  const VertexHandle wa = st.corner_vertex(first_window.corner_a),
                     wb = st.corner_vertex(first_window.corner_b);
  auto has_first_window = [&](const SliceRegion& candidate) {
    return std::any_of(candidate.windows.begin(), candidate.windows.end(), [&](const SliceWindow& w) {
      return o.vertex_of_sub[id(polygon.corner_vertex(w.corner_a))] == wa &&
             o.vertex_of_sub[id(polygon.corner_vertex(w.corner_b))] == wb;
    });
  };
  std::size_t r = 0;
  while (r < polygon.num_regions() && !has_first_window(polygon.region(r))) ++r;
  if (r == polygon.num_regions()) return false;
  const SliceRegion p_region = polygon.region(r);
  if (p_region.has_holes || p_region.windows.size() != region.windows.size()) return false;

  // The holes (the other boundary components: island chains, loops, isolated points) and their hulls.
  o.members.clear();
  for (int v : o.touched)
    if (find(v) != outer_root) o.members.emplace_back(find(v), v);
  std::sort(o.members.begin(), o.members.end());
  std::size_t holes = 0;
  for (std::size_t i = 0; i < o.members.size();) {
    o.points.clear();
    const int r = o.members[i].first;
    for (; i < o.members.size() && o.members[i].first == r; ++i)
      o.points.push_back(st.vertex_of(static_cast<Index>(o.members[i].second))->point());
    if (o.hulls.size() <= holes) o.hulls.resize(holes + 1);
    o.hulls[holes].clear();
    CGAL::convex_hull_2(o.points.begin(), o.points.end(), std::back_inserter(o.hulls[holes]));
    ++holes;
  }

  // Which corner of P stands for which corner of R: the same run of directions at the same vertex, named by
  // the separator that bounds it clockwise (a chain edge or a window, the same in both triangulations).
  const std::size_t corners = st.num_corners();
  o.by_expansion.assign(corners, 1);
  if (o.ranges.size() < corners) o.ranges.resize(corners);
  o.keys.clear();
  o.p_keys.clear();
  for (const FaceHandle f : region.faces)
    for (int k = 0; k < 3; ++k)
      if (is_separator(cdt, f, cdt.cw(k)) && is_needed(f->vertex(k), s))
        o.keys.push_back({id(f->vertex(k)), id(f->vertex(cdt.ccw(k))), f->info().corner[k]});
  for (const FaceHandle f : p_region.faces)
    for (int k = 0; k < 3; ++k)
      if (is_separator(polygon.cdt(), f, polygon.cdt().cw(k)))
        o.p_keys.push_back({id(o.vertex_of_sub[id(f->vertex(k))]),
                            id(o.vertex_of_sub[id(f->vertex(polygon.cdt().ccw(k)))]), f->info().corner[k]});
  std::sort(o.keys.begin(), o.keys.end());
  std::sort(o.p_keys.begin(), o.p_keys.end());
  o.r_corners.clear();
  o.p_corners.clear();
  for (std::size_t i = 0, j = 0; i < o.keys.size() && j < o.p_keys.size();) {
    const auto& [x, w, c] = o.keys[i];
    const auto& [px, pw, pc] = o.p_keys[j];
    if (std::tie(x, w) < std::tie(px, pw)) {
      ++i;
    } else if (std::tie(px, pw) < std::tie(x, w)) {
      ++j;
    } else {
      o.r_corners.push_back(c);
      o.p_corners.push_back(pc);
      o.ranges[c].clear();
      o.by_expansion[c] = 0;
      ++i;
      ++j;
    }
  }

  // Funnel trees in P: through each window, the range between the first segments of the paths to its ends.
  o.parent_a.assign(polygon.num_corners(), -1);
  o.parent_b.assign(polygon.num_corners(), -1);
  for_each_visible_window(polygon, p_region.windows, o.p_corners, o.parent_a, o.parent_b, s.funnel,
                          [&](std::size_t i, const Point2&, const Point2& pa, const Point2& pb) {
                            o.ranges[o.r_corners[i]].emplace_back(pa, pb);
                          });

  // Minus each hole's shadow: the range between its hull's tangents from x (x strictly outside the hull).
  for (const int c : o.r_corners) {
    const Point2& x = st.corner_vertex(c)->point();
    auto& ranges = o.ranges[c];
    for (std::size_t h = 0; h < holes && !ranges.empty(); ++h) {
      const std::vector<Point2>& hull = o.hulls[h];
      Point2 right, left;             // the shadow: counter-clockwise from ray x->right to ray x->left
      if (hull.size() < 2) continue;  // an isolated point blocks a single direction
      if (hull.size() == 2) {
        const CGAL::Orientation turn = cgal::orientation(x, hull[0], hull[1]);
        if (turn == CGAL::COLLINEAR) continue;  // a segment seen edge-on blocks a single direction
        right = turn == CGAL::LEFT_TURN ? hull[0] : hull[1];
        left = turn == CGAL::LEFT_TURN ? hull[1] : hull[0];
      } else {
        bool outside = false;
        for (std::size_t i = 0; i < hull.size() && !outside; ++i)
          outside = cgal::orientation(hull[i], hull[(i + 1) % hull.size()], x) == CGAL::RIGHT_TURN;
        if (!outside) {
          o.by_expansion[c] = 1;
          break;
        }
        // Seen from x the hull lies within less than a half-turn, where "clockwise of" is a total order.
        right = left = hull[0];
        for (const Point2& q : hull) {
          if (cgal::orientation(x, right, q) == CGAL::RIGHT_TURN) right = q;
          if (cgal::orientation(x, left, q) == CGAL::LEFT_TURN) left = q;
        }
      }
      // Both ranges are under a half-turn: they meet iff one contains the other's first ray, and what is left
      // of [a, b] is [a, right] where right is past a, and [left, b] where b is past left.
      auto contains = [&x](const Point2& from, const Point2& to, const Point2& d) {
        return cgal::orientation(x, from, d) != CGAL::RIGHT_TURN &&
               cgal::orientation(x, d, to) != CGAL::RIGHT_TURN;
      };
      o.next.clear();
      for (const auto& [a, b] : ranges) {
        if (!contains(a, b, right) && !contains(right, left, a)) {
          o.next.emplace_back(a, b);
          continue;
        }
        if (cgal::orientation(x, a, right) == CGAL::LEFT_TURN) o.next.emplace_back(a, right);
        if (cgal::orientation(x, left, b) == CGAL::LEFT_TURN) o.next.emplace_back(left, b);
      }
      ranges.swap(o.next);
    }
    if (o.by_expansion[c]) continue;
    ++s.outer_polygon_corners;
    const glm::dvec2 px = cgal::to_glm(x);
    for (const auto& [a, b] : ranges)
      s.corner_wedges[c].push_back(thin_wedge_between(cgal::to_glm(a) - px, cgal::to_glm(b) - px));
  }
  return true;
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
      const bool outer =
          region.faces.size() >= s.outer_polygon_min_faces && cones_by_outer_polygon(st, region, s);
      cones_by_expansion(st, region, s, outer ? &s.outer.by_expansion : nullptr);
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
