#include "kinetic/internal/change_tracking.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <glm/geometric.hpp>
#include <utility>

namespace pleat::kinetic {

namespace {

bool same_bits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}
bool same_bits(float a, float b) {
  return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b);
}
bool same_bits(const glm::dvec2& a, const glm::dvec2& b) {
  return same_bits(a.x, b.x) && same_bits(a.y, b.y);
}

bool same_wedges(std::span<const Wedge> a, std::span<const Wedge> b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (!same_bits(a[i].start, b[i].start) || !same_bits(a[i].width, b[i].width) ||
        !same_bits(a[i].start_reach, b[i].start_reach) || !same_bits(a[i].end_reach, b[i].end_reach))
      return false;
  return true;
}

/// Whether stored cone `b` of the snapshot and `a` of `after` hand their vertex the same data (the one side
/// they are stored for).
bool same_offer(const OfferSnapshot& before, const StoredCone& b, const PlaneCones& after,
                const StoredCone& a) {
  const Side side = static_cast<Side>(a.side);
  if (!same_bits(b.distance, a.distance) || b.vertex_above != a.vertex_above ||
      b.cuts_count != a.cuts_count ||
      !same_bits(before.points[b.slice_vertex], after.slice.vertices[a.slice_vertex].point) ||
      !same_wedges(before.cones.cone(b.slice_vertex, side), after.cones.cone(a.slice_vertex, side)))
    return false;
  for (std::uint32_t i = 0; i < a.cuts_count; ++i) {
    const Index xb = before.fan_cuts[b.cuts_begin + i], xa = after.fan_cuts[a.cuts_begin + i];
    if (!same_bits(before.chain_angles[xb], after.chain_angles[xa]) ||
        !same_wedges(before.cones.cone(xb, side), after.cones.cone(xa, side)))
      return false;
  }
  return true;
}

}  // namespace

void find_moved_vertices(const Frame& previous, const Frame& next, std::vector<char>& moved,
                         std::vector<Index>& list) {
  const std::size_t n = next.positions.size();
  moved.assign(n, 0);
  list.clear();
  for (std::size_t v = 0; v < n; ++v)
    if (std::memcmp(&previous.positions[v], &next.positions[v], sizeof(glm::dvec3)) != 0) {
      moved[v] = 1;
      list.push_back(static_cast<Index>(v));
    }
}

void append_whole_fan_changes(std::span<const std::uint8_t> before, std::span<const std::uint8_t> after,
                              std::vector<Index>& list) {
  const std::size_t n = std::max(before.size(), after.size());
  for (std::size_t v = 0; v < n; ++v) {
    const std::uint8_t b = v < before.size() ? before[v] : 0, a = v < after.size() ? after[v] : 0;
    if (a != b) list.push_back(static_cast<Index>(v));
  }
}

void planes_reached(const MeshConnectivity& connectivity, std::span<const SlicingPlane> planes,
                    std::size_t orientations, const Frame& previous, const Frame& next,
                    std::span<const Index> touched, std::vector<char>& reached) {
  reached.assign(planes.size(), 0);
  if (touched.empty()) return;
  std::vector<std::pair<double, Index>> family;  // (offset, plane) of one orientation, sorted
  for (std::size_t o = 0; o < orientations; ++o) {
    family.clear();
    bool parallel = true;
    for (Index p = 0; p < planes.size(); ++p) {
      if (planes[p].orientation != static_cast<int>(o)) continue;
      if (!family.empty() && planes[family.front().second].normal != planes[p].normal) parallel = false;
      family.emplace_back(planes[p].offset, p);
    }
    if (family.empty()) continue;
    if (!parallel) {  // a pencil: every plane's own normal; marked whole
      for (const auto& [offset, p] : family) reached[p] = 1;
      continue;
    }
    std::sort(family.begin(), family.end());
    const glm::dvec3 normal = planes[family.front().second].normal;
    for (const Index v : touched) {
      // Every edge (v, u) crosses a plane only between the heights of v and u in the frame where it does.
      double lo = INFINITY, hi = -INFINITY;
      auto extend = [&](Index u) {
        for (const Frame* frame : {&previous, &next}) {
          const double h = glm::dot(normal, frame->positions[u]);
          lo = std::min(lo, h);
          hi = std::max(hi, h);
        }
      };
      extend(v);
      for (const Index u : connectivity.neighbours(v)) extend(u);
      const double margin = 1e-9 * (1.0 + std::max(std::abs(lo), std::abs(hi)));  // as candidate faces'
      auto it = std::lower_bound(family.begin(), family.end(), std::make_pair(lo - margin, Index(0)));
      for (; it != family.end() && it->first <= hi + margin; ++it) reached[it->second] = 1;
    }
  }
}

void OfferSnapshot::take(const PlaneCones& plane) {
  points.resize(plane.slice.vertices.size());
  for (std::size_t x = 0; x < points.size(); ++x) points[x] = plane.slice.vertices[x].point;
  stored = plane.stored;
  fan_cuts = plane.fan_cuts;
  chain_angles = plane.chain_angles;
  cones.wedges = plane.cones.wedges;
  cones.offsets = plane.cones.offsets;
}

void OfferSnapshot::clear() {
  points.clear();
  stored.clear();
  fan_cuts.clear();
  chain_angles.clear();
  cones.wedges.clear();
  cones.offsets.clear();
}

void offers_changed(Index receivers, const OfferSnapshot& before, const PlaneCones& after,
                    OfferDiffScratch& scratch, std::vector<Index>& changed) {
  std::vector<std::int64_t>& slot = scratch.slot;
  if (slot.size() != 2 * std::size_t(receivers)) slot.assign(2 * std::size_t(receivers), -1);
  auto key = [](const StoredCone& c) { return 2 * std::size_t(c.vertex) + std::size_t(c.side); };
  for (std::size_t i = 0; i < before.stored.size(); ++i) slot[key(before.stored[i])] = std::int64_t(i);
  for (const StoredCone& a : after.stored) {
    std::int64_t& s = slot[key(a)];
    if (s < 0 || !same_offer(before, before.stored[std::size_t(s)], after, a)) changed.push_back(a.vertex);
    if (s >= 0) s = -2;  // matched (an unmatched earlier offer stays >= 0)
  }
  for (const StoredCone& b : before.stored) {
    std::int64_t& s = slot[key(b)];
    if (s >= 0) changed.push_back(b.vertex);  // offered before, not now
    s = -1;
  }
  for (const StoredCone& a : after.stored) slot[key(a)] = -1;
}

void append_offered(const PlaneCones& plane, std::vector<Index>& changed) {
  for (const StoredCone& c : plane.stored) changed.push_back(c.vertex);
}

}  // namespace pleat::kinetic
