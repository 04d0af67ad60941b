#include "static_core/internal/fan_cone.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/geometric.hpp>

namespace pleat {

bool fan_local_ranges(const MeshTopology& topology, const MeshConnectivity& connectivity, const Frame& frame,
                      Index v, const SlicingPlane& plane, std::vector<AngularInterval>& front,
                      std::vector<AngularInterval>& back) {
  front.clear();
  back.clear();
  if (!connectivity.has_closed_fan(v)) {
    front.push_back({0.0, kTwoPi});
    back.push_back({0.0, kTwoPi});
    return true;
  }
  // Each triangle (v, a, b) whose far edge crosses the plane through v bounds the sides along the ray from v
  // to the crossing; the triangle's normal, projected into the plane, points to the front side of that ray.
  struct Crossing {
    double angle;
    bool front_counter_clockwise;  ///< the front side lies counter-clockwise of the ray
  };
  constexpr std::size_t kMaxCrossings = 32;
  std::array<Crossing, kMaxCrossings> crossings;
  std::size_t count = 0;
  const glm::dvec3 apex = frame.positions[v];
  for (const Index f : connectivity.faces_around(v)) {
    const Triangle& t = topology.triangles[f];
    const int k = t[0] == v ? 0 : t[1] == v ? 1 : 2;
    const glm::dvec3 a = frame.positions[t[(k + 1) % 3]] - apex, b = frame.positions[t[(k + 2) % 3]] - apex;
    const double ha = glm::dot(plane.normal, a), hb = glm::dot(plane.normal, b);
    if ((ha > 0) == (hb > 0)) continue;
    if (count == kMaxCrossings) return false;
    const glm::dvec3 p = a + ha / (ha - hb) * (b - a), n = glm::cross(a, b);
    const glm::dvec2 ray(glm::dot(p, plane.u), glm::dot(p, plane.w));
    const glm::dvec2 normal(glm::dot(n, plane.u), glm::dot(n, plane.w));
    if (ray == glm::dvec2(0.0)) return false;
    crossings[count++] = {direction_angle(ray), ray.x * normal.y - ray.y * normal.x > 0};
  }
  if (count == 0 || count % 2 != 0) return false;
  std::sort(crossings.begin(), crossings.begin() + static_cast<long>(count),
            [](const Crossing& x, const Crossing& y) { return x.angle < y.angle; });
  for (std::size_t i = 0; i < count; ++i)
    if (crossings[i].front_counter_clockwise == crossings[(i + 1) % count].front_counter_clockwise)
      return false;
  // Between consecutive crossings the side alternates: a range runs counter-clockwise from a crossing with
  // its side counter-clockwise of it to the next crossing; the one that wraps past 2pi is split there.
  for (std::size_t i = 0; i < count; ++i) {
    std::vector<AngularInterval>& side = crossings[i].front_counter_clockwise ? front : back;
    const double from = crossings[i].angle;
    if (i + 1 < count) {
      side.push_back({from, crossings[i + 1].angle});
    } else {
      side.push_back({from, kTwoPi});
      side.insert(side.begin(), {0.0, crossings[0].angle});
    }
  }
  auto drop_empty = [](std::vector<AngularInterval>& iv) {
    iv.erase(std::remove_if(iv.begin(), iv.end(), [](const AngularInterval& x) { return !(x.hi > x.lo); }),
             iv.end());
  };
  drop_empty(front);
  drop_empty(back);
  return true;
}

glm::dvec2 chain_edge_angles(const Slice& slice, Index x) {
  const std::int32_t outgoing = slice.out_edge[x], incoming = slice.in_edge[x];
  if (outgoing < 0 || incoming < 0) return glm::dvec2(NAN);
  const glm::dvec2 at = slice.vertices[x].point;
  return {direction_angle(slice.vertices[slice.edges[outgoing].to].point - at),
          direction_angle(slice.vertices[slice.edges[incoming].from].point - at)};
}

void mark_whole_fans(const MeshTopology& topology, const MeshConnectivity& connectivity, const Frame& frame,
                     std::span<const glm::dvec3> normals, std::vector<std::uint8_t>& whole) {
  whole.assign(topology.num_vertices, 0);
  for (Index v = 0; v < topology.num_vertices; ++v)
    whole[v] = !connectivity.has_closed_fan(v) && !connectivity.is_isolated(v);
  for (const Triangle& t : topology.triangles) {
    const glm::dvec3& a = frame.positions[t[0]];
    const glm::dvec3 c = glm::cross(frame.positions[t[1]] - a, frame.positions[t[2]] - a);
    const double area = glm::length(c);
    if (!(area > 0)) continue;
    for (const Index v : t)
      if (glm::dot(c, normals[v]) < kSharpFan * area) whole[v] = 1;
  }
}

namespace {

/// The intervals of `wedges` (split_into_intervals), without its sort where they are united already: the
/// one that wraps past 2pi is the last wedge, its piece from 0 the first interval.
void to_intervals(std::span<const Wedge> wedges, std::vector<AngularInterval>& out) {
  if (!is_united(wedges) || (wedges.size() == 1 && wedges[0].width >= kTwoPi - kAngleTolerance)) {
    split_into_intervals(wedges, out);
    return;
  }
  out.clear();
  if (wedges.empty()) return;
  const Wedge& last = wedges.back();
  const bool wraps = last.end() > kTwoPi;
  if (wraps) out.push_back({0.0, last.end() - kTwoPi, INFINITY, last.end_reach});
  for (const Wedge& w : wedges)
    if (wraps && &w == &last)
      out.push_back({w.start, kTwoPi, w.start_reach, INFINITY});
    else
      out.push_back({w.start, w.end(), w.start_reach, w.end_reach});
}

/// a \ b (sorted, disjoint intervals) into `out` (cleared first), sorted.
void subtract(std::span<const AngularInterval> a, std::span<const AngularInterval> b,
              std::vector<AngularInterval>& out) {
  out.clear();
  std::size_t j = 0;
  for (AngularInterval x : a) {
    while (j < b.size() && b[j].hi <= x.lo) ++j;
    for (std::size_t k = j; k < b.size() && b[k].lo < x.hi; ++k) {
      if (b[k].lo - x.lo > kAngleTolerance) out.push_back({x.lo, b[k].lo, x.lo_reach, INFINITY});
      x.lo = std::max(x.lo, b[k].hi), x.lo_reach = INFINITY;
    }
    if (x.hi - x.lo > kAngleTolerance) out.push_back(x);
  }
}

}  // namespace

void fan_cone(std::span<const Index> cuts, const SliceCones& cones, std::span<const glm::dvec2> chain_angles,
              Side side, std::span<const AngularInterval> vertex_range, FanConeScratch& s,
              std::vector<Wedge>& out) {
  out.clear();
  s.todo.assign(vertex_range.begin(), vertex_range.end());  // what no nearer cut's range covered
  s.seen.clear();
  for (const Index x : cuts) {
    if (s.todo.empty()) break;
    const glm::dvec2 angles = chain_angles[x];
    const double from = side == Side::Front ? angles.x : angles.y,
                 to = side == Side::Front ? angles.y : angles.x;
    const Wedge range = std::isnan(from) ? Wedge{0.0, kTwoPi}  // a chain's end
                                         : Wedge{from, to > from ? to - from : to - from + kTwoPi};
    to_intervals(std::span<const Wedge>(&range, 1), s.range);
    to_intervals(cones.cone(x, side), s.cone);
    s.next.clear();
    intersect_intervals(s.range, s.todo, s.next);  // the directions this cut gives
    intersect_intervals(s.cone, s.next, s.seen);
    subtract(s.todo, s.range, s.next);
    s.todo.swap(s.next);
  }
  std::sort(s.seen.begin(), s.seen.end(),
            [](const AngularInterval& a, const AngularInterval& b) { return a.lo < b.lo; });
  merge_into_wedges(s.seen, out);
}

}  // namespace pleat
