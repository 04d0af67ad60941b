#include "kinetic/kinetic_slice.hpp"

#include <CGAL/FPU.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <optional>
#include <sstream>
#include <unordered_map>

#include "static_core/assert.hpp"

namespace pleat::kinetic {

using cgal::Cdt;
using cgal::FaceHandle;
using cgal::VertexHandle;

const char* rebuild_reason_name(RebuildReason reason) {
  switch (reason) {
    case RebuildReason::none:
      return "none";
    case RebuildReason::degenerate:
      return "degenerate";
    case RebuildReason::crossing:
      return "crossing";
    case RebuildReason::policy:
      return "policy";
    case RebuildReason::repair_failed:
      return "repair_failed";
    case RebuildReason::count:
      break;
  }
  return "?";
}

KineticScratch::KineticScratch() = default;
KineticScratch::~KineticScratch() = default;

namespace {

/// Later events first out of the heap: exact time, then creation order.
struct LaterEvent {
  bool operator()(const KineticScratch::Event& a, const KineticScratch::Event& b) const {
    const int c = compare(a.time, b.time);
    return c != 0 ? c > 0 : a.sequence > b.sequence;
  }
};

/// An infinite face (oo, a, b) walks the hull clockwise from a to b; `next` is the infinite face (oo, b, c).
struct HullCorner {
  VertexHandle a, b, c;
};

HullCorner hull_corner(const Cdt& cdt, FaceHandle f) {
  const int i = f->index(cdt.infinite_vertex());
  const FaceHandle g = f->neighbor(Cdt::ccw(i));
  const int j = g->index(cdt.infinite_vertex());
  return {f->vertex(Cdt::ccw(i)), f->vertex(Cdt::cw(i)), g->vertex(Cdt::cw(j))};
}

/// The moving points of face f's certificate, in the order whose orientation must stay non-negative: a finite
/// face (v0, v1, v2); an infinite face (oo, a, b) the hull corner (c, b, a) at b. False when there is nothing
/// to certify (a hull of two vertices, only while the slice degenerates).
template <class Motion>
bool certificate_points(const Cdt& cdt, FaceHandle f, const Motion& motion, std::array<MovingPoint, 3>& p) {
  if (cdt.is_infinite(f)) {
    const HullCorner h = hull_corner(cdt, f);
    if (h.a == h.c) return false;
    p = {motion(h.c), motion(h.b), motion(h.a)};
  } else {
    p = {motion(f->vertex(0)), motion(f->vertex(1)), motion(f->vertex(2))};
  }
  return true;
}

/// Flips the edge (f, i) (either face may be infinite) and keeps the constraint flags of the four outer
/// edges, as CGAL's Constrained_triangulation_2::flip does, without its geometric preconditions (the points
/// are those of t = 0 while the flip happens at the event time). Precondition: (f, i) is not constrained.
/// Returns false, changing nothing, when the flip is combinatorially impossible: the two opposite vertices
/// are one vertex or already joined by an edge (a repair sequence decided on doubles can lead there).
bool flip_edge(Cdt& cdt, FaceHandle f, int i) {
  const FaceHandle g = f->neighbor(i);
  const int j = cdt.mirror_index(f, i);
  if (f->vertex(i) == g->vertex(j) || cdt.tds().is_edge(f->vertex(i), g->vertex(j))) return false;
  std::array<std::pair<FaceHandle, int>, 4> outer{
      {{f->neighbor(Cdt::cw(i)), cdt.mirror_index(f, Cdt::cw(i))},
       {f->neighbor(Cdt::ccw(i)), cdt.mirror_index(f, Cdt::ccw(i))},
       {g->neighbor(Cdt::cw(j)), cdt.mirror_index(g, Cdt::cw(j))},
       {g->neighbor(Cdt::ccw(j)), cdt.mirror_index(g, Cdt::ccw(j))}}};
  cdt.tds().flip(f, i);
  f->set_constraint(f->index(g), false);
  g->set_constraint(g->index(f), false);
  for (const auto& [h, k] : outer)
    h->neighbor(k)->set_constraint(cdt.mirror_index(h, k), h->is_constrained(k));
  return true;
}

}  // namespace

std::string event_invariants(const Cdt& cdt, std::span<const SliceVertex> next,
                             const std::vector<KineticScratch::Event>& queue, const RootTime& t,
                             std::size_t constraints) {
  auto motion = [&](VertexHandle v) {
    return MovingPoint{cgal::to_glm(v->point()), next[v->info().slice_vertex].point};
  };
  if (!cdt.tds().is_valid()) return "the triangulation's combinatorics are invalid";
  std::size_t constrained = 0;
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f)
    for (int i = 0; i < 3; ++i) {
      if (f->is_constrained(i) != f->neighbor(i)->is_constrained(cdt.mirror_index(f, i)))
        return "a constraint flag differs on the two sides of an edge";
      constrained += f->is_constrained(i);
    }
  if (constrained != 2 * constraints)
    return std::to_string(constrained / 2) + " constrained edges for " + std::to_string(constraints) +
           " chain edges";
  std::unordered_map<const void*, const KineticScratch::Event*> live;
  for (const KineticScratch::Event& e : queue) {
    if (e.face->info().version != e.version) continue;
    if (compare(e.time, t) < 0) return "a live event lies in the past";
    if (!live.emplace(&*e.face, &e).second) return "a face has two live events";
  }
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) {
    const auto it = live.find(&*f);
    const KineticScratch::Event* pending = it == live.end() ? nullptr : it->second;
    std::array<MovingPoint, 3> p;
    if (!certificate_points(cdt, f, motion, p)) {
      if (pending) return "a two-vertex hull has an event";
      continue;
    }
    {
      CGAL::Protect_FPU_rounding<true> rounding;
      if (certainly_positive(p[0], p[1], p[2])) {
        if (pending) return "a face positive over the interval has an event";
        continue;
      }
    }
    const ExactPolynomial poly = orientation_polynomial(p[0], p[1], p[2]);
    const bool hull = cdt.is_infinite(f);
    if (pending && pending->fails && !poly.is_zero() && sign_after(poly, pending->time) >= 0 &&
        !(pending->time == RootTime::one() && sign_at(poly, pending->time) == 0))
      return "an event claims a failure its certificate does not have";
    if (poly.is_zero()) {
      if (hull ? pending != nullptr : !(pending && pending->time == t))
        return hull ? "a hull corner flat for all t has an event"
                    : "a triangle flat for all t is not repaired now";
      continue;
    }
    if (t == RootTime::one()) {
      // The end of the interval: every triangle must be strictly positive (one degenerate at t = 1 is
      // flipped, since static_core has none), a hull corner may be flat.
      const int s = sign_at(poly, t);
      if (hull ? s < 0 : s <= 0) {
        // A reflex hull corner at t = 1 can only follow a flip chosen on doubles; with its event now (a flip
        // at t = 1 made it), the exact guard after the events rebuilds the slice.
        if (!(pending && pending->time == t))
          return hull ? "a hull corner is reflex at t = 1"
                      : "a triangle flat or inverted at t = 1 has no event now";
      } else if (pending && !(s == 0 && pending->time == t)) {
        return "a certificate that holds at t = 1 has an event";
      }
      continue;
    }
    if (sign_after(poly, t) < 0) {
      if (!(pending && pending->time == t)) return "an inverted certificate has no event now";
      continue;
    }
    if (pending && pending->time == t && sign_at(poly, t) == 0)
      continue;  // this instant's touch, still queued
    const std::optional<RootTime> next = first_root_after(poly, t);
    if (next.has_value() != (pending != nullptr) || (next && !(pending->time == *next)))
      return "a certificate's event is not at its first zero";
  }
  return {};
}

