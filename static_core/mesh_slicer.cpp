#include "static_core/mesh_slicer.hpp"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <numeric>

#include "static_core/assert.hpp"
#include "static_core/internal/cgal_types.hpp"

namespace pleat {

void Slice::clear() {
  vertices.clear();
  edges.clear();
  out_edge.clear();
  in_edge.clear();
}

bool on_or_above_exact(const SlicingPlane& plane, const glm::dvec3& p) {
  const cgal::Kernel::Plane_3 h(plane.normal.x, plane.normal.y, plane.normal.z, -plane.offset);
  return h.oriented_side(cgal::Kernel::Point_3(p.x, p.y, p.z)) != CGAL::ON_NEGATIVE_SIDE;
}

bool on_or_above(const SlicingPlane& plane, const glm::dvec3& p) {
  // A semi-static filter in front of CGAL's exact predicate. The rounded d = (x + y + z) - offset of the
  // products x = n.x p.x, ... differs from the exact value by at most 4u / (1 - 4u) times the sum of the
  // terms' magnitudes (u = 2^-53: three roundings of products, three of sums); 8u times the rounded sum
  // covers that and the rounding of the sum itself. Below a magnitude of 1e-290 an underflowed product
  // could break the relative bound, and a non-finite term makes the comparison false: both go to CGAL.
  constexpr double kBound = 8.0 * 0x1p-53;
  const double x = plane.normal.x * p.x, y = plane.normal.y * p.y, z = plane.normal.z * p.z;
  const double d = ((x + y) + z) - plane.offset;
  const double magnitude = ((std::abs(x) + std::abs(y)) + std::abs(z)) + std::abs(plane.offset);
  if (magnitude > 1e-290 && std::abs(d) > kBound * magnitude) return d > 0;
  return on_or_above_exact(plane, p);
}

namespace {

/// Takes the slice vertices on flat edges out of `out` (see slice_mesh): each chain edge that leaves a kept
/// vertex is followed through flat vertices to the next kept one; the kept vertices are renumbered in order.
void run_through_flat_edges(std::span<const std::uint8_t> flat_edges, SlicerScratch& scratch, Slice& out) {
  auto& flat = scratch.flat;
  flat.assign(out.vertices.size(), 0);
  std::size_t dropped = 0;
  for (std::size_t x = 0; x < out.vertices.size(); ++x)
    if (flat_edges[out.vertices[x].edge] && out.in_edge[x] >= 0 && out.out_edge[x] >= 0)
      flat[x] = 1, ++dropped;
  if (dropped == 0) return;
  auto& new_index = scratch.new_index;
  new_index.assign(out.vertices.size(), -1);
  std::size_t kept = 0;
  for (std::size_t x = 0; x < out.vertices.size(); ++x)
    if (!flat[x]) {
      new_index[x] = static_cast<std::int32_t>(kept);
      out.vertices[kept++] = out.vertices[x];
    }
  auto& edges = scratch.edges;  // out.edges is read by the walks below while they run
  edges.clear();
  std::size_t passed = 0;
  for (const SliceEdge& first : out.edges) {
    if (flat[first.from]) continue;  // inside a straight run: the run's first edge carries it
    // A flat vertex has one edge in and one out (its edge has two faces, both cut): the run is a path.
    Index to = first.to;
    for (; flat[to]; ++passed) to = out.edges[out.out_edge[to]].to;
    edges.push_back({Index(new_index[first.from]), Index(new_index[to]), first.face});
  }
  // Every flat crossing lies inside a run from a kept vertex (the faces of a run lie in one plane and do not
  // fold, so its chain goes one way along a line and cannot close on itself).
  PLEAT_ASSERT(passed == dropped, "slice_mesh: a closed chain of flat crossings");
  out.edges.swap(edges);
  out.vertices.resize(kept);
}

}  // namespace

void flat_occluder_edges(const MeshTopology& topology, const MeshConnectivity& connectivity,
                         const Frame& frame, std::vector<std::uint8_t>& flat) {
  flat.assign(connectivity.num_edges(), 0);
  if (topology.num_occluder_vertices == 0) return;
  const Index first_occluder = topology.num_receivers();
  // An occluder's faces use its vertices alone, and edges are sorted by their smaller endpoint: the
  // occluders' edges are the last ones, from `first_edge` on.
  const auto& endpoints = connectivity.endpoints();
  const std::size_t first_edge =
      std::size_t(std::partition_point(endpoints.begin(), endpoints.end(),
                                       [&](const std::array<Index, 2>& e) { return e[0] < first_occluder; }) -
                  endpoints.begin());
  // Per occluder edge, the corner opposite it in each of its (two) faces.
  std::vector<std::array<std::int32_t, 2>> opposite(endpoints.size() - first_edge, {-1, -1});
  for (Index f = 0; f < topology.num_sliced_triangles(); ++f) {
    const Triangle& t = topology.triangles[f];
    if (t[0] < first_occluder) continue;
    for (int i = 0; i < 3; ++i) {
      const Index e = connectivity.of_face()[f][i];  // (t[i], t[i + 1]): opposite t[i + 2]
      if (connectivity.kind(e) != EdgeKind::Interior) continue;
      auto& o = opposite[e - first_edge];
      (o[0] < 0 ? o[0] : o[1]) = static_cast<std::int32_t>(t[(i + 2) % 3]);
    }
  }
  auto point = [&](Index v) {
    const glm::dvec3& p = frame.positions[v];
    return cgal::Kernel::Point_3(p.x, p.y, p.z);
  };
  for (std::size_t e = first_edge; e < endpoints.size(); ++e) {
    const auto [c, d] = opposite[e - first_edge];
    if (d < 0) continue;
    const auto a = point(endpoints[e][0]), b = point(endpoints[e][1]);
    const auto pc = point(Index(c)), pd = point(Index(d));
    if (CGAL::collinear(a, b, pc) || CGAL::orientation(a, b, pc, pd) != CGAL::COPLANAR) continue;
    // In the plane of a, b, c: d on the other side of the line ab (not folded onto c's face, not on the
    // line).
    flat[e] = CGAL::coplanar_orientation(a, b, pc, pd) == CGAL::NEGATIVE;
  }
}

void slice_mesh(const MeshTopology& topology, const MeshConnectivity& connectivity, const Frame& frame,
                const SlicingPlane& plane, std::span<const Index> candidate_faces, SlicerScratch& scratch,
                Slice& out, std::span<const std::uint8_t> flat_edges) {
  out.clear();
  auto& vertex_of_edge = scratch.slice_vertex_of_edge;
  if (vertex_of_edge.size() != connectivity.num_edges()) vertex_of_edge.assign(connectivity.num_edges(), -1);
  const auto& pos = frame.positions;
  const auto& of_face = connectivity.of_face();

  auto slice_vertex = [&](Index edge, Index above, Index below) -> Index {
    std::int32_t& id = vertex_of_edge[edge];
    if (id >= 0) return static_cast<Index>(id);
    SliceVertex sv;
    sv.edge = edge;
    sv.above = above;
    sv.below = below;
    const double sa = glm::dot(plane.normal, pos[above]) - plane.offset;
    const double sb = glm::dot(plane.normal, pos[below]) - plane.offset;
    // sa >= 0 > sb in exact arithmetic; the rounded values are clamped into [0, 1].
    const double denom = sa - sb;
    sv.t = denom > 0 ? std::clamp(sa / denom, 0.0, 1.0) : 0.0;
    const glm::dvec3 p = pos[above] + sv.t * (pos[below] - pos[above]);
    sv.point = {glm::dot(plane.u, p), glm::dot(plane.w, p)};
    const double length = glm::distance(pos[above], pos[below]);
    if (sv.t < 0.5 || (sv.t == 0.5 && above < below)) {
      sv.nearer = above;
      sv.distance = sv.t * length;
    } else {
      sv.nearer = below;
      sv.distance = (1.0 - sv.t) * length;
    }
    id = static_cast<std::int32_t>(out.vertices.size());
    out.vertices.push_back(sv);
    return static_cast<Index>(id);
  };

  for (Index f : candidate_faces) {
    const Triangle& t = topology.triangles[f];
    const bool up[3] = {on_or_above(plane, pos[t[0]]), on_or_above(plane, pos[t[1]]),
                        on_or_above(plane, pos[t[2]])};
    const int ups = up[0] + up[1] + up[2];
    if (ups == 0 || ups == 3) continue;
    // The lone vertex i is the one on the other side from the two others.
    int i = 0;
    for (int k = 0; k < 3; ++k)
      if ((ups == 1) == up[k]) i = k;
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    const Index lone = t[i];
    // Crossing points on edges (t[i], t[j]) and (t[k], t[i]).
    const Index on_ij =
        up[i] ? slice_vertex(of_face[f][i], lone, t[j]) : slice_vertex(of_face[f][i], t[j], lone);
    const Index on_ki =
        up[i] ? slice_vertex(of_face[f][k], lone, t[k]) : slice_vertex(of_face[f][k], t[k], lone);
    // With (u, w, normal) right-handed, the front (face normal) side is to the right of on_ij -> on_ki
    // when the lone vertex is above, and to the left when it is below.
    SliceEdge e;
    e.face = f;
    e.from = up[i] ? on_ki : on_ij;
    e.to = up[i] ? on_ij : on_ki;
    out.edges.push_back(e);
  }
  for (const auto& sv : out.vertices) vertex_of_edge[sv.edge] = -1;

  auto link = [&] {
    out.out_edge.assign(out.vertices.size(), -1);
    out.in_edge.assign(out.vertices.size(), -1);
    for (std::size_t e = 0; e < out.edges.size(); ++e) {
      if (out.out_edge[out.edges[e].from] < 0) out.out_edge[out.edges[e].from] = static_cast<std::int32_t>(e);
      if (out.in_edge[out.edges[e].to] < 0) out.in_edge[out.edges[e].to] = static_cast<std::int32_t>(e);
    }
  };
  link();
  if (!flat_edges.empty()) {
    const std::size_t before = out.vertices.size();
    run_through_flat_edges(flat_edges, scratch, out);
    if (out.vertices.size() != before) link();
  }
}

std::vector<Index> cone_recipients(const MeshTopology& topology, const MeshConnectivity& connectivity,
                                   const Frame& frame, const SlicingPlane& plane) {
  std::vector<Index> faces(topology.num_sliced_triangles());
  std::iota(faces.begin(), faces.end(), 0);
  SlicerScratch scratch;
  Slice slice;
  slice_mesh(topology, connectivity, frame, plane, faces, scratch, slice);
  std::vector<Index> result;
  for (const auto& sv : slice.vertices) result.push_back(sv.nearer);
  std::sort(result.begin(), result.end());
  result.erase(std::unique(result.begin(), result.end()), result.end());
  return result;
}

PlaneFaces split_faces(const MeshTopology& topology, std::span<const Index> faces) {
  const Index receivers = topology.num_receivers();
  const auto first = std::partition_point(faces.begin(), faces.end(),
                                          [&](Index f) { return topology.triangles[f][0] < receivers; });
  const std::size_t cloth = static_cast<std::size_t>(first - faces.begin());
  return {faces.first(cloth), faces.subspan(cloth)};
}

std::vector<std::vector<Index>> candidate_faces_per_plane(const MeshTopology& topology, const Frame& frame,
                                                          const SlicingPlan& plan) {
  std::vector<std::vector<Index>> result;
  candidate_faces_per_plane(topology, frame, plan, result);
  return result;
}

void candidate_faces_per_plane(const MeshTopology& topology, const Frame& frame, const SlicingPlan& plan,
                               std::vector<std::vector<Index>>& result, std::span<const char> only) {
  result.resize(plan.planes.size());
  for (auto& faces_of_plane : result) faces_of_plane.clear();  // keeps their capacity from frame to frame
  const std::size_t faces = topology.num_sliced_triangles();
  for (int o = 0; o < static_cast<int>(plan.orientations.size()); ++o) {
    std::vector<std::pair<double, Index>> planes;  // (offset, plane index) of this family
    glm::dvec3 normal(0.0);
    bool parallel = true;
    for (Index p = 0; p < plan.planes.size(); ++p) {
      if (plan.planes[p].orientation != o || (!only.empty() && !only[p])) continue;
      if (planes.empty())
        normal = plan.planes[p].normal;
      else if (plan.planes[p].normal != normal)
        parallel = false;
      planes.emplace_back(plan.planes[p].offset, p);
    }
    if (planes.empty()) continue;
    if (!parallel) {
      for (const auto& [offset, p] : planes) {
        result[p].resize(faces);
        std::iota(result[p].begin(), result[p].end(), 0);
      }
      continue;
    }
    std::sort(planes.begin(), planes.end());
    std::vector<double> height(frame.positions.size());
    double scale = 0.0;
    for (std::size_t v = 0; v < height.size(); ++v) {
      height[v] = glm::dot(normal, frame.positions[v]);
      scale = std::max(scale, std::abs(height[v]));
    }
    const double margin = 1e-9 * (1.0 + scale);  // far above the rounding of a dot product
    for (Index f = 0; f < faces; ++f) {
      const Triangle& t = topology.triangles[f];
      const double lo = std::min({height[t[0]], height[t[1]], height[t[2]]}) - margin;
      const double hi = std::max({height[t[0]], height[t[1]], height[t[2]]}) + margin;
      auto it = std::lower_bound(planes.begin(), planes.end(), std::make_pair(lo, Index(0)));
      for (; it != planes.end() && it->first <= hi; ++it) result[it->second].push_back(f);
    }
  }
}

}  // namespace pleat
