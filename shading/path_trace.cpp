// path_trace: per-vertex path-traced reference radiance (see the header for the model).
#include "shading/path_trace.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <glm/glm.hpp>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "shading/ray_visibility.hpp"
#include "static_core/mesh_validation.hpp"

namespace pleat {

namespace {

constexpr double kInvPi = 1.0 / std::numbers::pi;
constexpr int kMaxBounces = 64;
constexpr int kRouletteAfter = 3;

/// Counter-based stream: splitmix64 over a per-(seed, vertex, side, path) key.
class Random {
 public:
  explicit Random(std::uint64_t key) : m_state(key) {}
  double next() { return unit_double(splitmix64(m_state++)); }

 private:
  std::uint64_t m_state;
};

/// Radiance arriving along w from the lights that live at infinity (the kinds with escaped_radiance).
glm::dvec3 sky_radiance(const Lighting& lighting, const glm::dvec3& w) {
  glm::dvec3 l(0.0);
  lighting.for_each([&](const auto& light) {
    if constexpr (requires { light.escaped_radiance(w); }) l += light.escaped_radiance(w);
  });
  return l;
}

/// The nearest light crossed by the ray o + t w, t in (0, tmax) (the kinds with hit): its radiance towards
/// the ray.
bool area_light_hit(const Lighting& lighting, const glm::dvec3& o, const glm::dvec3& w, double tmax,
                    glm::dvec3& radiance) {
  bool found = false;
  lighting.for_each([&](const auto& light) {
    if constexpr (requires { light.hit(o, w, tmax, radiance); })
      if (light.hit(o, w, tmax, radiance)) found = true;
  });
  return found;
}

/// A point a path is at: a mesh vertex (with its one-ring side test) or a point inside a hit triangle.
struct PathPoint {
  glm::dvec3 position;
  glm::dvec3 axis;                 // unit normal of the side the path is on
  const VertexFan* fan = nullptr;  // set at the starting vertex
  Side side = Side::Front;
  std::span<const Index> ignore;  // the vertex's one-ring, or the hit triangle
  int on_plane = -1;              // the infinite plane (MeshTopology::planes) the point lies on, if any
};

class Tracer {
 public:
  Tracer(const EmbreeScene& scene, const MeshTopology& topology, const Frame& frame, const Lighting& lighting,
         double albedo)
      : m_scene(scene),
        m_topology(topology),
        m_frame(frame),
        m_lighting(lighting),
        m_albedo(albedo),
        m_tnear(1e-6 * scene.scene_diameter()) {}

  std::uint64_t rays() const { return m_rays; }

  /// Irradiance at x from point and directional lights (shadow rays), over the hemisphere of x.axis.
  glm::dvec3 direct_irradiance(const PathPoint& x) {
    glm::dvec3 e(0.0);
    m_lighting.for_each([&](const auto& light) {
      LightSample s;
      if constexpr (requires { light.sample(x.position, s); }) {
        if (!light.sample(x.position, s)) return;
        const double c = glm::dot(s.direction, x.axis);
        if (c > 0.0 && visible(x, s.direction, s.distance)) e += (c / s.divisor) * s.value;
      }
    });
    return e;
  }

  /// One path's estimate of E_cos[L_in] at the starting vertex, first direction `first` (world).
  glm::dvec3 trace(const PathPoint& start, const glm::dvec3& first, Random& random) {
    glm::dvec3 sum(0.0);
    double beta = 1.0;  // throughput relative to the start's L_in
    PathPoint x = start;
    Index hit_triangle = 0;
    glm::dvec3 w = first;
    for (int bounce = 0; bounce < kMaxBounces; ++bounce) {
      if (bounce > 0) w = sample(x.axis, random);
      if (x.fan != nullptr && x.fan->enters_cloth(w, x.side)) {
        // The cloth right at the vertex: the path continues from the same vertex and side.
        sum += beta * m_albedo * kInvPi * direct_irradiance(x);
      } else {
        RayQuery ray;
        ray.origin = x.position;
        ray.direction = w;
        ray.tnear = m_tnear;
        const RayHit hit = m_scene.intersect(ray, x.ignore);
        ++m_rays;
        // The squares that stand for infinite planes in the Embree scene are taken as their planes.
        const bool on_mesh = hit.hit && hit.triangle < m_topology.num_sliced_triangles();
        glm::dvec3 plane_side;
        int plane = -1;
        const double to_plane = plane_hit(x, w, plane_side, plane);
        const double t_hit =
            std::min(on_mesh ? double(hit.t) : std::numeric_limits<double>::infinity(), to_plane);
        glm::dvec3 area(0.0);
        if (area_light_hit(m_lighting, x.position, w, t_hit, area)) {
          sum += beta * area;
          break;
        }
        if (!(t_hit < std::numeric_limits<double>::infinity())) {
          sum += beta * sky_radiance(m_lighting, w);
          break;
        }
        if (to_plane <= t_hit) {  // the path goes on from the plane
          x.position += to_plane * w;
          x.axis = plane_side;
          x.on_plane = plane;
          x.ignore = {};
        } else {
          x.on_plane = -1;
          const Triangle& t = m_topology.triangles[hit.triangle];
          const glm::dvec3 &p0 = m_frame.positions[t[0]], &p1 = m_frame.positions[t[1]],
                           &p2 = m_frame.positions[t[2]];
          const glm::dvec3 n = glm::normalize(glm::cross(p1 - p0, p2 - p0));
          x.position = (1.0 - hit.u - hit.v) * p0 + hit.u * p1 + hit.v * p2;
          x.axis = glm::dot(w, n) < 0.0 ? n : -n;
          hit_triangle = hit.triangle;
          x.ignore = std::span<const Index>(&hit_triangle, 1);
        }
        x.fan = nullptr;
        sum += beta * m_albedo * kInvPi * direct_irradiance(x);
      }
      beta *= m_albedo;
      if (bounce + 1 >= kRouletteAfter) {
        if (random.next() >= m_albedo) break;
        beta /= m_albedo;
      }
    }
    return sum;
  }

