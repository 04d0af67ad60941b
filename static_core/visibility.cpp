#include "static_core/visibility.hpp"

#include "static_core/cone_assembly.hpp"
#include "static_core/mesh_slicer.hpp"
#include "static_core/slice_cones.hpp"
#include "static_core/slice_triangulation.hpp"

#include <glm/geometric.hpp>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>

namespace pleat {
namespace {

/// A 2D cone stored on a mesh vertex: which plane, which side, and its wedges (in the plane's result).
struct StoredCone {
  Index vertex = 0;
  int side = 0;
  Index slice_vertex = 0;
  double distance = 0.0;
};

struct PlaneResult {
  Slice slice;
  SliceCones cones;
  std::vector<StoredCone> stored;
  std::size_t crossings = 0;
};

struct Workspace {
  SlicerScratch slicer;
  SliceTriangulation triangulation;
  SliceConeScratch cones;
  std::vector<std::int64_t> best;  // per mesh vertex and side: index into `stored`, -1 if none
};

void process_plane(const MeshTopology& topology, const MeshEdges& edges, const Frame& frame,
                   const SlicingPlane& plane, std::span<const Index> faces, Workspace& ws, PlaneResult& out) {
  slice_mesh(topology, edges, frame, plane, faces, ws.slicer, out.slice);
  ws.triangulation.build(out.slice);
  out.crossings = ws.triangulation.crossings();
  compute_slice_cones(out.slice, ws.triangulation, ws.cones, out.cones);
  // One cone per mesh vertex and side: from the nearest slice vertex (ties: the lower index).
  if (ws.best.size() != 2 * std::size_t(topology.num_vertices)) ws.best.assign(2 * std::size_t(topology.num_vertices), -1);
  out.stored.clear();
  for (Index x = 0; x < out.slice.vertices.size(); ++x) {
    const SliceVertex& sv = out.slice.vertices[x];
    for (int side = 0; side < 2; ++side) {
      std::int64_t& best = ws.best[2 * std::size_t(sv.nearer) + side];
      if (best >= 0 && out.stored[best].distance <= sv.distance) continue;
      if (best < 0) {
        best = static_cast<std::int64_t>(out.stored.size());
        out.stored.push_back({});
      }
      out.stored[best] = {sv.nearer, side, x, sv.distance};
    }
  }
  for (const StoredCone& s : out.stored) ws.best[2 * std::size_t(s.vertex) + s.side] = -1;
}

}  // namespace

std::vector<glm::dvec3> vertex_normals(const MeshTopology& topology, const Frame& frame) {
  std::vector<glm::dvec3> n(topology.num_vertices, glm::dvec3(0.0));
  for (const Triangle& t : topology.triangles) {
    const glm::dvec3& a = frame.positions[t[0]];
    const glm::dvec3 c = glm::cross(frame.positions[t[1]] - a, frame.positions[t[2]] - a);
    for (Index v : t) n[v] += c;
  }
  for (auto& v : n) {
    const double len = glm::length(v);
    v = len > 0 ? v / len : glm::dvec3(0, 0, 1);
  }
  return n;
}

/// Everything a frame's computation reuses from the previous one: topology-derived structures, per-plane
/// results, per-thread workspaces and the CSR arrays of stored cones.
struct StaticVisibility::Impl {
  struct Ref {
    std::uint32_t plane;
    std::uint32_t stored;
  };
  struct AssemblyWorkspace {
    ConeAssemblyScratch scratch;
    std::vector<PlanarCone> cones;
  };

  Impl(const MeshTopology& topology, SlicingPlan plan, const VisibilityParams& params)
      : topology(topology), plan(std::move(plan)), params(params), edges(topology), planes(this->plan.planes.size()) {}

  void compute(const Frame& frame, FrameVisibility& result);

