#include "static_core/internal/frame_assembly.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "static_core/assert.hpp"
#include "static_core/cone_assembly.hpp"
#include "static_core/cone_rules.hpp"
#include "static_core/contact.hpp"
#include "static_core/internal/fan_cone.hpp"

namespace pleat {

void store_cones(Index num_receivers, ConeStorage storage, const Frame& frame, const Slice& slice,
                 std::vector<StoredCone>& stored, std::vector<std::int64_t>& best_of) {
  if (best_of.size() != 2 * std::size_t(num_receivers)) best_of.assign(2 * std::size_t(num_receivers), -1);
  stored.clear();
  auto offer = [&](Index vertex, Index x, double distance, bool vertex_above) {
    if (vertex >= num_receivers) return;  // an occluder's: it receives no cone
    for (int side = 0; side < 2; ++side) {
      std::int64_t& best = best_of[2 * std::size_t(vertex) + side];
      if (best >= 0 && stored[best].distance <= distance) continue;
      if (best < 0) {
        best = static_cast<std::int64_t>(stored.size());
        stored.push_back({});
      }
      stored[best] = {vertex, side, x, distance, vertex_above};
    }
  };
  const bool nearer = cone_storage_rule(storage).offer == ConeStorageRule::Offer::NearerEndpoint;
  for (Index x = 0; x < slice.vertices.size(); ++x) {
    const SliceVertex& sv = slice.vertices[x];
    if (nearer) {
      offer(sv.nearer, x, sv.distance, sv.nearer == sv.above);
    } else {
      const double length = glm::distance(frame.positions[sv.above], frame.positions[sv.below]);
      offer(sv.above, x, sv.t * length, true);
      offer(sv.below, x, (1.0 - sv.t) * length, false);
    }
  }
  for (const StoredCone& s : stored) best_of[2 * std::size_t(s.vertex) + s.side] = -1;
}

void mark_frame(const MeshTopology& topology, const MeshConnectivity& connectivity, const Frame& frame,
                FrameMarks& marks) {
  flat_occluder_edges(topology, connectivity, frame, marks.flat_edges);
  marks.normals = area_weighted_normals(topology, frame);
  mark_whole_fans(topology, connectivity, frame, marks.normals, marks.whole_fans);
}

void list_fan_cuts(Index num_receivers, const Frame& frame, const Slice& slice,
                   std::span<const std::uint8_t> whole_fans, std::vector<StoredCone>& stored,
                   FanCutScratch& scratch, std::vector<Index>& fan_cuts) {
  std::vector<std::int64_t>& slot_of = scratch.slot_of;
  std::vector<FanCut>& entries = scratch.entries;
  // Each stored vertex gets a slot (its first stored cone's index; both sides share its cuts); the cuts are
  // counted into slots, placed, and each slot's few sorted by (distance, slice vertex).
  if (slot_of.size() != 2 * std::size_t(num_receivers)) slot_of.assign(2 * std::size_t(num_receivers), -1);
  auto whole = [&](Index u) { return u < num_receivers && u < whole_fans.size() && whole_fans[u]; };
  for (std::size_t i = 0; i < stored.size(); ++i) {
    if (!whole(stored[i].vertex)) continue;
    std::int64_t& slot = slot_of[2 * std::size_t(stored[i].vertex)];
    if (slot < 0) slot = static_cast<std::int64_t>(i);
  }
  std::vector<std::uint32_t>& first = scratch.first;
  first.assign(stored.size() + 1, 0);
  auto each_cut = [&](bool with_distance, auto&& visit) {
    for (Index x = 0; x < slice.vertices.size(); ++x) {
      const SliceVertex& sv = slice.vertices[x];
      if (!whole(sv.above) && !whole(sv.below)) continue;
      const double length =
          with_distance ? glm::distance(frame.positions[sv.above], frame.positions[sv.below]) : 0.0;
      if (whole(sv.above)) visit(sv.above, sv.t * length, x);
      if (whole(sv.below)) visit(sv.below, (1.0 - sv.t) * length, x);
    }
  };
  each_cut(false, [&](Index u, double, Index) { ++first[slot_of[2 * std::size_t(u)] + 1]; });
  for (std::size_t i = 0; i < stored.size(); ++i) first[i + 1] += first[i];
  entries.resize(first[stored.size()]);
  std::vector<std::uint32_t>& cursor = scratch.cursor;
  cursor.assign(first.begin(), first.end() - 1);
  each_cut(true, [&](Index u, double distance, Index x) {
    entries[cursor[slot_of[2 * std::size_t(u)]]++] = {distance, x};
  });
  fan_cuts.resize(entries.size());
  for (std::size_t i = 0; i < stored.size(); ++i) {
    const auto begin = entries.begin() + first[i], end = entries.begin() + first[i + 1];
    std::sort(begin, end, [](const FanCut& a, const FanCut& b) {
      return a.distance != b.distance ? a.distance < b.distance : a.slice_vertex < b.slice_vertex;
    });
    for (auto e = begin; e != end; ++e) fan_cuts[e - entries.begin()] = e->slice_vertex;
  }
  for (StoredCone& c : stored) {
    if (!whole(c.vertex)) {
      c.cuts_begin = c.cuts_count = 0;
      continue;
    }
    const std::int64_t slot = slot_of[2 * std::size_t(c.vertex)];
    c.cuts_begin = first[slot];
    c.cuts_count = first[slot + 1] - first[slot];
    PLEAT_ASSERT(c.cuts_count > 0 && fan_cuts[c.cuts_begin] == c.slice_vertex,
                 "list_fan_cuts: the nearest cut is not the stored one");
  }
  for (const StoredCone& c : stored) slot_of[2 * std::size_t(c.vertex)] = -1;
}

bool offer_plane_cones(Index num_receivers, ConeStorage storage, const Frame& frame,
                       std::span<const std::uint8_t> whole_fans, PlaneConeScratch& s, PlaneCones& out) {
  store_cones(num_receivers, storage, frame, out.slice, out.stored, s.best);
  out.fan_cuts.clear();
  out.chain_angles.clear();
  if (out.stored.empty()) {
    out.cones.wedges.clear();
    out.cones.offsets.assign(2 * out.slice.vertices.size() + 1, 0);
    out.cones.windows = out.cones.regions = out.cones.regions_with_holes = 0;
    return false;
  }
  s.needed.assign(out.slice.vertices.size(), 0);
  for (const StoredCone& c : out.stored) s.needed[c.slice_vertex] = 1;
  if (cone_storage_rule(storage).fan_cones) {
    list_fan_cuts(num_receivers, frame, out.slice, whole_fans, out.stored, s.fan_cuts, out.fan_cuts);
    out.chain_angles.assign(out.slice.vertices.size(), glm::dvec2(INFINITY));
    for (const Index x : out.fan_cuts) {
      s.needed[x] = 1;
      if (std::isinf(out.chain_angles[x].x)) out.chain_angles[x] = chain_edge_angles(out.slice, x);
    }
  }
  return true;
}

void compute_plane_cones(const SliceTriangulation& triangulation, double contact_tolerance,
                         PlaneConeScratch& s, PlaneCones& out) {
  compute_slice_cones(out.slice, triangulation, s.cones, out.cones, s.needed);
  if (out.occluders.vertices.empty()) return;
  gather_occluder_chains(out.occluders, s.shadows, s.chains);
  cast_occluder_shadows(out.slice, s.chains, s.needed, contact_tolerance, s.shadows, out.cones);
}

void nearest_sources(const MeshConnectivity& connectivity, std::span<const double> edge_length,
                     std::span<const char> own, NearestSourceScratch& scratch, std::span<std::int32_t> src) {
  const Index n = connectivity.num_vertices();
  PLEAT_ASSERT(own.size() == n && src.size() == n && edge_length.size() == connectivity.num_edges(),
               "nearest_sources: sizes do not match the mesh");
  std::vector<double>& dist = scratch.dist;
  auto& heap = scratch.heap;
  dist.resize(n);
  heap.clear();
  for (Index v = 0; v < n; ++v) {
    dist[v] = own[v] ? 0.0 : INFINITY;
    src[v] = own[v] ? static_cast<std::int32_t>(v) : -1;
  }
  // Only sources next to a vertex without a cone (or on an edge of length 0) start the search: from any
  // other source, every step reaches a source at distance 0 by a positive length and changes nothing, so
  // the result is that of starting from every source.
  for (Index v = 0; v < n; ++v) {
    if (!own[v]) continue;
    const auto around = connectivity.neighbours(v);
    const auto along = connectivity.incident_edges(v);
    for (std::size_t i = 0; i < around.size(); ++i)
      if (!own[around[i]] || !(edge_length[along[i]] > 0)) {
        heap.emplace_back(0.0, v);
        break;
      }
  }
  std::make_heap(heap.begin(), heap.end(), std::greater<>());
  while (!heap.empty()) {
    std::pop_heap(heap.begin(), heap.end(), std::greater<>());
    const auto [d, v] = heap.back();
    heap.pop_back();
    if (d > dist[v]) continue;
    const auto around = connectivity.neighbours(v);
    const auto along = connectivity.incident_edges(v);
    for (std::size_t i = 0; i < around.size(); ++i) {
      const Index u = around[i];
      const double du = d + edge_length[along[i]];
      if (du < dist[u] || (du == dist[u] && src[v] < src[u])) {
        dist[u] = du;
        src[u] = src[v];
        heap.emplace_back(du, u);
        std::push_heap(heap.begin(), heap.end(), std::greater<>());
      }
    }
  }
}

namespace {
/// Whether two planes belong to one family of parallel planes (the same normal and in-plane frame).
bool parallel(const SlicingPlane& a, const SlicingPlane& b) {
  return a.normal == b.normal && a.u == b.u && a.w == b.w;
}
}  // namespace

struct FrameAssembler::Impl {
  /// A stored cone in the CSR: its plane and slice vertex.
  struct Ref {
    std::uint32_t plane;
    std::uint32_t slice_vertex;
    std::uint32_t cuts_begin, cuts_count;  ///< StoredCone's: the vertex's cuts in the plane (AimedOnFan)
  };
  /// What step 2 compares of an offer, beside its Ref in the CSR: the offers are read in CSR order, not
  /// gathered from the planes' lists (a gather costs a pass over every plane's list).
  struct OfferKey {
    double distance;
    bool vertex_above;
  };
  struct Blend {
    std::size_t cone, begin, count;              ///< ws.cones[cone] has ws.blended[begin, begin + count)
    std::size_t tangents_begin, tangents_count;  ///< and ws.tangents[tangents_begin, + tangents_count)
  };
  struct Workspace {
    ConeAssemblyScratch scratch;
    std::vector<PlanarCone> cones;
    std::vector<Wedge> blended;
    std::vector<HorizonTangent> tangents;  ///< of the aimed ends (aim_wedges)
    std::vector<Blend> blends;
    WedgeScratch wedge_scratch;
    FanConeScratch fan;
    /// Per orientation and side, the vertex's fan_local_ranges (ranges[2 o + side]; ranged[o]: it has them).
    std::vector<std::vector<AngularInterval>> ranges;
    std::vector<char> ranged;
    std::vector<Wedge> fan_lo, fan_hi;  ///< the fan cones of one plane or two
  };

