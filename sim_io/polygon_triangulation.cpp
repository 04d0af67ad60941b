#include "sim_io/polygon_triangulation.hpp"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Constrained_triangulation_face_base_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_data_structure_2.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <optional>
#include <queue>

namespace pleat {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point2 = Kernel::Point_2;
using Vb = CGAL::Triangulation_vertex_base_with_info_2<std::size_t, Kernel>;  // the corner
using Fbb = CGAL::Triangulation_face_base_with_info_2<int, Kernel>;           // nesting depth, -1 unseen
using Fb = CGAL::Constrained_triangulation_face_base_2<Kernel, Fbb>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
// Crossing edges would need new vertices: CGAL throws instead, and the polygon keeps its fan.
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::No_constraint_intersection_tag>;
using Triangles = std::vector<std::array<std::size_t, 3>>;

Triangles fan(std::size_t n) {
  Triangles triangles;
  for (std::size_t k = 1; k + 1 < n; ++k) triangles.push_back({0, k, k + 1});
  return triangles;
}

/// The corners in the plane normal to the Newell vector, as (u, w) coordinates with (u, w, normal)
/// right-handed, so the polygon winds counter-clockwise; nullopt when the Newell vector is zero (no area).
std::optional<std::vector<Point2>> project_on_plane(std::span<const glm::dvec3> corners) {
  const std::size_t n = corners.size();
  glm::dvec3 newell(0.0);
  for (std::size_t k = 0; k < n; ++k) {
    const glm::dvec3 a = corners[k] - corners[0], b = corners[(k + 1) % n] - corners[0];
    newell += glm::cross(a, b);
  }
  const double length = glm::length(newell);
  if (!(length > 0.0) || !std::isfinite(length)) return std::nullopt;
  const glm::dvec3 normal = newell / length;
  const glm::dvec3 other = std::abs(normal.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 u = glm::normalize(glm::cross(other, normal));
  const glm::dvec3 w = glm::cross(normal, u);
  std::vector<Point2> points;
  points.reserve(n);
  for (const glm::dvec3& c : corners)
    points.emplace_back(glm::dot(u, c - corners[0]), glm::dot(w, c - corners[0]));
  return points;
}

/// True when the fan from corner 0 tiles the counter-clockwise polygon: every fan triangle turns left and
/// every corner lies strictly left of the line through corners 0 and 1 (the fan sweeps less than half a
/// turn).
bool fan_tiles(const std::vector<Point2>& p) {
  for (std::size_t k = 1; k + 1 < p.size(); ++k) {
    if (CGAL::orientation(p[0], p[k], p[k + 1]) != CGAL::LEFT_TURN) return false;
    if (CGAL::orientation(p[0], p[1], p[k + 1]) != CGAL::LEFT_TURN) return false;
  }
  return true;
}

/// Sets each finite face's info to its nesting depth (the polygon edges crossed from the infinite face).
void mark_depths(Cdt& cdt) {
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info() = -1;
  std::queue<Cdt::Face_handle> next;
  cdt.infinite_face()->info() = 0;
  next.push(cdt.infinite_face());
  while (!next.empty()) {
    const Cdt::Face_handle f = next.front();
    next.pop();
    for (int i = 0; i < 3; ++i) {
      const Cdt::Face_handle g = f->neighbor(i);
      if (g->info() != -1) continue;
      g->info() = f->info() + (f->is_constrained(i) ? 1 : 0);
      next.push(g);
    }
  }
}

/// The constrained Delaunay triangulation of a counter-clockwise polygon's inside; nullopt when it is not a
/// simple polygon (corners that coincide, edges that cross, a corner on another edge).
std::optional<Triangles> triangulate_inside(const std::vector<Point2>& points) {
  const std::size_t n = points.size();
  Cdt cdt;
  std::vector<Cdt::Vertex_handle> vertices;
  vertices.reserve(n);
  for (std::size_t k = 0; k < n; ++k) {
    vertices.push_back(cdt.insert(points[k]));
    vertices.back()->info() = k;
  }
  if (cdt.number_of_vertices() != n || cdt.dimension() != 2) return std::nullopt;
  try {
    for (std::size_t k = 0; k < n; ++k) cdt.insert_constraint(vertices[k], vertices[(k + 1) % n]);
  } catch (const Cdt::Intersection_of_constraints_exception&) {
    return std::nullopt;
  }
  for (std::size_t k = 0; k < n; ++k)
    if (!cdt.is_edge(vertices[k], vertices[(k + 1) % n])) return std::nullopt;  // split at a corner on it
  mark_depths(cdt);
  Triangles triangles;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
    if (f->info() % 2 == 1)
      triangles.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
  if (triangles.size() != n - 2) return std::nullopt;
  return triangles;
}

}  // namespace

Triangles triangulate_polygon(std::span<const glm::dvec3> corners) {
  const std::size_t n = corners.size();
  if (n <= 3) return fan(n);
  const std::optional<std::vector<Point2>> points = project_on_plane(corners);
  if (!points || fan_tiles(*points)) return fan(n);
  std::optional<Triangles> inside = triangulate_inside(*points);
  return inside ? std::move(*inside) : fan(n);
}

}  // namespace pleat
