#include "oracles/random_slices.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <numeric>

#include "oracles/test_meshes.hpp"
#include "static_core/mesh_connectivity.hpp"

namespace pleat::test {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;

bool segments_cross(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c, const glm::dvec2& d) {
  const K::Segment_2 s(K::Point_2(a.x, a.y), K::Point_2(b.x, b.y)),
      t(K::Point_2(c.x, c.y), K::Point_2(d.x, d.y));
  return CGAL::do_intersect(s, t);
}

using Segment = std::pair<glm::dvec2, glm::dvec2>;

/// True when the chain's segments meet none of `taken` and, within the chain, only consecutive ones touch
/// (at their shared point).
bool fits(const std::vector<glm::dvec2>& chain, bool closed, const std::vector<Segment>& taken) {
  std::vector<Segment> own;
  const std::size_t m = chain.size();
  for (std::size_t i = 0; i + 1 < m + (closed ? 1 : 0); ++i) own.emplace_back(chain[i], chain[(i + 1) % m]);
  for (const auto& s : own) {
    if (s.first == s.second) return false;
    for (const auto& t : taken)
      if (segments_cross(s.first, s.second, t.first, t.second)) return false;
  }
  for (std::size_t i = 0; i < own.size(); ++i)
    for (std::size_t j = i + 1; j < own.size(); ++j) {
      const bool adjacent = j == i + 1 || (closed && i == 0 && j + 1 == own.size());
      if (adjacent) {
        // Consecutive segments must not fold back over each other.
        const auto& [a, b] = own[i];
        const auto& [c, d] = own[j];
        const glm::dvec2 shared = (b == c) ? b : a;
        const glm::dvec2 u = (b == c) ? a - b : b - a, v = (b == c) ? d - c : c - d;
        if (std::abs(u.x * v.y - u.y * v.x) == 0 && glm::dot(u, v) > 0) return false;
        (void)shared;
        continue;
      }
      if (segments_cross(own[i].first, own[i].second, own[j].first, own[j].second)) return false;
    }
  return true;
}

}  // namespace

Slice make_slice(const std::vector<std::vector<glm::dvec2>>& chains, const std::vector<bool>& closed) {
  Slice slice;
  for (std::size_t c = 0; c < chains.size(); ++c) {
    const Index first = static_cast<Index>(slice.vertices.size());
    for (const auto& p : chains[c]) {
      SliceVertex v;
      v.point = p;
      v.edge = v.nearer = static_cast<Index>(slice.vertices.size());
      slice.vertices.push_back(v);
    }
    const Index m = static_cast<Index>(chains[c].size());
    for (Index i = 0; i + 1 < m; ++i) slice.edges.push_back({first + i, first + i + 1, 0});
    if (closed[c] && m >= 3) slice.edges.push_back({first + m - 1, first, 0});
  }
  slice.out_edge.assign(slice.vertices.size(), -1);
  slice.in_edge.assign(slice.vertices.size(), -1);
  for (std::size_t e = 0; e < slice.edges.size(); ++e) {
    slice.out_edge[slice.edges[e].from] = static_cast<std::int32_t>(e);
    slice.in_edge[slice.edges[e].to] = static_cast<std::int32_t>(e);
  }
  return slice;
}

