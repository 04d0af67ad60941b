// Ray-cast sky visibility: stratified cosine sampling, one-ring side test, Embree ray streams.
#include "shading/ray_visibility.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "static_core/spherical_polygon.hpp"

namespace pleat {

namespace {

double radical_inverse_base2(std::uint32_t i) {
  i = (i << 16) | (i >> 16);
  i = ((i & 0x00ff00ffu) << 8) | ((i & 0xff00ff00u) >> 8);
  i = ((i & 0x0f0f0f0fu) << 4) | ((i & 0xf0f0f0f0u) >> 4);
  i = ((i & 0x33333333u) << 2) | ((i & 0xccccccccu) >> 2);
  i = ((i & 0x55555555u) << 1) | ((i & 0xaaaaaaaau) >> 1);
  return static_cast<double>(i) * 0x1.0p-32;
}

std::uint64_t stream_key(std::uint64_t seed, Index vertex, Side side) {
  return splitmix64(splitmix64(seed) ^
                    (static_cast<std::uint64_t>(vertex) << 1 | static_cast<std::uint64_t>(side)));
}

/// sin and cos of x in [-π/4, π/4] by their Taylor series to x^11 / x^10 (error < 2e-9): no libm call,
/// the same bits on every platform, several times cheaper than sincos.
void small_sincos(double x, double& s, double& c) {
  const double x2 = x * x;
  s = x * (1.0 + x2 * (-1.0 / 6 +
                       x2 * (1.0 / 120 + x2 * (-1.0 / 5040 + x2 * (1.0 / 362880 + x2 * (-1.0 / 39916800))))));
  c = 1.0 +
      x2 * (-1.0 / 2 + x2 * (1.0 / 24 + x2 * (-1.0 / 720 + x2 * (1.0 / 40320 + x2 * (-1.0 / 3628800)))));
}

}  // namespace

glm::dvec3 cosine_hemisphere_direction(double u1, double u2) {
  const double a = 2.0 * u1 - 1.0, b = 2.0 * u2 - 1.0;
  if (a == 0.0 && b == 0.0) return {0.0, 0.0, 1.0};
  // Branch-free (the two cases alternate at random): with |den| >= |num|,
  //   |a| > |b|: phi = (π/4)(b/a),        (x, y) = a (cos, sin)
  //   else:      phi = π/2 - (π/4)(a/b),  (x, y) = b (sin, cos) of (π/4)(a/b).
  constexpr double kQuarterPi = std::numbers::pi / 4.0;
  const bool wide = std::abs(a) > std::abs(b);
  const double num = wide ? b : a, den = wide ? a : b;
  double s = 0.0, c = 0.0;
  small_sincos(kQuarterPi * (num / den), s, c);
  const double x = den * (wide ? c : s), y = den * (wide ? s : c);
  return {x, y, std::sqrt(std::max(0.0, 1.0 - x * x - y * y))};
}

void tangent_basis(const glm::dvec3& m, glm::dvec3& t1, glm::dvec3& t2) {
  const double sign = std::copysign(1.0, m.z);
  const double a = -1.0 / (sign + m.z);
  const double b = m.x * m.y * a;
  t1 = {1.0 + sign * m.x * m.x * a, sign * b, -sign * m.x};
  t2 = {b, sign + m.y * m.y * a, -m.y};
}

void VertexFan::build(const MeshTopology& topology, const Frame& frame, std::span<const Index> ring, Index v,
                      const glm::dvec3& n) {
  m_wedges.clear();
  m_edges.clear();
  const glm::dvec3& p = frame.positions[v];
  for (Index t : ring) {
    const Triangle& tri = topology.triangles[t];
    const int k = tri[0] == v ? 0 : (tri[1] == v ? 1 : 2);
    m_edges.push_back({tri[(k + 1) % 3], tri[(k + 2) % 3]});
    const glm::dvec3 ea = frame.positions[tri[(k + 1) % 3]] - p;
    const glm::dvec3 eb = frame.positions[tri[(k + 2) % 3]] - p;
    const glm::dvec3 normal = glm::cross(ea, eb);
    const double length = glm::length(normal);
    if (!(length > 0.0)) continue;  // degenerate: no plane, no side
    const double projected = glm::dot(normal, n);
    m_wedges.push_back(
        {glm::cross(n, ea), glm::cross(eb, n), normal / length, projected < 0.0, projected == 0.0});
  }
  // The link: follow the far edges a -> b from one that no other edge enters (an open ring's first) or from
  // any (a closed one). One chain through every edge, closed or open; anything else is non-manifold.
  m_ring = Ring::NonManifold;
  m_link.clear();
  const std::size_t count = m_edges.size();
  auto edge_from = [&](Index a) -> std::size_t {
    std::size_t found = count;
    for (std::size_t i = 0; i < count; ++i)
      if (m_edges[i][0] == a) {
        if (found != count) return count + 1;  // two edges leave a: non-manifold
        found = i;
      }
    return found;
  };
  if (count == 0) return;
  std::size_t start = 0;
  for (std::size_t i = 0; i < count; ++i) {
    bool entered = false;
    for (std::size_t j = 0; j < count && !entered; ++j) entered = m_edges[j][1] == m_edges[i][0];
    if (!entered) {
      start = i;
      break;
    }
  }
  std::size_t steps = 0, at = start;
  while (at < count && steps <= count) {
    const glm::dvec3 d = frame.positions[m_edges[at][0]] - p;
    const double length = glm::length(d);
    if (!(length > 0.0)) return;  // a ring vertex on v: no direction
    m_link.push_back(d / length);
    ++steps;
    const Index b = m_edges[at][1];
    if (b == m_edges[start][0]) {  // back at the start: closed, if every edge was walked once
      if (steps == count) m_ring = Ring::Closed;
      break;
    }
    at = edge_from(b);
    if (at == count) {  // nothing leaves b: the boundary, if every edge was walked once
      if (steps == count) m_ring = Ring::Open;
      break;
    }
  }
  if (m_ring == Ring::Closed) m_link_solid_angle = solid_angle(m_link);
}

int VertexFan::side_of(const glm::dvec3& w) const {
  if (m_ring == Ring::Closed) return contains_direction(m_link, w, m_link_solid_angle) ? 1 : -1;
  if (m_ring == Ring::Open) return 0;
  double nearest = std::numeric_limits<double>::infinity();
  int side = 0;
  for (const Wedge& f : m_wedges) {
    if (f.edge_on) continue;  // seen edge-on along n: its sector is empty
    const double s1 = glm::dot(w, f.sector_a);
    const double s2 = glm::dot(w, f.sector_b);
    const bool inside = f.flipped ? (s1 <= 0.0 && s2 <= 0.0) : (s1 >= 0.0 && s2 >= 0.0);
    if (!inside) continue;
    const double d = glm::dot(w, f.unit_normal);
    if (std::abs(d) < nearest) {
      nearest = std::abs(d);
      side = d > 0.0 ? 1 : (d < 0.0 ? -1 : 0);
    }
  }
  return side;
}

bool VertexFan::enters_cloth(const glm::dvec3& w, Side side) const {
  if (m_ring == Ring::Open) return false;
  const double sign = side_sign(side);
  // Fast path: a direction on the wanted side of every ring triangle's plane lies on that side of the link
  // (were it on the other, the link arc nearest to it would have it on its other side).
  bool all_on_side = true;
  for (const Wedge& f : m_wedges) all_on_side &= sign * glm::dot(w, f.unit_normal) >= 0.0;
  if (all_on_side) return false;
  return side_of(w) == -static_cast<int>(sign);
}

void cosine_hemisphere_directions(int count, std::uint64_t seed, Index vertex, Side side,
                                  std::vector<glm::dvec3>& out) {
  out.resize(static_cast<std::size_t>(std::max(count, 0)));
  const std::uint64_t key = stream_key(seed, vertex, side);
  const double shift1 = unit_double(splitmix64(key));
  const double shift2 = unit_double(splitmix64(key + 1));
  const double step = 1.0 / count;
  for (int i = 0; i < count; ++i) {
    double u1 = (i + 0.5) * step + shift1;  // both in [0, 2): wrap once
    double u2 = radical_inverse_base2(static_cast<std::uint32_t>(i)) + shift2;
    u1 -= u1 >= 1.0 ? 1.0 : 0.0;
    u2 -= u2 >= 1.0 ? 1.0 : 0.0;
    out[static_cast<std::size_t>(i)] = cosine_hemisphere_direction(u1, u2);
  }
}

void check_vertex_estimator_inputs(const char* who, const char* count_name, int count,
                                   const EmbreeScene& scene, const MeshTopology& topology, const Frame& frame,
                                   const std::vector<glm::dvec3>& normals) {
  const std::string name(who);
  if (count < 1) throw std::invalid_argument(name + ": " + count_name + " must be >= 1");
  if (frame.positions.size() != topology.num_vertices || normals.size() != topology.num_receivers())
    throw std::invalid_argument(name + ": frame has " + std::to_string(frame.positions.size()) +
                                " positions and " + std::to_string(normals.size()) + " normals for " +
                                std::to_string(topology.num_vertices) + " vertices (" +
                                std::to_string(topology.num_receivers()) + " not occluders)");
  if (scene.topology().num_vertices != topology.num_vertices ||
      scene.topology().triangles.size() != topology.triangles.size())
    throw std::invalid_argument(name + ": the Embree scene was built for another topology");
}

RayVisibility ray_cast_visibility(EmbreeScene& scene, const MeshTopology& topology, const Frame& frame,
                                  const std::vector<glm::dvec3>& normals, const RayVisibilityParams& params) {
  check_vertex_estimator_inputs("ray_cast_visibility", "rays_per_vertex", params.rays_per_vertex, scene,
                                topology, frame, normals);
  if (params.vertex_stride < 1)
    throw std::invalid_argument("ray_cast_visibility: vertex_stride must be >= 1");
  scene.update(frame);

  const Index n_vertices = topology.num_receivers();  // occluders block rays, cast none
  const int k = params.rays_per_vertex;
  const double tnear = 1e-6 * scene.scene_diameter();
  RayVisibility out;
  const Index stride = params.vertex_stride;
  const double unset = stride == 1 ? 0.0 : std::numeric_limits<double>::quiet_NaN();
  for (int s = 0; s < 2; ++s) {
    out.sky_visibility[s].assign(n_vertices, unset);
    out.bent_normals[s].assign(n_vertices, glm::dvec3(unset));
  }
  std::vector<std::uint64_t> cast(n_vertices, 0);

  auto work = [&](Index begin, Index end) {
    VertexFan fan;
    std::vector<glm::dvec3> local;
    std::vector<glm::dvec3> world;
    std::vector<glm::vec3> to_cast;
    std::vector<std::uint8_t> escaped;
    std::vector<glm::dvec3> half_spaces;  // the outer sides of the infinite planes, as the engines take them
    for (const OccludingPlane& p : topology.planes) half_spaces.push_back(p.normal);
    world.reserve(static_cast<std::size_t>(k));
    to_cast.reserve(static_cast<std::size_t>(k));
    for (Index v = begin; v < end; ++v) {
      if (v % stride != 0) continue;
      const glm::dvec3 n = glm::length(normals[v]) > 0.0 ? normals[v] : glm::dvec3(0.0, 0.0, 1.0);
      fan.build(topology, frame, scene.incident_triangles(v), v, n);
      for (Side side : kBothSides) {
        const int si = static_cast<int>(side);
        const glm::dvec3 axis = side_sign(side) * n;
        glm::dvec3 t1, t2;
        tangent_basis(axis, t1, t2);
        cosine_hemisphere_directions(k, params.seed, v, side, local);
        world.clear();
        to_cast.clear();
        for (const glm::dvec3& l : local) {
          const glm::dvec3 w = l.x * t1 + l.y * t2 + l.z * axis;
          if (fan.enters_cloth(w, side)) continue;  // crosses the cloth at its origin
          if (std::any_of(half_spaces.begin(), half_spaces.end(),
                          [&](const glm::dvec3& h) { return glm::dot(w, h) < 0.0; }))
            continue;  // meets an infinite plane (its square, cast, would let it pass beyond the edge)
          world.push_back(w);
          to_cast.emplace_back(w);
        }
        escaped.resize(to_cast.size());
        scene.escaping_rays(frame.positions[v], to_cast, tnear, scene.incident_triangles(v), escaped);
        std::size_t count = 0;
        glm::dvec3 sum(0.0);
        for (std::size_t i = 0; i < escaped.size(); ++i)
          if (escaped[i] != 0) {
            ++count;
            sum += world[i];
          }
        out.sky_visibility[si][v] = static_cast<double>(count) / k;
        const double length = glm::length(sum);
        out.bent_normals[si][v] = length > 0.0 ? sum / length : axis;
        cast[v] += to_cast.size();
      }
    }
  };

  if (params.parallel) {
    tbb::parallel_for(tbb::blocked_range<Index>(0, n_vertices, 16),
                      [&](const tbb::blocked_range<Index>& r) { work(r.begin(), r.end()); });
  } else {
    work(0, n_vertices);
  }
  for (std::uint64_t c : cast) out.rays_cast += c;
  return out;
}

std::array<std::vector<double>, 2> ray_cast_sky_visibility(EmbreeScene& scene, const MeshTopology& topology,
                                                           const Frame& frame,
                                                           const std::vector<glm::dvec3>& normals,
                                                           const RayVisibilityParams& params) {
  return std::move(ray_cast_visibility(scene, topology, frame, normals, params).sky_visibility);
}

}  // namespace pleat