void KineticSlice::build(const MeshTopology& topology, const MeshEdges& edges, const Frame& frame,
                         const SlicingPlane& plane, ConeStorage storage, std::span<const Index> faces,
                         KineticScratch& scratch) {
  m_storage = storage;
  slice_mesh(topology, edges, frame, plane, faces, scratch.slicer, m_out.slice);
  finish_build(topology, frame, scratch);
}

void KineticSlice::finish_build(const MeshTopology& topology, const Frame& frame, KineticScratch& scratch) {
  m_tri.build(m_out.slice);
  m_out.crossings = m_tri.crossings();
  m_editable = m_tri.dimension() == 2 && m_out.crossings == 0 &&
               m_tri.cdt().number_of_vertices() == m_out.slice.vertices.size() && chains_are_edges();
  grow_cones(topology, frame, scratch);
}

void KineticSlice::finish_frame(const MeshTopology& topology, const Frame& frame, bool structure_changed,
                                KineticScratch& scratch) {
  std::swap(m_out.slice, m_next);
  m_tri.adopt_edits(m_out.slice, structure_changed);
  m_out.crossings = 0;
  grow_cones(topology, frame, scratch);
}

void KineticSlice::grow_cones(const MeshTopology& topology, const Frame& frame, KineticScratch& scratch) {
  compute_plane_cones(topology.num_vertices, m_storage, frame, m_tri, scratch.cones, m_out);
}

