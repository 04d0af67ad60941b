#include "oracles/test_meshes.hpp"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <map>

namespace pleat::test {

TestMesh flat_sheet(int nx, int ny, double spacing, glm::dvec2 origin) {
  TestMesh m;
  m.topology.num_vertices = static_cast<Index>(nx * ny);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      m.frame.positions.emplace_back(origin.x + spacing * i, origin.y + spacing * j, 0.0);
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      const Index a = j * nx + i, b = a + 1, c = a + nx, d = c + 1;
      m.topology.triangles.push_back({a, b, d});
      m.topology.triangles.push_back({a, d, c});
    }
  return m;
}

TestMesh icosphere(int subdivisions) {
  TestMesh m;
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<glm::dvec3> p = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                               {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (auto& q : p) q = glm::normalize(q);
  std::vector<Triangle> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                             {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                             {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                             {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<Index, Index>, Index> mid;
    auto midpoint = [&](Index a, Index b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      p.push_back(glm::normalize(p[a] + p[b]));
      return mid[key] = static_cast<Index>(p.size() - 1);
    };
    std::vector<Triangle> g;
    for (const auto& tri : f) {
      const Index ab = midpoint(tri[0], tri[1]), bc = midpoint(tri[1], tri[2]), ca = midpoint(tri[2], tri[0]);
      g.push_back({tri[0], ab, ca});
      g.push_back({tri[1], bc, ab});
      g.push_back({tri[2], ca, bc});
      g.push_back({ab, bc, ca});
    }
    f = std::move(g);
  }
  m.topology.num_vertices = static_cast<Index>(p.size());
  m.topology.triangles = std::move(f);
  m.frame.positions = std::move(p);
  return m;
}

TestMesh v_fold(double alpha, int nx, int n_arm, double length, double arm) {
  TestMesh m;
  const int rows = 2 * n_arm - 1;  // j = 0 .. rows-1; the bottom is row n_arm - 1
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < nx; ++i) {
      const double x = -length / 2 + length * i / (nx - 1);
      const double s = arm * double(j - (n_arm - 1)) / (n_arm - 1);  // signed distance along the arm
      m.frame.positions.emplace_back(x, s * std::sin(alpha), std::abs(s) * std::cos(alpha));
    }
  m.topology.num_vertices = static_cast<Index>(m.frame.positions.size());
  for (int j = 0; j + 1 < rows; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      const Index a = j * nx + i, b = a + 1, c = a + nx, d = c + 1;
      m.topology.triangles.push_back({a, b, d});
      m.topology.triangles.push_back({a, d, c});
    }
  m.marked_vertex = static_cast<Index>((n_arm - 1) * nx + nx / 2);
  return m;
}

TestMesh closed_box(const glm::dvec3& lo, const glm::dvec3& hi) {
  TestMesh m;
  m.topology = {8,
                {{0, 2, 1},
                 {0, 3, 2},
                 {4, 5, 6},
                 {4, 6, 7},
                 {0, 1, 5},
                 {0, 5, 4},
                 {1, 2, 6},
                 {1, 6, 5},
                 {2, 3, 7},
                 {2, 7, 6},
                 {3, 0, 4},
                 {3, 4, 7}}};
  m.frame.positions = {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {lo.x, hi.y, lo.z},
                       {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}};
  return m;
}

void rigid_transform(TestMesh& mesh, const glm::dvec3& axis, double angle, const glm::dvec3& translation) {
  const glm::dmat4 r = glm::rotate(glm::dmat4(1.0), angle, glm::normalize(axis));
  for (auto& p : mesh.frame.positions) p = glm::dvec3(r * glm::dvec4(p, 1.0)) + translation;
}

}  // namespace pleat::test