 private:
  static glm::dvec3 sample(const glm::dvec3& axis, Random& random) {
    const glm::dvec3 l = cosine_hemisphere_direction(random.next(), random.next());
    glm::dvec3 t1, t2;
    tangent_basis(axis, t1, t2);
    return l.x * t1 + l.y * t2 + l.z * axis;
  }

  /// How far along unit w from x the ray enters one of the topology's infinite planes (infinity: none), the
  /// normal of the plane's side it comes from, and the plane's index. A point on a plane (x.on_plane) leaves
  /// it on its side. The planes are taken exactly, as the engines and the ray-cast reference take them: their
  /// squares in the Embree scene end.
  double plane_hit(const PathPoint& x, const glm::dvec3& w, glm::dvec3& side, int& plane) const {
    double nearest = std::numeric_limits<double>::infinity();
    for (int i = 0; i < static_cast<int>(m_topology.planes.size()); ++i) {
      if (i == x.on_plane) continue;
      const OccludingPlane& p = m_topology.planes[static_cast<std::size_t>(i)];
      const glm::dvec3& origin = x.position;
      const glm::dvec3& h = p.normal;  // every point is on the outer side (inside the solid: on its surface)
      const double towards = glm::dot(w, h);
      if (!(towards < 0.0)) continue;
      const double height = std::max(0.0, -p.depth(origin));
      if (const double t = height / -towards; t < nearest) {
        nearest = t;
        side = h;
        plane = i;
      }
    }
    return nearest;
  }

  bool visible(const PathPoint& x, const glm::dvec3& l, double distance) {
    if (x.fan != nullptr && x.fan->enters_cloth(l, x.side)) return false;
    glm::dvec3 side;
    int plane;
    if (plane_hit(x, l, side, plane) < distance) return false;
    RayQuery ray;
    ray.origin = x.position;
    ray.direction = l;
    ray.tnear = m_tnear;
    ray.tfar = distance;
    ++m_rays;
    return !m_scene.occluded(ray, x.ignore);
  }

  const EmbreeScene& m_scene;
  const MeshTopology& m_topology;
  const Frame& m_frame;
  const Lighting& m_lighting;
  double m_albedo;
  double m_tnear;
  std::uint64_t m_rays = 0;
};

}  // namespace

PathTracedFrame path_trace_vertices(EmbreeScene& scene, const MeshTopology& topology, const Frame& frame,
                                    const std::vector<glm::dvec3>& normals, const Lighting& lighting,
                                    const PathTraceParams& params) {
  validate_mesh(topology, frame, "path_trace_vertices");
  check_vertex_estimator_inputs("path_trace_vertices", "paths_per_vertex", params.paths_per_vertex, scene,
                                topology, frame, normals);
  if (!(params.albedo >= 0.0 && params.albedo < 1.0))
    throw std::invalid_argument("path_trace_vertices: albedo must be in [0, 1)");
  scene.update(frame);

  const Index n_vertices = topology.num_receivers();  // occluders scatter paths (grey, ρ), start none
  const int k = params.paths_per_vertex;
  PathTracedFrame out;
  for (int s = 0; s < 2; ++s) out.radiance[s].assign(n_vertices, glm::vec3(0.0f));
  std::vector<std::uint64_t> rays(n_vertices, 0);

  auto work = [&](Index begin, Index end) {
    Tracer tracer(scene, topology, frame, lighting, params.albedo);
    VertexFan fan;
    std::vector<glm::dvec3> local;
    for (Index v = begin; v < end; ++v) {
      const std::uint64_t before = tracer.rays();
      const glm::dvec3 n = glm::length(normals[v]) > 0.0 ? normals[v] : glm::dvec3(0.0, 0.0, 1.0);
      fan.build(topology, frame, scene.incident_triangles(v), v, n);
      for (Side side : kBothSides) {
        PathPoint start;
        start.position = frame.positions[v];
        start.axis = side_sign(side) * n;
        start.fan = &fan;
        start.side = side;
        start.ignore = scene.incident_triangles(v);
        glm::dvec3 t1, t2;
        tangent_basis(start.axis, t1, t2);
        cosine_hemisphere_directions(k, params.seed, v, side, local);
        glm::dvec3 indirect(0.0);
        for (int i = 0; i < k; ++i) {
          const glm::dvec3& l = local[static_cast<std::size_t>(i)];
          Random random(splitmix64(params.seed ^ 0x5eedULL) ^
                        splitmix64((static_cast<std::uint64_t>(v) << 24) ^
                                   (static_cast<std::uint64_t>(i) << 1) ^ static_cast<std::uint64_t>(side)));
          indirect += tracer.trace(start, l.x * t1 + l.y * t2 + l.z * start.axis, random);
        }
        const glm::dvec3 b =
            params.albedo * kInvPi * tracer.direct_irradiance(start) + params.albedo * indirect / double(k);
        out.radiance[static_cast<int>(side)][v] = glm::vec3(b);
      }
      rays[v] = tracer.rays() - before;
    }
  };
  if (params.parallel)
    tbb::parallel_for(tbb::blocked_range<Index>(0, n_vertices, 8),
                      [&](const tbb::blocked_range<Index>& r) { work(r.begin(), r.end()); });
  else
    work(0, n_vertices);
  for (std::uint64_t r : rays) out.rays += r;
  return out;
}

}  // namespace pleat