  Impl(const MeshTopology& topology, const MeshConnectivity& connectivity, const SlicingPlan& plan,
       const VisibilityParams& params)
      : topology(topology), connectivity(connectivity), plan(plan), params(params), contact(topology) {
    for (const OccludingPlane& p : topology.planes) half_spaces.push_back(p.normal);
  }

  void assemble(const Frame& frame, const FrameMarks& marks, std::span<const PlaneCones* const> planes,
                FrameVisibility& result, const AssemblyChanges* changes);
  /// Under `changes`, the receivers whose 3D cone can differ from the last frame's into `to_assemble`
  /// (FrameAssembler::assemble); false when there is no completed last frame to keep from.
  bool select_changed(const AssemblyChanges* changes, Index receivers);

  const MeshTopology& topology;
  const MeshConnectivity& connectivity;
  const SlicingPlan& plan;
  VisibilityParams params;
  std::vector<glm::dvec3> half_spaces;  ///< every vertex's: the outer sides of the occluding planes
  ContactCheck contact;
  tbb::enumerable_thread_specific<Workspace> workspaces;
  std::vector<std::uint32_t> first, cursor;
  std::vector<Ref> refs;
  std::vector<OfferKey> offer_keys;  // parallel to refs while step 2 builds the CSR
  std::vector<std::int32_t> source;
  std::vector<std::int32_t> fill_source;  // one orientation's, per vertex (step 3)
  std::vector<char> own;                  // one orientation's: the vertex has a cone of its own
  std::vector<double> edge_length;        // per edge (MeshConnectivity::endpoints)
  NearestSourceScratch fill;
  std::vector<std::int32_t> previous_source;  // the last completed frame's `source`
  bool has_previous = false;                  // the last call completed (its result may be kept from)
  std::vector<Index> to_assemble;             // the vertices an incremental frame assembles
  std::size_t assembled = 0;                  // by the last call
};

bool FrameAssembler::Impl::select_changed(const AssemblyChanges* changes, Index receivers) {
  if (!changes || !has_previous || previous_source.size() != source.size() ||
      changes->offers_changed.size() < receivers || changes->moved.size() < topology.num_vertices)
    return false;
  const std::size_t orientations = plan.orientations.size();
  const std::span<const char> offers = changes->offers_changed, moved = changes->moved;
  auto changed = [&](Index v) {
    if (offers[v] || moved[v]) return true;
    for (const Index u : connectivity.neighbours(v))  // its normal and fan
      if (moved[u]) return true;
    for (std::size_t o = 0; o < orientations; ++o) {  // both sides share their sources (step 3)
      const std::size_t k = std::size_t(v) * 2 * orientations + o;
      const std::int32_t from = source[k];
      if (from != previous_source[k]) return true;
      if (from >= 0 && Index(from) != v && (offers[Index(from)] || moved[Index(from)])) return true;
    }
    return false;
  };
  to_assemble.clear();
  for (Index v = 0; v < receivers; ++v)
    if (changed(v)) to_assemble.push_back(v);
  return true;
}

void FrameAssembler::Impl::assemble(const Frame& frame, const FrameMarks& marks,
                                    std::span<const PlaneCones* const> planes, FrameVisibility& result,
                                    const AssemblyChanges* changes) {
  const std::size_t n = topology.num_vertices;
  const Index receivers = topology.num_receivers();  // the result holds theirs only: occluders get no cone
  result.normals.assign(marks.normals.begin(), marks.normals.begin() + receivers);

  VisibilityStats& stats = result.stats;
  stats = {};
  stats.slices = planes.size();
  for (const PlaneCones* plane : planes) {
    const PlaneCones& r = *plane;
    stats.slice_vertices += r.slice.vertices.size();
    stats.regions += r.cones.regions;
    stats.windows += r.cones.windows;
    stats.regions_with_holes += r.cones.regions_with_holes;
    stats.chain_crossings += r.crossings;
    stats.crossing_slices += r.crossings > 0;
  }
  contact.check(frame, stats);

  // 1. Storage: what each plane offers its mesh vertices is in planes[p]->stored (offer_plane_cones).
  auto stored = [&](std::uint32_t p) -> const std::vector<StoredCone>& { return planes[p]->stored; };

  // 2. Per vertex, side and orientation, the stored cones: one CSR array over the key
  //    (v * 2 + side) * orientations + o, in plane order (a vertex's cones lie together for step 4).
  const std::size_t orientations = plan.orientations.size();
  const std::size_t keys = 2 * orientations * n;
  auto key_of = [&](int side, std::size_t o, Index v) {
    return (std::size_t(v) * 2 + side) * orientations + o;
  };
  first.assign(keys + 1, 0);
  for (std::uint32_t p = 0; p < planes.size(); ++p)
    for (const StoredCone& c : stored(p)) ++first[key_of(c.side, plan.planes[p].orientation, c.vertex) + 1];
  for (std::size_t k = 0; k < keys; ++k) first[k + 1] += first[k];
  refs.resize(first[keys]);
  offer_keys.resize(first[keys]);
  cursor.assign(first.begin(), first.end() - 1);
  for (std::uint32_t p = 0; p < planes.size(); ++p)
    for (const StoredCone& c : stored(p)) {
      const std::uint32_t at = cursor[key_of(c.side, plan.planes[p].orientation, c.vertex)]++;
      refs[at] = {p, c.slice_vertex, c.cuts_begin, c.cuts_count};
      offer_keys[at] = {c.distance, c.vertex_above};
    }
  const ConeStorageRule& rule = cone_storage_rule(plan.storage);
  if (rule.keep != ConeStorageRule::Keep::EveryPlane) {
    // Keep only the nearest offer of each key (ties: the first, i.e. the lower plane), or under
    // InterpolatedOnFan the nearest from a plane below the vertex and then the nearest from a plane above it
    // (only the nearer of the two where their planes are not parallel: they are not blended, see
    // the aiming in step 4): compact the CSR in place.
    const bool both_sides_of_vertex = rule.keep == ConeStorageRule::Keep::NearestBelowAndAbove;
    std::uint32_t out = 0;
    for (std::size_t k = 0; k < keys; ++k) {
      const std::uint32_t begin = first[k], end = first[k + 1];
      first[k] = out;
      std::int64_t best[2] = {-1, -1};  // [0]: from a plane below the vertex, [1]: above
      for (std::uint32_t i = begin; i < end; ++i) {
        std::int64_t& b = best[both_sides_of_vertex && !offer_keys[i].vertex_above ? 1 : 0];
        if (b < 0 || offer_keys[i].distance < offer_keys[b].distance) b = i;
      }
      if (best[0] >= 0 && best[1] >= 0 &&
          !parallel(plan.planes[refs[best[0]].plane], plan.planes[refs[best[1]].plane])) {
        const bool upper = offer_keys[best[1]].distance < offer_keys[best[0]].distance;
        best[upper ? 0 : 1] = -1;
      }
      // Both chosen before either is written: in place, the first write may land on the second's slot.
      const Ref chosen[2] = {best[0] >= 0 ? refs[best[0]] : Ref{}, best[1] >= 0 ? refs[best[1]] : Ref{}};
      for (int i = 0; i < 2; ++i)
        if (best[i] >= 0) refs[out++] = chosen[i];
    }
    first[keys] = out;
    refs.resize(out);
  }

  // 3. Fill: a vertex with no cone in an orientation borrows those of its nearest vertex (along mesh
  //    edges) that has one — multi-source Dijkstra per orientation. source[key] is the vertex whose cones the
  //    key uses (itself when it has its own), or -1. Both storage rules offer a slice vertex's cone to both
  //    sides at once, so the sides have the same sources: the fill runs once per orientation.
  stats.filled_fraction.assign(orientations, 0.0);
  source.assign(keys, -1);
  const auto& endpoints = connectivity.endpoints();
  edge_length.resize(endpoints.size());
  for (std::size_t e = 0; e < endpoints.size(); ++e)
    edge_length[e] = glm::distance(frame.positions[endpoints[e][1]], frame.positions[endpoints[e][0]]);
  fill_source.resize(n);
  own.resize(n);
  for (std::size_t o = 0; o < orientations; ++o) {
    for (Index v = 0; v < n; ++v) {
      const std::size_t k = key_of(0, o, v);
      PLEAT_ASSERT((first[k + 1] > first[k]) == (first[key_of(1, o, v) + 1] > first[key_of(1, o, v)]),
                   "a cone stored for one side only");
      own[v] = first[k + 1] > first[k];
    }
    nearest_sources(connectivity, edge_length, own, fill, fill_source);
    const std::int32_t* src = fill_source.data();  // (may be empty: no vertex)
    for (Index v = 0; v < n; ++v) source[key_of(0, o, v)] = source[key_of(1, o, v)] = src[v];
    std::size_t filled = 0;
    for (Index v = 0; v < receivers; ++v) filled += src[v] >= 0 && src[v] != static_cast<std::int32_t>(v);
    stats.filled_fraction[o] = receivers ? double(filled) / double(receivers) : 0.0;
  }

  // 4. 3D cones and their measures, per vertex and side (per-thread scratch; result memory reused); under
  //    `changes`, of the vertices whose cones can differ only.
  const bool incremental = select_changed(changes, receivers);
  has_previous = false;  // until this frame completes
  for (int side = 0; side < 2; ++side) {
    result.cones[side].resize(receivers);
    if (incremental)
      result.measures[side].resize(receivers);
    else
      result.measures[side].assign(receivers, {});
  }
  auto cone_of = [&](const Ref& r, int side) {
    return planes[r.plane]->cones.cone(r.slice_vertex, static_cast<Side>(side));
  };
  // Under AimedOnFan, the cone of plane r at vertex v from v's own cuts is the cone of its fan
  // (fan_cone.hpp); a borrowed cone (own false), or one whose fan gives no range, is the stored slice
  // vertex's.
  const bool fan = rule.fan_cones;
  auto plane_cone = [&](const Ref& r, int side, bool own, Workspace& ws,
                        std::vector<Wedge>& buffer) -> std::span<const Wedge> {
    const int o = plan.planes[r.plane].orientation;
    if (!fan || !own || r.cuts_count == 0 || !ws.ranged[o]) return cone_of(r, side);
    const PlaneCones& plane = *planes[r.plane];
    fan_cone({plane.fan_cuts.data() + r.cuts_begin, r.cuts_count}, plane.cones, plane.chain_angles,
             static_cast<Side>(side), ws.ranges[2 * o + side], ws.fan, buffer);
    return buffer;
  };
  // A cone of plane p gathered from a workspace buffer: copied to ws.blended, its span set once that stops
  // growing (as a blend's).
  auto place = [&](const SlicingPlane& p, std::span<const Wedge> wedges, Workspace& ws) {
    ws.blends.push_back({ws.cones.size(), ws.blended.size(), wedges.size(), ws.tangents.size(), 0});
    ws.blended.insert(ws.blended.end(), wedges.begin(), wedges.end());
    ws.cones.push_back({&p, {}});
  };
  // Under InterpolatedOnFan, a key with offers from a plane below the vertex (lo) and one above it (hi), of
  // parallel planes (step 2 kept only the nearer of a pencil's two): the blend of their cones at the vertex's
  // height, or, where they do not match, the nearer plane's cone. Under AimedOnFan the blend is of the two
  // planes' horizon points, aimed at from the vertex itself (aim_wedges, docs/method.md §7). Appends to
  // ws.cones (a blended cone's wedges are placed once ws.blended stops growing). `v` is the vertex whose
  // cone this is, `own` whether the cuts are on its edges (not borrowed from the vertex at `position`).
  auto blend_at_vertex = [&](const glm::dvec3& position, const Ref& lo, const Ref& hi, int side, bool aim,
                             bool own, Workspace& ws) {
    const SlicingPlane &below = plan.planes[lo.plane], &above = plan.planes[hi.plane];
    const double t = std::clamp(
        (glm::dot(below.normal, position) - below.offset) / (above.offset - below.offset), 0.0, 1.0);
    auto apex = [&](const Ref& r) { return planes[r.plane]->slice.vertices[r.slice_vertex].point; };
    const glm::dvec2 eye(glm::dot(below.u, position), glm::dot(below.w, position));
    const std::span<const Wedge> a = plane_cone(lo, side, own, ws, ws.fan_lo);
    const std::span<const Wedge> b = plane_cone(hi, side, own, ws, ws.fan_hi);
    const std::size_t begin = ws.blended.size(), tangents_begin = ws.tangents.size();
    const bool blended = aim ? aim_wedges(a, apex(lo), b, apex(hi), t, eye, ws.wedge_scratch, ws.blended,
                                          above.offset - below.offset, &ws.tangents)
                             : blend_wedges(a, b, t, ws.wedge_scratch, ws.blended);
    if (blended) {
      ws.blends.push_back({ws.cones.size(), begin, ws.blended.size() - begin, tangents_begin,
                           ws.tangents.size() - tangents_begin});
      ws.cones.push_back({&below, {}});
    } else {
      ws.tangents.resize(tangents_begin);
      const bool lower = t <= 0.5;
      place(lower ? below : above, lower ? a : b, ws);
    }
  };
  const bool aim = rule.combine == ConeStorageRule::Combine::Aim;
  const bool blend = rule.combine != ConeStorageRule::Combine::None;
  auto assemble_vertex = [&](std::size_t v) {
    if (params.progress && v % 64 == 63) params.progress->vertices.fetch_add(64, std::memory_order_relaxed);
    Workspace& ws = workspaces.local();
    if (fan) {  // the vertex's own fan in each orientation's plane through it (fan_cone.hpp)
      ws.ranges.resize(2 * orientations);
      ws.ranged.assign(orientations, 0);
      for (std::size_t o = 0; o < orientations; ++o) {
        const std::size_t k = key_of(0, o, static_cast<Index>(v));
        if (first[k + 1] == first[k] || refs[first[k]].cuts_count == 0) continue;  // no fan cuts listed
        const SlicingPlane& plane = plan.planes[refs[first[k]].plane];
        ws.ranged[o] = fan_local_ranges(topology, connectivity, frame, static_cast<Index>(v), plane,
                                        ws.ranges[2 * o], ws.ranges[2 * o + 1]);
      }
    }
    for (int side = 0; side < 2; ++side) {
      ws.cones.clear();
      ws.blended.clear();
      ws.tangents.clear();
      ws.blends.clear();
      for (std::size_t o = 0; o < orientations; ++o) {
        const std::int32_t from = source[key_of(side, o, static_cast<Index>(v))];
        if (from < 0) continue;
        const std::size_t k = key_of(side, o, static_cast<Index>(from));
        const std::uint32_t count = first[k + 1] - first[k];
        const bool own = from == static_cast<std::int32_t>(v);
        if (blend && count == 2) {  // at the height of the vertex whose cuts these are
          blend_at_vertex(frame.positions[from], refs[first[k]], refs[first[k] + 1], side, aim, own, ws);
          continue;
        }
        for (std::uint32_t i = first[k]; i < first[k + 1]; ++i) {
          const Ref& r = refs[i];
          if (fan && own)
            place(plan.planes[r.plane], plane_cone(r, side, own, ws, ws.fan_lo), ws);
          else
            ws.cones.push_back({&plan.planes[r.plane], cone_of(r, side)});
        }
      }
      for (const Blend& b : ws.blends) {  // ws.blended and ws.tangents have stopped growing
        ws.cones[b.cone].wedges = {ws.blended.data() + b.begin, b.count};
        ws.cones[b.cone].tangents = {ws.tangents.data() + b.tangents_begin, b.tangents_count};
      }
      const glm::dvec3 side_normal = side_sign(static_cast<Side>(side)) * result.normals[v];
      assemble_and_measure_cone(ws.cones, side_normal, ws.scratch, result.cones[side][v],
                                &result.measures[side][v], half_spaces, plan.reconstruction);
    }
    if (params.poll && v % 256 == 0) params.poll();
  };
  assembled = incremental ? to_assemble.size() : std::size_t(receivers);
  auto assemble_at = [&](std::size_t i) { assemble_vertex(incremental ? std::size_t(to_assemble[i]) : i); };
  if (params.parallel)
    tbb::parallel_for(std::size_t(0), assembled, assemble_at);
  else
    for (std::size_t i = 0; i < assembled; ++i) assemble_at(i);
  previous_source.swap(source);
  has_previous = true;
}

FrameAssembler::FrameAssembler(const MeshTopology& topology, const MeshConnectivity& connectivity,
                               const SlicingPlan& plan, const VisibilityParams& params)
    : m_impl(std::make_unique<Impl>(topology, connectivity, plan, params)) {}
FrameAssembler::~FrameAssembler() = default;

void FrameAssembler::assemble(const Frame& frame, const FrameMarks& marks,
                              std::span<const PlaneCones* const> planes, FrameVisibility& result,
                              const AssemblyChanges* changes) {
  m_impl->assemble(frame, marks, planes, result, changes);
}
std::size_t FrameAssembler::last_assembled() const { return m_impl->assembled; }

}  // namespace pleat