SliceEventCounts KineticSlice::advance(const MeshTopology& topology, const MeshEdges& edges,
                                       const Frame& next, const SlicingPlane& plane,
                                       std::span<const Index> faces, const KineticPolicy& policy,
                                       KineticScratch& scratch, bool check_every_event) {
  SliceEventCounts counts;
  m_changed_edges.clear();
  slice_mesh(topology, edges, next, plane, faces, scratch.slicer, m_next);
  auto rebuild = [&](RebuildReason reason) {
    counts.rebuild = reason;
    counts.structure_changed = true;
    std::swap(m_out.slice, m_next);
    finish_build(topology, next, scratch);
    return counts;
  };
  if (!m_editable) return rebuild(RebuildReason::degenerate);

  // Match slice vertices by mesh edge: survivors, and those that vanish or appear.
  const Slice& old = m_out.slice;
  if (scratch.old_of_edge.size() != edges.endpoints.size())
    scratch.old_of_edge.assign(edges.endpoints.size(), -1);
  for (Index x = 0; x < old.vertices.size(); ++x)
    scratch.old_of_edge[old.vertices[x].edge] = static_cast<std::int32_t>(x);
  scratch.new_of_old.assign(old.vertices.size(), -1);
  scratch.born.clear();
  scratch.is_born.assign(m_next.vertices.size(), 0);
  for (Index y = 0; y < m_next.vertices.size(); ++y) {
    const std::int32_t x = scratch.old_of_edge[m_next.vertices[y].edge];
    if (x >= 0)
      scratch.new_of_old[x] = static_cast<std::int32_t>(y);
    else {
      scratch.born.push_back(y);
      m_changed_edges.push_back(m_next.vertices[y].edge);
      scratch.is_born[y] = 1;
    }
  }
  for (Index x = 0; x < old.vertices.size(); ++x) {
    scratch.old_of_edge[old.vertices[x].edge] = -1;
    if (scratch.new_of_old[x] < 0) m_changed_edges.push_back(old.vertices[x].edge);
  }
  counts.inserted = scratch.born.size();
  counts.removed = old.vertices.size() + counts.inserted - m_next.vertices.size();
  if (double(counts.removed + counts.inserted) > policy.max_edit_fraction * double(old.vertices.size()) + 2.0)
    return rebuild(RebuildReason::policy);

  // 1. Remove the vanishing slice vertices at t = 0; survivors take their new ids.
  Cdt& cdt = m_tri.cdt_for_editing();
  scratch.vertex_of_new.assign(m_next.vertices.size(), VertexHandle());
  for (Index x = 0; x < old.vertices.size(); ++x) {
    const VertexHandle v = m_tri.vertex_of(x);
    if (const std::int32_t y = scratch.new_of_old[x]; y >= 0) {
      v->info().slice_vertex = y;
      scratch.vertex_of_new[y] = v;
      continue;
    }
    cdt.remove_incident_constraints(v);
    // Constrained_triangulation_2's removal (ear filling of the star-shaped hole), not the Delaunay one:
    // the kept triangulation is not Delaunay, and the Delaunay hole filling can cycle on it.
    cdt.Cdt::Ctr::remove(v);
    if (cdt.dimension() < 2) return rebuild(RebuildReason::degenerate);
  }

  // 2. Move the survivors from t = 0 to t = 1, repairing at every event.
  std::optional<std::size_t> surviving_chain_edges;
  if (check_every_event) {
    surviving_chain_edges = 0;
    for (const SliceEdge& e : old.edges)
      *surviving_chain_edges += scratch.new_of_old[e.from] >= 0 && scratch.new_of_old[e.to] >= 0;
  }
  if (const RebuildReason r = move_survivors(policy, surviving_chain_edges, scratch, counts);
      r != RebuildReason::none)
    return rebuild(r);

  // 3. Insert the appearing slice vertices and their chain edges at t = 1.
  for (Index y : scratch.born) {
    const VertexHandle v = cdt.insert(cgal::to_point(m_next.vertices[y].point));
    if (v->info().slice_vertex != -1)
      return rebuild(RebuildReason::degenerate);  // coincides with another point
    v->info().slice_vertex = static_cast<int>(y);
    scratch.vertex_of_new[y] = v;
  }
  if (!scratch.born.empty()) {
    const std::size_t vertices = cdt.number_of_vertices();
    for (const SliceEdge& e : m_next.edges) {
      const VertexHandle a = scratch.vertex_of_new[e.from], b = scratch.vertex_of_new[e.to];
      if (scratch.is_born[e.from] || scratch.is_born[e.to]) cdt.insert_constraint(a, b);
    }
    if (cdt.number_of_vertices() != vertices) return rebuild(RebuildReason::crossing);
  }
  counts.structure_changed =
      counts.removed + counts.inserted + counts.flips + counts.hull_enter + counts.hull_leave > 0;
  finish_frame(topology, next, counts.structure_changed, scratch);
  return counts;
}

