#include "static_core/cone_assembly.hpp"

#include "static_core/cgal_types.hpp"

#include <CGAL/convex_hull_2.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace pleat {
namespace {

constexpr double kHalfPi = kTwoPi / 4;
constexpr double kContainTolerance = 1e-9;

struct SpatialWedge {
  const SlicingPlane* plane;
  double start, end;  // angles in the plane's frame, end > start
  glm::dvec3 direction(double angle) const { return std::cos(angle) * plane->u + std::sin(angle) * plane->w; }
  bool contains(const glm::dvec3& d) const {
    double a = std::atan2(glm::dot(d, plane->w), glm::dot(d, plane->u)) - start;
    a = a - kTwoPi * std::floor(a / kTwoPi);
    return a <= end - start + kContainTolerance || kTwoPi - a <= kContainTolerance;
  }
};

bool share_more_than_apex(const SpatialWedge& a, const SpatialWedge& b) {
  const glm::dvec3 line = glm::cross(a.plane->normal, b.plane->normal);
  if (glm::length(line) < 1e-12) {
    // Coplanar: the arcs overlap when one holds a point of the other.
    for (const SpatialWedge* p : {&a, &b}) {
      const SpatialWedge* q = p == &a ? &b : &a;
      for (double t : {0.0, 0.5, 1.0})
        if (q->contains(p->direction(p->start + t * (p->end - p->start)))) return true;
    }
    return false;
  }
  const glm::dvec3 l = glm::normalize(line);
  return (a.contains(l) && b.contains(l)) || (a.contains(-l) && b.contains(-l));
}

int find_root(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

VisibilityCone assemble_cone(std::span<const PlanarCone> cones, const glm::dvec3& side_normal) {
  // 1. Clip every wedge to the side's half-space and lift it into space.
  std::vector<SpatialWedge> wedges;
  for (const PlanarCone& cone : cones) {
    const SlicingPlane& plane = *cone.plane;
    const glm::dvec2 m(glm::dot(plane.u, side_normal), glm::dot(plane.w, side_normal));
    AngularSet set = AngularSet::from_wedges({cone.wedges.begin(), cone.wedges.end()});
    if (glm::length(m) > 1e-9) {
      const double facing = direction_angle(m);
      set = set.intersect(AngularSet::from_wedges({{wrap_angle(facing - kHalfPi), 2 * kHalfPi}}));
    }
    for (const Wedge& w : set.wedges())
      if (w.width > kContainTolerance) wedges.push_back({&plane, w.start, w.end()});
  }
  // 2. Group by intersection (union-find).
  const int k = static_cast<int>(wedges.size());
  std::vector<int> parent(k);
  std::iota(parent.begin(), parent.end(), 0);
  for (int i = 0; i < k; ++i)
    for (int j = i + 1; j < k; ++j)
      if (find_root(parent, i) != find_root(parent, j) && share_more_than_apex(wedges[i], wedges[j]))
        parent[find_root(parent, i)] = find_root(parent, j);
  // 3. One piece per group: project, hull, centroid, radial sort, lift.
  const glm::dvec3 t1 = glm::normalize(std::abs(side_normal.x) < 0.9
                                           ? glm::cross(side_normal, glm::dvec3(1, 0, 0))
                                           : glm::cross(side_normal, glm::dvec3(0, 1, 0)));
  const glm::dvec3 t2 = glm::cross(side_normal, t1);  // (t1, t2, side_normal) right-handed
  VisibilityCone result;
  std::vector<glm::dvec3> directions;
  std::vector<cgal::Point2> projected, hull;
  for (int root = 0; root < k; ++root) {
    if (find_root(parent, root) != root) continue;
    directions.clear();
    for (int i = 0; i < k; ++i)
      if (find_root(parent, i) == root) {
        directions.push_back(wedges[i].direction(wedges[i].start));
        directions.push_back(wedges[i].direction(wedges[i].end));
      }
    projected.clear();
    for (const auto& d : directions) projected.emplace_back(glm::dot(d, t1), glm::dot(d, t2));
    hull.clear();
    CGAL::convex_hull_2(projected.begin(), projected.end(), std::back_inserter(hull));
    // Area centroid of the hull polygon (vertex mean when it is degenerate).
    double area = 0, cx = 0, cy = 0;
    for (std::size_t i = 0; i < hull.size(); ++i) {
      const auto& p = hull[i];
      const auto& q = hull[(i + 1) % hull.size()];
      const double cross = p.x() * q.y() - q.x() * p.y();
      area += cross;
      cx += (p.x() + q.x()) * cross;
      cy += (p.y() + q.y()) * cross;
    }
    if (std::abs(area) > 1e-14) {
      cx /= 3 * area;
      cy /= 3 * area;
    } else {
      cx = cy = 0;
      for (const auto& p : projected) cx += p.x(), cy += p.y();
      cx /= projected.size();
      cy /= projected.size();
    }
    std::vector<std::pair<double, int>> order;
    for (std::size_t i = 0; i < projected.size(); ++i)
      order.emplace_back(std::atan2(projected[i].y() - cy, projected[i].x() - cx), static_cast<int>(i));
    std::sort(order.begin(), order.end());
    SphericalPolygon piece;
    for (const auto& [angle, i] : order) {
      const glm::dvec3 d = glm::normalize(directions[i]);
      if (!piece.empty() && glm::dot(piece.back(), d) > 1 - 1e-15) continue;
      piece.push_back(d);
    }
    while (piece.size() > 1 && glm::dot(piece.back(), piece.front()) > 1 - 1e-15) piece.pop_back();
    if (piece.size() >= 3) result.pieces.push_back(std::move(piece));
  }
  return result;
}

ConeMeasures measure_cone(const VisibilityCone& cone, const glm::dvec3& side_normal) {
  ConeMeasures m;
  glm::dvec3 moment(0.0);
  double projected = 0.0;
  for (const auto& piece : cone.pieces) {
    const SphericalPolygon clipped = clip_to_hemisphere(piece, side_normal);
    if (clipped.size() >= 3) {
      projected += projected_solid_angle(clipped, side_normal);
      moment += cosine_weighted_moment(clipped, side_normal);
    }
    m.solid_angle += solid_angle(piece);
  }
  m.sky_visibility = std::clamp(projected / (kTwoPi / 2), 0.0, 1.0);
  const double len = glm::length(moment);
  m.bent_normal = len > 1e-15 ? moment / len : side_normal;
  return m;
}

}  // namespace pleat