  const MeshTopology& topology;
  SlicingPlan plan;
  VisibilityParams params;
  MeshEdges edges;
  std::vector<PlaneResult> planes;
  std::vector<std::vector<Index>> faces;  // candidate faces per plane
  tbb::enumerable_thread_specific<Workspace> workspaces;
  tbb::enumerable_thread_specific<AssemblyWorkspace> assembly;
  std::vector<std::uint32_t> first, cursor;
  std::vector<Ref> refs;
  std::vector<std::int32_t> source;
  std::vector<double> dist;
  std::vector<std::pair<double, Index>> heap;
  FrameVisibility result;
};

void StaticVisibility::Impl::compute(const Frame& frame, FrameVisibility& result) {
  const std::size_t n = topology.num_vertices;
  result.normals = vertex_normals(topology, frame);
  candidate_faces_per_plane(topology, frame, plan, faces);

  // 1. Every plane on its own: slice, triangulate, shortest-path trees, 2D cones, storage.
  auto run = [&](std::size_t p) {
    process_plane(topology, edges, frame, plan.planes[p], faces[p], workspaces.local(), planes[p]);
  };
  if (params.parallel)
    tbb::parallel_for(std::size_t(0), planes.size(), run);
  else
    for (std::size_t p = 0; p < planes.size(); ++p) run(p);

  VisibilityStats& stats = result.stats;
  stats = {};
  stats.slices = planes.size();
  for (const PlaneResult& r : planes) {
    stats.slice_vertices += r.slice.vertices.size();
    stats.regions += r.cones.regions;
    stats.windows += r.cones.windows;
    stats.regions_with_holes += r.cones.regions_with_holes;
    stats.chain_crossings += r.crossings;
    stats.crossing_slices += r.crossings > 0;
  }

  // 2. Per vertex, side and orientation, the stored cones: one CSR array over the key
  //    (side * orientations + o) * n + v.
  const std::size_t orientations = plan.orientations.size();
  const std::size_t keys = 2 * orientations * n;
  auto key_of = [&](int side, std::size_t o, Index v) { return (side * orientations + o) * n + v; };
  first.assign(keys + 1, 0);
  for (std::uint32_t p = 0; p < planes.size(); ++p)
    for (const StoredCone& c : planes[p].stored) ++first[key_of(c.side, plan.planes[p].orientation, c.vertex) + 1];
  for (std::size_t k = 0; k < keys; ++k) first[k + 1] += first[k];
  refs.resize(first[keys]);
  cursor.assign(first.begin(), first.end() - 1);
  for (std::uint32_t p = 0; p < planes.size(); ++p)
    for (std::uint32_t s = 0; s < planes[p].stored.size(); ++s) {
      const StoredCone& c = planes[p].stored[s];
      refs[cursor[key_of(c.side, plan.planes[p].orientation, c.vertex)]++] = {p, s};
    }

  // 3. Fill: a vertex with no cone in an orientation borrows those of its nearest vertex (along mesh
  //    edges) that has one — multi-source Dijkstra per orientation and side. source[key] is the vertex
  //    whose cones the key uses (itself when it has its own), or -1.
  stats.filled_fraction.assign(orientations, 0.0);
  source.assign(keys, -1);
  dist.resize(n);
  for (int side = 0; side < 2; ++side)
    for (std::size_t o = 0; o < orientations; ++o) {
      std::int32_t* src = &source[key_of(side, o, 0)];
      heap.clear();
      for (Index v = 0; v < n; ++v) {
        const std::size_t k = key_of(side, o, v);
        if (first[k + 1] > first[k]) {
          dist[v] = 0;
          src[v] = static_cast<std::int32_t>(v);
          heap.emplace_back(0.0, v);
        } else {
          dist[v] = INFINITY;
        }
      }
      if (heap.empty()) continue;
      std::make_heap(heap.begin(), heap.end(), std::greater<>());
      while (!heap.empty()) {
        std::pop_heap(heap.begin(), heap.end(), std::greater<>());
        const auto [d, v] = heap.back();
        heap.pop_back();
        if (d > dist[v]) continue;
        for (Index u : edges.neighbours[v]) {
          const double du = d + glm::distance(frame.positions[u], frame.positions[v]);
          if (du < dist[u] || (du == dist[u] && src[v] < src[u])) {
            dist[u] = du;
            src[u] = src[v];
            heap.emplace_back(du, u);
            std::push_heap(heap.begin(), heap.end(), std::greater<>());
          }
        }
      }
      std::size_t filled = 0;
      for (Index v = 0; v < n; ++v) filled += src[v] >= 0 && src[v] != static_cast<std::int32_t>(v);
      if (side == 0) stats.filled_fraction[o] = n ? double(filled) / double(n) : 0.0;
    }

  // 4. 3D cones and their measures, per vertex and side (per-thread scratch; result memory reused).
  for (int side = 0; side < 2; ++side) {
    result.cones[side].resize(n);
    result.measures[side].assign(n, {});
  }
  auto assemble = [&](std::size_t v) {
    AssemblyWorkspace& ws = assembly.local();
    for (int side = 0; side < 2; ++side) {
      ws.cones.clear();
      for (std::size_t o = 0; o < orientations; ++o) {
        const std::int32_t from = source[key_of(side, o, static_cast<Index>(v))];
        if (from < 0) continue;
        const std::size_t k = key_of(side, o, static_cast<Index>(from));
        for (std::uint32_t i = first[k]; i < first[k + 1]; ++i) {
          const PlaneResult& pr = planes[refs[i].plane];
          const StoredCone& s = pr.stored[refs[i].stored];
          ws.cones.push_back({&plan.planes[refs[i].plane], pr.cones.cone(s.slice_vertex, static_cast<Side>(side))});
        }
      }
      const glm::dvec3 side_normal = side_sign(static_cast<Side>(side)) * result.normals[v];
      assemble_cone(ws.cones, side_normal, ws.scratch, result.cones[side][v]);
      result.measures[side][v] = measure_cone(result.cones[side][v], side_normal);
    }
  };
  if (params.parallel)
    tbb::parallel_for(std::size_t(0), n, assemble);
  else
    for (std::size_t v = 0; v < n; ++v) assemble(v);
}

StaticVisibility::StaticVisibility(const MeshTopology& topology, SlicingPlan plan, const VisibilityParams& params)
    : m_impl(std::make_unique<Impl>(topology, std::move(plan), params)) {}
StaticVisibility::~StaticVisibility() = default;
StaticVisibility::StaticVisibility(StaticVisibility&&) noexcept = default;
StaticVisibility& StaticVisibility::operator=(StaticVisibility&&) noexcept = default;

const FrameVisibility& StaticVisibility::compute(const Frame& frame) {
  m_impl->compute(frame, m_impl->result);
  return m_impl->result;
}

const SlicingPlan& StaticVisibility::plan() const { return m_impl->plan; }

FrameVisibility compute_visibility(const MeshTopology& topology, const Frame& frame, const SlicingPlan& plan,
                                   const VisibilityParams& params) {
  FrameVisibility result;
  compute_visibility(topology, frame, plan, params, result);
  return result;
}

void compute_visibility(const MeshTopology& topology, const Frame& frame, const SlicingPlan& plan,
                        const VisibilityParams& params, FrameVisibility& result) {
  StaticVisibility::Impl(topology, plan, params).compute(frame, result);
}

}  // namespace pleat