RebuildReason KineticSlice::move_survivors(const KineticPolicy& policy,
                                           std::optional<std::size_t> check_constraints,
                                           KineticScratch& scratch, SliceEventCounts& counts) {
  Cdt& cdt = m_tri.cdt_for_editing();
  const VertexHandle infinite = cdt.infinite_vertex();
  auto motion = [&](VertexHandle v) {
    return MovingPoint{cgal::to_glm(v->point()), m_next.vertices[v->info().slice_vertex].point};
  };
  auto& queue = scratch.queue;
  queue.clear();
  std::uint64_t sequence = 0;
  auto schedule = [&](const RootTime& time, FaceHandle f, CertificatePolynomial certificate, bool fails) {
    queue.push_back({time, f, f->info().version, fails, sequence++, std::move(certificate)});
    std::push_heap(queue.begin(), queue.end(), LaterEvent());
  };
  // (Re)certifies face f from time t0: a finite face stays positively oriented; an infinite face (oo, a, b)
  // certifies the hull corner at b (orient(c, b, a) >= 0). A certificate that already fails just after t0 (a
  // repair left a triangle inverted right away, or degenerate for all t) gets its event at t0.
  auto certify = [&](FaceHandle f, const RootTime& t0) {
    ++f->info().version;
    ++counts.certificates;
    std::array<MovingPoint, 3> p;
    if (!certificate_points(cdt, f, motion, p)) return;
    CertificateFailure failure = first_failure(p, t0, !cdt.is_infinite(f));
    counts.exact_certificates += failure.decided_by != CertificateFailure::DecidedBy::filter;
    if (failure.time) schedule(*failure.time, f, std::move(failure.certificate), failure.fails);
  };
  // The policy's bound, and in any case a bound on same-instant cascades (flips at one exact time that keep
  // producing degenerate triangles) and on the total (a kinetic triangulation has O(n^2) events at most).
  const std::size_t n = cdt.number_of_vertices();
  const std::size_t max_events = std::min<std::size_t>(
      16 + static_cast<std::size_t>(policy.max_events_per_vertex * double(n)), 4 * n * n + 64);
  const std::size_t max_same_instant = n + 16;
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) {
    certify(f, RootTime::zero());
    // More certificates fail than the policy allows events: rebuild now, before certifying the rest.
    // Or more are left undecided by the filter (about 5 us each on average; a sign of degenerate motion).
    if (queue.size() > max_events || counts.exact_certificates > max_events) return RebuildReason::policy;
  }
  // check_every_event: the kinetic invariants after each event (event_invariants); a violation is a bug.
  auto check = [&](const RootTime& t) {
    if (!check_constraints) return;
    const std::string why = event_invariants(cdt, m_next.vertices, queue, t, *check_constraints);
    if (why.empty()) return;
    std::ostringstream message;
    message << "kinetic invariant after the event at " << t << ": " << why;
    throw InvariantError(message.str());  // thrown whatever PLEAT_CHECK_INVARIANTS says: the caller asked
  };
  check(RootTime::zero());

  // After a flip of (f, i) at time t: the two new faces and, around every new infinite face, the hull corners
  // whose neighbours changed.
  std::vector<FaceHandle>& touched = scratch.touched;
  auto recertify_around = [&](FaceHandle f, FaceHandle g, const RootTime& t) {
    touched.clear();
    for (FaceHandle h : {f, g}) {
      touched.push_back(h);
      if (!cdt.is_infinite(h)) continue;
      const int i = h->index(infinite);
      touched.push_back(h->neighbor(Cdt::cw(i)));   // the previous hull corner
      touched.push_back(h->neighbor(Cdt::ccw(i)));  // the next one
    }
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    for (FaceHandle h : touched) certify(h, t);
  };

  std::size_t same_instant = 0;
  RootTime last_time;
  const RootTime one = RootTime::one();
  while (!queue.empty()) {
    std::pop_heap(queue.begin(), queue.end(), LaterEvent());
    KineticScratch::Event event = std::move(queue.back());
    queue.pop_back();
    const FaceHandle f = event.face;
    if (f->info().version != event.version) continue;  // replaced by a repair
    if (counts.events() >= max_events || counts.exact_certificates > max_events) return RebuildReason::policy;
    same_instant = event.time == last_time ? same_instant + 1 : 0;
    if (same_instant > max_same_instant) return RebuildReason::policy;
    last_time = event.time;
    const bool at_end = event.time == one;
    // Before t = 1, an event not known to fail may be a touch: decide exactly. (At t = 1 a triangle is
    // flipped and a hull corner left flat, whatever the sign after.)
    bool inverts = event.fails;
    ExactPolynomial poly;
    if (!inverts && !at_end) {
      poly = event.certificate.exact();
      inverts = poly.is_zero() || sign_after(poly, event.time) < 0;
    }
    if (at_end ? cdt.is_infinite(f) : !inverts) {
      // A certificate that touches zero and keeps its sign, or a hull corner flat at t = 1 (static_core keeps
      // collinear hull points as hull vertices): no repair; look for its next zero.
      ++counts.touches;
      if (!at_end)
        if (auto next = first_root_after(poly, event.time))
          schedule(*next, f, std::move(event.certificate), false);
      check(event.time);
      continue;
    }
    if (cdt.is_infinite(f)) {
      const int i = f->index(infinite);
      const FaceHandle g = f->neighbor(Cdt::ccw(i));
      // Edge (b, oo): b leaves the hull, triangle (a, b, c) appears.
      if (!flip_edge(cdt, f, Cdt::ccw(i))) return RebuildReason::repair_failed;
      ++counts.hull_leave;
      recertify_around(f, g, event.time);
      check(event.time);
      continue;
    }
    // The triangle collapses: flip the edge opposite the vertex that lies between the other two. (Chosen on
    // doubles at the event time; the exact check at t = 1 guards the outcome.)
    const double t = event.time.approximate();
    int k = 0;
    double most_between = INFINITY;
    for (int m = 0; m < 3; ++m) {
      const glm::dvec2 pm = motion(f->vertex(m)).at(t);
      const double d =
          glm::dot(motion(f->vertex(Cdt::ccw(m))).at(t) - pm, motion(f->vertex(Cdt::cw(m))).at(t) - pm);
      if (d < most_between) most_between = d, k = m;
    }
    if (f->is_constrained(k)) return RebuildReason::crossing;  // a vertex reaches a chain edge
    const FaceHandle g = f->neighbor(k);
    ++(cdt.is_infinite(g) ? counts.hull_enter : counts.flips);
    if (!flip_edge(cdt, f, k)) return RebuildReason::repair_failed;
    recertify_around(f, g, event.time);
    check(event.time);
  }

  // Every vertex at its t = 1 point; then the exact guard: the static engine's predicates on these points.
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v)
    v->set_point(cgal::to_point(m_next.vertices[v->info().slice_vertex].point));
  // Flips at t = 1 can fold every triangle of a slice that becomes collinear into the outside: no finite
  // face is left, which the face count exposes (static_core's triangulation then has dimension 1).
  const std::size_t hull_size = cdt.degree(infinite);
  if (cdt.number_of_faces() == 0 || cdt.number_of_faces() + hull_size + 2 != 2 * cdt.number_of_vertices())
    return RebuildReason::degenerate;
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) {
    // Two faces that share two edges (a repair sequence decided on doubles can fold the hull onto itself).
    for (int i = 0; i < 3; ++i)
      if (f->neighbor(i)->index(f) != cdt.mirror_index(f, i)) return RebuildReason::repair_failed;
    if (cdt.is_infinite(f)) {
      const HullCorner h = hull_corner(cdt, f);
      if (h.a == h.c || CGAL::orientation(h.c->point(), h.b->point(), h.a->point()) == CGAL::RIGHT_TURN)
        return RebuildReason::repair_failed;
    } else if (CGAL::orientation(f->vertex(0)->point(), f->vertex(1)->point(), f->vertex(2)->point()) !=
               CGAL::LEFT_TURN) {
      return RebuildReason::repair_failed;
    }
  }
  return RebuildReason::none;
}

