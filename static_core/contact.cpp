#include "static_core/contact.hpp"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <unordered_map>
#include <vector>

#include "static_core/internal/cgal_types.hpp"
#include "static_core/union_find.hpp"

namespace pleat {
namespace {

using Point3 = cgal::Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point3>;
using Tree =
    CGAL::AABB_tree<CGAL::AABB_traits<cgal::Kernel, CGAL::AABB_face_graph_triangle_primitive<SurfaceMesh>>>;
using SideOf = CGAL::Side_of_triangle_mesh<SurfaceMesh, cgal::Kernel, CGAL::Default, Tree>;

/// One closed part of the occluders: its triangles as a surface mesh, and the tree that answers distance and
/// inside queries, rebuilt when its vertices moved.
struct Solid {
  SurfaceMesh mesh;
  std::vector<Index> vertex;  ///< per mesh vertex, in order: the topology's
  Tree tree;
  Bounds box;
  bool placed = false;
};

std::uint64_t key(Index a, Index b) { return (std::uint64_t(a) << 32) | b; }

/// The connected parts of the occluders' triangles [begin, end) in which every directed edge is met by its
/// reverse exactly once (closed and consistently wound), as surface meshes.
std::vector<Solid> closed_parts(const MeshTopology& topology, std::size_t begin, std::size_t end) {
  std::vector<int> parent(topology.num_vertices);
  std::iota(parent.begin(), parent.end(), 0);
  std::unordered_map<std::uint64_t, int> directed;  // how often each directed edge occurs
  for (std::size_t f = begin; f < end; ++f) {
    const Triangle& t = topology.triangles[f];
    for (int i = 0; i < 3; ++i) {
      parent[find_root(parent, int(t[i]))] = find_root(parent, int(t[(i + 1) % 3]));
      ++directed[key(t[i], t[(i + 1) % 3])];
    }
  }
  std::unordered_map<int, std::vector<std::size_t>> faces_of;  // by the root of their part
  std::unordered_map<int, bool> closed;
  for (std::size_t f = begin; f < end; ++f) {
    const Triangle& t = topology.triangles[f];
    const int root = find_root(parent, int(t[0]));
    faces_of[root].push_back(f);
    bool& ok = closed.try_emplace(root, true).first->second;
    for (int i = 0; i < 3; ++i) {
      const auto reverse = directed.find(key(t[(i + 1) % 3], t[i]));
      ok = ok && t[i] != t[(i + 1) % 3] && directed[key(t[i], t[(i + 1) % 3])] == 1 &&
           reverse != directed.end() && reverse->second == 1;
    }
  }
  std::vector<int> roots;
  for (const auto& [root, faces] : faces_of)
    if (closed[root]) roots.push_back(root);
  std::sort(roots.begin(), roots.end());  // a deterministic order
  std::vector<Solid> solids;
  for (const int root : roots) {
    Solid solid;
    std::unordered_map<Index, SurfaceMesh::Vertex_index> index;
    bool ok = true;
    for (const std::size_t f : faces_of[root]) {
      std::array<SurfaceMesh::Vertex_index, 3> corners;
      for (int i = 0; i < 3; ++i) {
        const Index v = topology.triangles[f][i];
        auto [at, added] = index.try_emplace(v);
        if (added) {
          at->second = solid.mesh.add_vertex(Point3(0, 0, 0));
          solid.vertex.push_back(v);
        }
        corners[i] = at->second;
      }
      ok = ok && solid.mesh.add_face(corners[0], corners[1], corners[2]) != SurfaceMesh::null_face();
    }
    if (ok) solids.push_back(std::move(solid));  // else non-manifold at a vertex: not a solid we can test
  }
  return solids;
}

/// Places the solid's vertices at `frame`; rebuilds its tree if they moved.
void place(Solid& solid, const Frame& frame) {
  bool moved = !solid.placed;
  for (std::size_t i = 0; i < solid.vertex.size(); ++i) {
    const glm::dvec3& p = frame.positions[solid.vertex[i]];
    Point3& q = solid.mesh.point(SurfaceMesh::Vertex_index(static_cast<SurfaceMesh::size_type>(i)));
    if (q.x() != p.x || q.y() != p.y || q.z() != p.z) {
      q = Point3(p.x, p.y, p.z);
      moved = true;
    }
  }
  if (!moved) return;
  // The tree's search structure for distances is built by its first distance query (CGAL's default).
  solid.tree.rebuild(faces(solid.mesh).first, faces(solid.mesh).second, solid.mesh);
  solid.box = {};
  for (const Index v : solid.vertex) solid.box.add(frame.positions[v]);
  solid.placed = true;
}

bool within(const Bounds& box, const glm::dvec3& p, double margin) {
  for (int a = 0; a < 3; ++a)
    if (!(p[a] > box.lo[a] + margin && p[a] < box.hi[a] - margin)) return false;
  return true;
}

}  // namespace

struct ContactCheck::Impl {
  const MeshTopology& topology;
  std::vector<Solid> solids;
  std::vector<double> depth;  ///< per cloth vertex, this frame's deepest penetration found
};

ContactCheck::ContactCheck(const MeshTopology& topology) : m_impl(new Impl{topology, {}, {}}) {
  const Index receivers = topology.num_receivers();
  std::size_t begin = 0;  // the cloth's triangles come first, then the occluders'
  while (begin < topology.triangles.size() && topology.triangles[begin][0] < receivers) ++begin;
  m_impl->solids = closed_parts(topology, begin, topology.num_sliced_triangles());
}

ContactCheck::~ContactCheck() = default;
ContactCheck::ContactCheck(ContactCheck&&) noexcept = default;
ContactCheck& ContactCheck::operator=(ContactCheck&&) noexcept = default;

void ContactCheck::check(const Frame& frame, VisibilityStats& stats) {
  Impl& m = *m_impl;
  const double tolerance = m.topology.contact_tolerance;
  const Index receivers = m.topology.num_receivers();
  stats.penetrating_vertices = 0;
  stats.deepest_penetration = 0.0;
  stats.deepest_vertex = 0;
  if (m.topology.planes.empty() && m.solids.empty()) return;
  m.depth.assign(receivers, 0.0);
  for (const OccludingPlane& plane : m.topology.planes)
    for (Index v = 0; v < receivers; ++v) m.depth[v] = std::max(m.depth[v], plane.depth(frame.positions[v]));
  for (Solid& solid : m.solids) {
    place(solid, frame);
    const SideOf side(solid.tree);
    for (Index v = 0; v < receivers; ++v) {
      const glm::dvec3& p = frame.positions[v];
      if (!within(solid.box, p, std::max(tolerance, m.depth[v]))) continue;  // cannot be deeper
      const Point3 q(p.x, p.y, p.z);
      if (side(q) != CGAL::ON_BOUNDED_SIDE) continue;  // a ray's crossings: far cheaper than the distance
      const double d2 = solid.tree.squared_distance(q);
      if (d2 > tolerance * tolerance) m.depth[v] = std::max(m.depth[v], std::sqrt(d2));
    }
  }
  for (Index v = 0; v < receivers; ++v) {
    if (!(m.depth[v] > tolerance)) continue;
    ++stats.penetrating_vertices;
    if (m.depth[v] > stats.deepest_penetration) {
      stats.deepest_penetration = m.depth[v];
      stats.deepest_vertex = v;
    }
  }
}

}  // namespace pleat
