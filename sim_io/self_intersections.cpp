// Self-intersection check of one frame: which face pairs meet other than along a shared edge or vertex.
//
// Two paths, one answer:
//  - the mesh is a consistently oriented manifold (the usual cloth): it goes into a CGAL::Surface_mesh and
//    CGAL::Polygon_mesh_processing::self_intersections does the work (box_intersection_d + exact filtered
//    predicates, shared edges and vertices recognized from the halfedge structure);
//  - anything a Surface_mesh cannot hold (non-manifold edges or vertices, inconsistent winding, a face with a
//    repeated index): the same test on the triangle soup, written here because CGAL 5.5 has no
//    triangle_soup_self_intersections. Adjacency comes from shared vertex indices instead of halfedges.
// Both use exact predicates of CGAL::Epick (no epsilon decides anything). Degenerate faces (collinear corners
// or a repeated index) are skipped. Cost: O((n + k) log n) for n faces and k overlapping bounding boxes.
#include "sim_io/self_intersections.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <array>
#include <iterator>
#include <stdexcept>
#include <string>

namespace pleat {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using FacePairs = std::vector<std::pair<Index, Index>>;

std::vector<Point> to_points(const Frame& frame) {
  std::vector<Point> points;
  points.reserve(frame.positions.size());
  for (const auto& p : frame.positions) points.emplace_back(p.x, p.y, p.z);
  return points;
}

bool has_repeated_index(const Triangle& t) { return t[0] == t[1] || t[1] == t[2] || t[0] == t[2]; }

void normalize(FacePairs& pairs) {
  for (auto& [a, b] : pairs)
    if (b < a) std::swap(a, b);
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
}

// The manifold path: Polygon_mesh_processing on a Surface_mesh whose face i is triangle i.
FacePairs intersect_as_surface_mesh(const std::vector<Point>& points,
                                    const std::vector<Triangle>& triangles) {
  SurfaceMesh mesh;
  mesh.reserve(static_cast<SurfaceMesh::size_type>(points.size()),
               static_cast<SurfaceMesh::size_type>(3 * triangles.size()),
               static_cast<SurfaceMesh::size_type>(triangles.size()));
  std::vector<SurfaceMesh::Vertex_index> vertex(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) vertex[i] = mesh.add_vertex(points[i]);
  // A fresh Surface_mesh numbers faces in insertion order; the map below does not rely on it.
  auto [triangle_of, created] = mesh.add_property_map<SurfaceMesh::Face_index, Index>("f:pleat_triangle", 0);
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    const auto& t = triangles[i];
    const std::array<SurfaceMesh::Vertex_index, 3> corners = {vertex[t[0]], vertex[t[1]], vertex[t[2]]};
    const auto f = CGAL::Euler::add_face(corners, mesh);
    if (f == SurfaceMesh::null_face()) return {};  // unreachable after is_polygon_soup_a_polygon_mesh
    triangle_of[f] = static_cast<Index>(i);
  }
  std::vector<std::pair<SurfaceMesh::Face_index, SurfaceMesh::Face_index>> found;
  CGAL::Polygon_mesh_processing::self_intersections(mesh, std::back_inserter(found));
  FacePairs pairs;
  pairs.reserve(found.size());
  for (const auto& [f, g] : found)
    if (f != g) pairs.emplace_back(triangle_of[f], triangle_of[g]);  // (f, f) marks a degenerate face
  return pairs;
}

// Exact test of two non-degenerate triangles given by vertex indices: do they meet other than in the
// vertices and edges they share?
bool do_soup_faces_intersect(const Triangle& a, const Triangle& b, const std::vector<Point>& points) {
  std::array<int, 3> b_slot_of_a = {-1, -1, -1};  // for each corner of a, its slot in b, or -1
  int shared = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (a[i] == b[j]) {
        b_slot_of_a[i] = j;
        ++shared;
      }
  const auto P = [&](Index v) -> const Point& { return points[v]; };
  if (shared == 3) return true;  // the same triangle twice: they overlap entirely
  if (shared == 2) {
    // Sharing edge (u, w): they overlap beyond it only if coplanar with the far corners on the same side.
    int ia = 0;
    while (b_slot_of_a[ia] != -1) ++ia;  // a's corner not in b
    int jb = 0;
    while (jb == b_slot_of_a[0] || jb == b_slot_of_a[1] || jb == b_slot_of_a[2]) ++jb;
    const Point& u = P(a[(ia + 1) % 3]);
    const Point& w = P(a[(ia + 2) % 3]);
    const Point& p = P(a[ia]);
    const Point& q = P(b[jb]);
    return CGAL::coplanar(u, w, p, q) && CGAL::coplanar_orientation(u, w, p, q) == CGAL::POSITIVE;
  }
  const Kernel::Triangle_3 ta(P(a[0]), P(a[1]), P(a[2]));
  const Kernel::Triangle_3 tb(P(b[0]), P(b[1]), P(b[2]));
  if (shared == 1) {
    // Sharing vertex v: they meet elsewhere iff the edge opposite v in one meets the other triangle.
    int ia = 0;
    while (b_slot_of_a[ia] == -1) ++ia;
    const int jb = b_slot_of_a[ia];
    const Kernel::Segment_3 opposite_a(P(a[(ia + 1) % 3]), P(a[(ia + 2) % 3]));
    const Kernel::Segment_3 opposite_b(P(b[(jb + 1) % 3]), P(b[(jb + 2) % 3]));
    return CGAL::do_intersect(opposite_a, tb) || CGAL::do_intersect(opposite_b, ta);
  }
  return CGAL::do_intersect(ta, tb);
}

// The general path: a triangle soup (non-manifold edges, inconsistent winding, repeated indices).
FacePairs intersect_as_soup(const std::vector<Point>& points, const std::vector<Triangle>& triangles) {
  using Box =
      CGAL::Box_intersection_d::Box_with_info_d<double, 3, Index, CGAL::Box_intersection_d::ID_EXPLICIT>;
  std::vector<Box> boxes;
  boxes.reserve(triangles.size());
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    const auto& t = triangles[i];
    if (has_repeated_index(t) || CGAL::collinear(points[t[0]], points[t[1]], points[t[2]])) continue;
    boxes.emplace_back(points[t[0]].bbox() + points[t[1]].bbox() + points[t[2]].bbox(),
                       static_cast<Index>(i));
  }
  FacePairs pairs;
  CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& x, const Box& y) {
    if (do_soup_faces_intersect(triangles[x.info()], triangles[y.info()], points))
      pairs.emplace_back(x.info(), y.info());
  });
  return pairs;
}

}  // namespace

std::vector<std::pair<Index, Index>> self_intersecting_faces(const MeshTopology& topology,
                                                             const Frame& frame) {
  // Input is validated where it enters (sim_io readers); a mismatch here is a caller's bug.
  for (const auto& t : topology.triangles)
    for (Index v : t)
      if (v >= frame.positions.size())
        throw std::invalid_argument("self_intersecting_faces: vertex index " + std::to_string(v) +
                                    " out of range (frame has " + std::to_string(frame.positions.size()) +
                                    " positions)");
  const std::vector<Point> points = to_points(frame);
  FacePairs pairs;
  if (CGAL::Polygon_mesh_processing::is_polygon_soup_a_polygon_mesh(topology.triangles))
    pairs = intersect_as_surface_mesh(points, topology.triangles);
  else
    pairs = intersect_as_soup(points, topology.triangles);
  normalize(pairs);
  return pairs;
}

}  // namespace pleat
