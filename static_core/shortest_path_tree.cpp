#include "static_core/internal/shortest_path_tree.hpp"

#include "static_core/assert.hpp"

namespace pleat {

namespace {

/// Where x's tangent touches the funnel funnel[lo..hi] with its cusp at funnel[apex] (see the header): the
/// position of x's parent, and whether it lies on the L-chain (funnel[lo .. apex - 1]).
/// L-chain funnel[apex - 1 .. lo]: x's tangent is there iff x is left of or on (cusp, l_1); it is the
/// outermost l_i with x left of or on (l_{i-1}, l_i) (those i form a prefix: see the header). R-chain
/// mirrored. Else the cusp.
template <class Point>
std::pair<int, bool> funnel_tangent(const std::vector<int>& funnel, int lo, int apex, int hi,
                                    const cgal::Point2& x, Point&& point) {
  auto turn = [&](int from, int to) { return cgal::orientation(point(funnel[from]), point(funnel[to]), x); };
  if (lo < apex && turn(apex, apex - 1) != CGAL::RIGHT_TURN) {
    int a = lo, b = apex - 1;  // the answer is in [a, b]
    while (a < b) {
      const int m = a + (b - a) / 2;
      if (turn(m + 1, m) != CGAL::RIGHT_TURN)
        b = m;
      else
        a = m + 1;
    }
    return {a, true};
  }
  if (apex < hi && turn(apex, apex + 1) != CGAL::LEFT_TURN) {
    int a = apex + 1, b = hi;
    while (a < b) {
      const int m = b - (b - a) / 2;
      if (turn(m - 1, m) != CGAL::LEFT_TURN)
        a = m;
      else
        b = m - 1;
    }
    return {a, false};
  }
  return {apex, false};
}

/// Brings a funnel array back to a task's state: undoes the writes made since `mark` (the depth-first walk
/// backtracking), then writes the task's new end corners (unless -1) at lo and hi, logged for the next undo.
void restore_funnel(std::vector<int>& funnel, std::vector<std::pair<int, int>>& undo, std::uint32_t mark,
                    int lo, int left, int hi, int right) {
  while (undo.size() > mark) {
    funnel[undo.back().first] = undo.back().second;
    undo.pop_back();
  }
  for (const auto& [at, corner] : {std::pair{lo, left}, std::pair{hi, right}}) {
    if (corner < 0) continue;
    PLEAT_ASSERT(at >= 0 && std::size_t(at) < funnel.size(), "funnel outgrew its array");
    undo.emplace_back(at, funnel[at]);
    funnel[at] = corner;
  }
}

// Per funnel of a sleeve (0: from a, 1: from b): the turn a path from its root may not make (outward convex:
// counter-clockwise only from a, clockwise only from b), and the direction of the chain on its own side in
// the funnel array (the L-chain from a, the R-chain from b).
constexpr CGAL::Orientation kWrongTurn[2] = {CGAL::RIGHT_TURN, CGAL::LEFT_TURN};
constexpr int kOwnSide[2] = {-1, 1};

}  // namespace

void grow_shortest_path_tree(const SliceTriangulation& slice, const SliceWindow& window, bool from_b,
                             std::vector<int>& parent, FunnelScratch& scratch) {
  const cgal::Cdt& cdt = slice.cdt();
  const int root_index = from_b ? cdt.cw(window.index) : cdt.ccw(window.index);
  const int root = from_b ? window.corner_b : window.corner_a;
  const cgal::VertexHandle root_vertex = window.face->vertex(root_index);
  auto point = [&](int corner) -> const cgal::Point2& { return slice.corner_vertex(corner)->point(); };
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
    restore_funnel(funnel, undo, task.undo, task.lo, task.left, task.hi, task.right);
    const int lo = task.lo, apex = task.apex, hi = task.hi;

    const cgal::FaceHandle g = task.face->neighbor(task.index);
    const int j = cdt.mirror_index(task.face, task.index);
    PLEAT_ASSERT(g->info().corner[cdt.ccw(j)] == funnel[lo] && g->info().corner[cdt.cw(j)] == funnel[hi],
                 "funnel ends are not the diagonal's corners");
    const int cx = g->info().corner[j];
    const cgal::Point2& x = g->vertex(j)->point();
    const auto [tangent, on_left] = funnel_tangent(funnel, lo, apex, hi, x, point);
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

void see_window_through_sleeves(const SliceTriangulation& slice, const SliceWindow& window,
                                std::size_t region_faces, SleeveScratch& scratch,
                                std::vector<SleeveSight>& sights) {
  const cgal::Cdt& cdt = slice.cdt();
  auto point = [&](int corner) -> const cgal::Point2& { return slice.corner_vertex(corner)->point(); };
  const int max_depth = static_cast<int>(region_faces);
  const int middle = max_depth + 2;
  for (int s = 0; s < 2; ++s) {
    if (scratch.funnel[s].size() < std::size_t(2 * middle + 1)) scratch.funnel[s].resize(2 * middle + 1);
    scratch.undo[s].clear();
  }
  std::vector<SleeveTask>& stack = scratch.stack;
  stack.clear();

  // The window's triangle (c0, a, b), counter-clockwise: c0 sees the window directly. Its other two edges,
  // seen from inside the triangle: (a, c0) with L = a, R = c0, and (c0, b) with L = c0, R = b.
  const cgal::FaceHandle t0 = window.face;
  const int i0 = window.index;
  const int a = window.corner_a, b = window.corner_b, c0 = t0->info().corner[i0];
  sights.push_back({c0, a, b});
  scratch.funnel[0][middle] = a;
  scratch.funnel[1][middle] = b;
  if (max_depth > 1) {
    SleeveTask task;
    task.face = t0;
    task.depth = 1;
    if (!is_separator(cdt, t0, cdt.cw(i0))) {  // across (a, c0): funnels (a | c0) and (a, b, c0)
      task.index = cdt.cw(i0);
      task.funnel[0] = {middle, middle, middle + 1, 0, -1, c0, -1};
      task.funnel[1] = {middle - 1, middle, middle + 1, 0, a, c0, -1};
      stack.push_back(task);
    }
    if (!is_separator(cdt, t0, cdt.ccw(i0))) {  // across (c0, b): funnels (c0, a, b) and (c0 | b)
      task.index = cdt.ccw(i0);
      task.funnel[0] = {middle - 1, middle, middle + 1, 0, c0, b, -1};
      task.funnel[1] = {middle - 1, middle, middle, 0, c0, -1, -1};
      stack.push_back(task);
    }
  }

  while (!stack.empty()) {
    const SleeveTask task = stack.back();
    stack.pop_back();
    for (int s = 0; s < 2; ++s) {
      const SleeveFunnel& f = task.funnel[s];
      restore_funnel(scratch.funnel[s], scratch.undo[s], f.undo, f.lo, f.left, f.hi, f.right);
    }
    // The path from a root turns at its cusp towards a point of the edge at best towards the first vertex of
    // the chain on its own side (l_1 from a, r_1 from b: the funnel's directions at the cusp lie within a
    // half-turn that does not hold the path's way back); when even that turn is the wrong way, no point of
    // the edge sees the window.
    auto closed_at_cusp = [&](int s) {
      const SleeveFunnel& f = task.funnel[s];
      const int own = f.apex + kOwnSide[s];
      return f.before_cusp >= 0 && own >= f.lo && own <= f.hi &&
             cgal::orientation(point(f.before_cusp), point(scratch.funnel[s][f.apex]),
                               point(scratch.funnel[s][own])) == kWrongTurn[s];
    };
    if (closed_at_cusp(0) || closed_at_cusp(1)) continue;
    const cgal::FaceHandle g = task.face->neighbor(task.index);
    const int j = cdt.mirror_index(task.face, task.index);
    const int cx = g->info().corner[j];
    const cgal::Point2& x = g->vertex(j)->point();
    std::pair<int, bool> tangent[2];
    for (int s = 0; s < 2; ++s) {
      const SleeveFunnel& f = task.funnel[s];
      PLEAT_ASSERT(g->info().corner[cdt.ccw(j)] == scratch.funnel[s][f.lo] &&
                       g->info().corner[cdt.cw(j)] == scratch.funnel[s][f.hi],
                   "sleeve funnel ends are not the edge's corners");
      tangent[s] = funnel_tangent(scratch.funnel[s], f.lo, f.apex, f.hi, x, point);
    }
    const int from_a = scratch.funnel[0][tangent[0].first], from_b = scratch.funnel[1][tangent[1].first];
    if (cgal::orientation(x, point(from_a), point(from_b)) == CGAL::LEFT_TURN)
      sights.push_back({cx, from_a, from_b});
    if (task.depth + 1 >= max_depth) continue;

    // The two sleeves beyond: across (L, x), edge cw(j), and across (x, R), edge ccw(j), as in
    // grow_shortest_path_tree; each funnel's cusp moves in at most one of them, along one of its chains, and
    // the path from the root to the new cusp must still turn only one way: counter-clockwise from a,
    // clockwise from b.
    for (const bool towards_l : {true, false}) {
      const int edge = towards_l ? cdt.cw(j) : cdt.ccw(j);
      if (is_separator(cdt, g, edge)) continue;
      SleeveTask child{g, edge, task.depth + 1, {}};
      bool open = true;
      for (int s = 0; s < 2 && open; ++s) {
        const SleeveFunnel& f = task.funnel[s];
        const std::vector<int>& funnel = scratch.funnel[s];
        const auto [t, on_left] = tangent[s];
        const auto undo = static_cast<std::uint32_t>(scratch.undo[s].size());
        SleeveFunnel& c = child.funnel[s];
        c = towards_l ? SleeveFunnel{f.lo, on_left ? t : f.apex, t + 1, undo, -1, cx, f.before_cusp}
                      : SleeveFunnel{t - 1, on_left ? f.apex : t, f.hi, undo, cx, -1, f.before_cusp};
        if (c.apex == f.apex) continue;
        // The cusp moves from funnel[f.apex] along a chain to funnel[t]: step is -1 on the L-chain.
        const int step = c.apex < f.apex ? -1 : 1;
        const int first = funnel[f.apex + step];
        if (f.before_cusp >= 0 &&
            cgal::orientation(point(f.before_cusp), point(funnel[f.apex]), point(first)) == kWrongTurn[s])
          open = false;
        else if (c.apex != f.apex + step &&
                 cgal::orientation(point(funnel[f.apex]), point(first), point(funnel[f.apex + 2 * step])) ==
                     kWrongTurn[s])
          open = false;  // the chain is convex: its first turn is every turn's
        c.before_cusp = funnel[c.apex - step];
      }
      if (open) stack.push_back(child);
    }
  }
}

}  // namespace pleat