bool KineticSlice::chains_are_edges() const {
  const Cdt& cdt = m_tri.cdt();
  for (const SliceEdge& e : m_out.slice.edges) {
    const VertexHandle a = m_tri.vertex_of(e.from), b = m_tri.vertex_of(e.to);
    FaceHandle f;
    int i = 0;
    if (a != b && (!cdt.is_edge(a, b, f, i) || !f->is_constrained(i))) return false;
  }
  return true;
}

bool KineticSlice::check_invariants(std::string* why) const {
  auto fail = [&](const std::string& message) {
    if (why) *why = message;
    return false;
  };
  // Orientations, hull convexity and the triangulation's combinatorics: CGAL's check, inside this one.
  if (!m_tri.check_invariants(why)) return false;
  const Cdt& cdt = m_tri.cdt();
  // A slice that is not editable (chains cross or touch, points merged, or not 2D) is rebuilt every interval:
  // CGAL's own split constraints are its invariant, checked above.
  if (m_tri.dimension() < 2 || !m_editable) return true;
  // The constraints are exactly the chain edges between distinct points (several chain edges may join the
  // same two points where slice points coincide: a mesh edge lying in the plane).
  std::size_t constrained = 0;
  for (auto e = cdt.finite_edges_begin(); e != cdt.finite_edges_end(); ++e)
    constrained += cdt.is_constrained(*e);
  std::vector<std::pair<const void*, const void*>> chain_edges;
  for (const SliceEdge& e : m_out.slice.edges) {
    const VertexHandle a = m_tri.vertex_of(e.from), b = m_tri.vertex_of(e.to);
    if (a == b) continue;
    const void* pa = &*a;
    const void* pb = &*b;
    chain_edges.emplace_back(std::less<const void*>()(pa, pb) ? std::make_pair(pa, pb)
                                                              : std::make_pair(pb, pa));
    FaceHandle f;
    int i = 0;
    if (!cdt.is_edge(a, b, f, i) || !f->is_constrained(i))
      return fail("a chain edge is not a constrained edge");
  }
  std::sort(chain_edges.begin(), chain_edges.end());
  const std::size_t distinct = std::unique(chain_edges.begin(), chain_edges.end()) - chain_edges.begin();
  if (m_out.crossings == 0 && constrained != distinct) return fail("a constrained edge is not a chain edge");
  return true;
}

}  // namespace pleat::kinetic