Slice random_chain_slice(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const bool grid = unit(rng) < 0.5;  // snap to a coarse grid: collinear and duplicate points abound
  auto snap = [&](glm::dvec2 p) { return grid ? glm::round(p * 4.0) / 4.0 : p; };
  std::vector<std::vector<glm::dvec2>> chains;
  std::vector<bool> closed;
  std::vector<Segment> taken;
  const int components = 1 + static_cast<int>(unit(rng) * 5);
  for (int attempt = 0; attempt < 40 && static_cast<int>(chains.size()) < components; ++attempt) {
    // A star-shaped loop around a random centre.
    const glm::dvec2 centre(unit(rng) * 8, unit(rng) * 8);
    const double radius = 0.5 + unit(rng) * (chains.empty() ? 4.0 : 2.0);
    const int m = 3 + static_cast<int>(unit(rng) * 12);
    std::vector<double> angles(m);
    for (auto& a : angles) a = unit(rng) * 6.283185307179586;
    std::sort(angles.begin(), angles.end());
    std::vector<glm::dvec2> loop;
    for (double a : angles) {
      const double r = radius * (0.3 + 0.7 * unit(rng));
      const glm::dvec2 p = snap(centre + r * glm::dvec2(std::cos(a), std::sin(a)));
      if (loop.empty() || p != loop.back()) loop.push_back(p);
    }
    while (loop.size() > 1 && loop.front() == loop.back()) loop.pop_back();
    if (loop.size() < 2) continue;
    if (unit(rng) < 0.5) std::reverse(loop.begin(), loop.end());  // which side is the front
    const double kind = unit(rng);
    std::vector<std::pair<std::vector<glm::dvec2>, bool>> pieces;
    if (kind < 0.4 && loop.size() >= 3) {
      pieces.emplace_back(loop, true);
    } else if (kind < 0.8) {
      std::rotate(loop.begin(), loop.begin() + static_cast<long>(unit(rng) * loop.size()), loop.end());
      pieces.emplace_back(loop, false);  // an open chain
    } else {
      // Cut into dangling pieces.
      std::size_t cut = 1 + static_cast<std::size_t>(unit(rng) * (loop.size() - 1));
      pieces.emplace_back(std::vector<glm::dvec2>(loop.begin(), loop.begin() + cut), false);
      if (cut + 1 < loop.size())
        pieces.emplace_back(std::vector<glm::dvec2>(loop.begin() + cut, loop.end()), false);
    }
    for (auto& [chain, is_closed] : pieces) {
      if (chain.size() < 2) continue;
      // Duplicate a point now and then: the slice of a mesh vertex lying exactly on the plane.
      if (unit(rng) < 0.3) {
        const std::size_t i = static_cast<std::size_t>(unit(rng) * chain.size());
        chain.insert(chain.begin() + static_cast<long>(i), chain[i]);
      }
      std::vector<glm::dvec2> distinct;
      for (const auto& p : chain)
        if (distinct.empty() || distinct.back() != p) distinct.push_back(p);
      if (is_closed && distinct.size() > 1 && distinct.front() == distinct.back()) distinct.pop_back();
      if (distinct.size() < 2 || (is_closed && distinct.size() < 3)) continue;
      if (!fits(distinct, is_closed, taken)) continue;
      for (std::size_t i = 0; i + 1 < distinct.size() + (is_closed ? 1 : 0); ++i)
        taken.emplace_back(distinct[i], distinct[(i + 1) % distinct.size()]);
      chains.push_back(chain);
      closed.push_back(is_closed);
    }
  }
  return make_slice(chains, closed);
}

RandomSurface random_height_field(std::mt19937_64& rng, int n) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  RandomSurface s;
  s.topology = flat_sheet(n, n).topology;  // the grid's triangles; positions below (x = i / (n - 1) exactly)
  struct Bump {
    double x, y, h, r;
  };
  std::vector<Bump> bumps(4 + static_cast<int>(unit(rng) * 6));
  for (auto& b : bumps) b = {unit(rng), unit(rng), (unit(rng) - 0.5) * 1.5, 0.05 + 0.2 * unit(rng)};
  const double fold = unit(rng) * 0.4;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = double(i) / (n - 1), y = double(j) / (n - 1);
      double z = fold * std::sin(12 * x);
      for (const auto& b : bumps)
        z += b.h * std::exp(-((x - b.x) * (x - b.x) + (y - b.y) * (y - b.y)) / (b.r * b.r));
      s.frame.positions.emplace_back(x, y, z);
    }
  return s;
}

SlicingPlane random_plane_through(std::mt19937_64& rng, const Frame& frame) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  glm::dvec3 n(normal(rng), normal(rng), normal(rng));
  if (unit(rng) < 0.3) n = {normal(rng), normal(rng), 0.0};  // vertical: open graph-like chains
  if (glm::length(n) < 1e-6) n = {0, 0, 1};
  n = glm::normalize(n);
  const glm::dvec3& p = frame.positions[static_cast<std::size_t>(unit(rng) * frame.positions.size())];
  if (unit(rng) < 1.0 / 3.0) {
    // Exactly through the vertex: an axis-aligned normal makes dot(n, p) exact.
    const int axis = static_cast<int>(unit(rng) * 3) % 3;
    n = glm::dvec3(0.0);
    n[axis] = 1.0;
    return make_plane(n, p[axis], 0);
  }
  return make_plane(n, glm::dot(n, p) + (unit(rng) - 0.5) * 0.05, 0);
}

std::vector<Slice> random_surface_slices(std::uint64_t seed, int count) {
  std::mt19937_64 rng(seed);
  const RandomSurface surface = random_height_field(rng, 6 + static_cast<int>(seed % 10));
  const MeshConnectivity connectivity(surface.topology);
  std::vector<Index> faces(surface.topology.triangles.size());
  std::iota(faces.begin(), faces.end(), 0);
  SlicerScratch scratch;
  std::vector<Slice> slices(static_cast<std::size_t>(count));
  for (Slice& slice : slices)
    slice_mesh(surface.topology, connectivity, surface.frame, random_plane_through(rng, surface.frame), faces,
               scratch, slice);
  return slices;
}

}  // namespace pleat::test
