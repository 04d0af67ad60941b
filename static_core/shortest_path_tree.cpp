#include "static_core/shortest_path_tree.hpp"

#include "static_core/assert.hpp"

namespace pleat {

void grow_shortest_path_tree(const SliceTriangulation& slice, const SliceWindow& window, bool from_b,
                             std::vector<int>& parent, FunnelScratch& scratch) {
  const cgal::Cdt& cdt = slice.cdt();
  const int root_index = from_b ? cdt.cw(window.index) : cdt.ccw(window.index);
  const int root = from_b ? window.corner_b : window.corner_a;
  const cgal::VertexHandle root_vertex = window.face->vertex(root_index);
  auto point = [&](int corner) -> const cgal::Point2& { return slice.corner_vertex(corner)->point(); };
  auto turn = [&](int from, int to, const cgal::Point2& x) {
    return cgal::orientation(point(from), point(to), x);
  };
  std::vector<int>& funnel = scratch.funnel;
  std::vector<std::pair<int, int>>& undo = scratch.undo;
  std::vector<FunnelTask>& stack = scratch.stack;
  PLEAT_ASSERT(!slice.region(static_cast<std::size_t>(slice.corner_region(root))).has_holes,
               "a funnel tree in a region with holes");
  // A funnel range moves outwards by at most one place per triangle it crosses: fewer than the corners.
  const int corners = static_cast<int>(slice.num_corners());
  const int middle = corners + 2;
  if (funnel.size() < std::size_t(2 * middle + 1)) funnel.resize(2 * middle + 1);
  undo.clear();
  stack.clear();
  parent[root] = root;
  funnel[middle] = root;

  // The root's fan: every triangle of the root corner sees the root directly; its funnel is (L, root, R).
  {
    auto fc = cdt.incident_faces(root_vertex), done = fc;
    do {
      const cgal::FaceHandle f = fc;
      if (cdt.is_infinite(f)) continue;
      const int i = f->index(root_vertex);
      if (f->info().corner[i] != root) continue;
      // Seen across the edge opposite the root, L is its cw(i) end and R its ccw(i) end.
      const int l = f->info().corner[cdt.cw(i)], r = f->info().corner[cdt.ccw(i)];
      parent[l] = parent[r] = root;
      if (!is_separator(cdt, f, i)) stack.push_back({f, i, middle - 1, middle, middle + 1, 0, l, r});
    } while (++fc != done);
  }

  while (!stack.empty()) {
    const FunnelTask task = stack.back();
    stack.pop_back();
    while (undo.size() > task.undo) {
      funnel[undo.back().first] = undo.back().second;
      undo.pop_back();
    }
    auto write = [&](int at, int corner) {
      PLEAT_ASSERT(at >= 0 && std::size_t(at) < funnel.size(), "funnel outgrew its array");
      undo.emplace_back(at, funnel[at]);
      funnel[at] = corner;
    };
    if (task.left >= 0) write(task.lo, task.left);
    if (task.right >= 0) write(task.hi, task.right);
    const int lo = task.lo, apex = task.apex, hi = task.hi;

    const cgal::FaceHandle g = task.face->neighbor(task.index);
    const int j = cdt.mirror_index(task.face, task.index);
    PLEAT_ASSERT(g->info().corner[cdt.ccw(j)] == funnel[lo] && g->info().corner[cdt.cw(j)] == funnel[hi],
                 "funnel ends are not the diagonal's corners");
    const int cx = g->info().corner[j];
    const cgal::Point2& x = g->vertex(j)->point();
    // L-chain funnel[apex - 1 .. lo]: x's tangent is there iff x is left of or on (cusp, l_1); it is the
    // outermost l_i with x left of or on (l_{i-1}, l_i) (those i form a prefix: see the header). R-chain
    // mirrored. Else the cusp.
    int tangent = apex;
    bool on_left = false;
    if (lo < apex && turn(funnel[apex], funnel[apex - 1], x) != CGAL::RIGHT_TURN) {
      on_left = true;
      int a = lo, b = apex - 1;  // the answer is in [a, b]
      while (a < b) {
        const int m = a + (b - a) / 2;
        if (turn(funnel[m + 1], funnel[m], x) != CGAL::RIGHT_TURN)
          b = m;
        else
          a = m + 1;
      }
      tangent = a;
    } else if (apex < hi && turn(funnel[apex], funnel[apex + 1], x) != CGAL::LEFT_TURN) {
      int a = apex + 1, b = hi;
      while (a < b) {
        const int m = b - (b - a) / 2;
        if (turn(funnel[m - 1], funnel[m], x) != CGAL::LEFT_TURN)
          a = m;
        else
          b = m - 1;
      }
      tangent = a;
    }
    parent[cx] = funnel[tangent];
    // Across (L, x), edge cw(j): funnel[lo..tangent] then x. Across (x, R), edge ccw(j): x then
    // funnel[tangent..hi]. The cusp moves to the tangent on the side the tangent is not.
    const auto mark = static_cast<std::uint32_t>(undo.size());
    if (!is_separator(cdt, g, cdt.cw(j)))
      stack.push_back({g, cdt.cw(j), lo, on_left ? tangent : apex, tangent + 1, mark, -1, cx});
    if (!is_separator(cdt, g, cdt.ccw(j)))
      stack.push_back({g, cdt.ccw(j), tangent - 1, on_left ? apex : tangent, hi, mark, cx, -1});
  }
}

}  // namespace pleat
