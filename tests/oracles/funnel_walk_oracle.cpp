#include "oracles/funnel_walk_oracle.hpp"

#include <stdexcept>

namespace pleat::test {

void walk_shortest_path_tree(const SliceTriangulation& slice, const SliceWindow& window, bool from_b,
                             std::vector<int>& parent) {
  // One funnel still to expand: cross the edge (face, index) with cusp `apex`.
  struct Task {
    cgal::FaceHandle face;
    int index = 0;
    int apex = -1;
  };
  std::vector<Task> stack;
  const cgal::Cdt& cdt = slice.cdt();
  const int root_index = from_b ? cdt.cw(window.index) : cdt.ccw(window.index);
  const int root = from_b ? window.corner_b : window.corner_a;
  const cgal::VertexHandle root_vertex = window.face->vertex(root_index);
  auto point = [&](int corner) -> const cgal::Point2& { return slice.corner_vertex(corner)->point(); };
  parent[root] = root;

  // The root's fan: every triangle of the root corner sees the root directly.
  {
    auto fc = cdt.incident_faces(root_vertex), done = fc;
    do {
      const cgal::FaceHandle f = fc;
      if (cdt.is_infinite(f)) continue;
      const int i = f->index(root_vertex);
      if (f->info().corner[i] != root) continue;
      parent[f->info().corner[cdt.ccw(i)]] = root;
      parent[f->info().corner[cdt.cw(i)]] = root;
      if (!is_separator(cdt, f, i)) stack.push_back({f, i, root});
    } while (++fc != done);
  }

  while (!stack.empty()) {
    const Task task = stack.back();
    stack.pop_back();
    const cgal::FaceHandle g = task.face->neighbor(task.index);
    const int j = cdt.mirror_index(task.face, task.index);
    // Seen from the funnel, L = g->vertex(ccw(j)) is on the left and R = g->vertex(cw(j)) on the right.
    const int cl = g->info().corner[cdt.ccw(j)], cr = g->info().corner[cdt.cw(j)], cx = g->info().corner[j];
    const cgal::Point2& x = g->vertex(j)->point();
    // Left chain: x wraps around z when (parent(z), z, x) turns left or is straight; right chain: mirrored.
    auto walk = [&](int from, CGAL::Orientation wrong_turn) {
      for (int z = from; z != task.apex; z = parent[z]) {
        if (z == parent[z]) throw std::logic_error("funnel chain does not reach its cusp");
        if (CGAL::orientation(point(parent[z]), point(z), x) != wrong_turn) return z;
      }
      return -1;
    };
    int tangent = walk(cl, CGAL::RIGHT_TURN);
    const bool on_left = tangent >= 0;
    if (!on_left) tangent = walk(cr, CGAL::LEFT_TURN);
    if (tangent < 0) tangent = task.apex;
    parent[cx] = tangent;
    // Edge (L, x) is opposite R (index cw(j)); edge (x, R) is opposite L (index ccw(j)).
    const int apex_left = on_left ? tangent : task.apex;
    const int apex_right = (!on_left && tangent != task.apex) ? tangent : task.apex;
    if (!is_separator(cdt, g, cdt.cw(j))) stack.push_back({g, cdt.cw(j), apex_left});
    if (!is_separator(cdt, g, cdt.ccw(j))) stack.push_back({g, cdt.ccw(j), apex_right});
  }
}

}  // namespace pleat::test
