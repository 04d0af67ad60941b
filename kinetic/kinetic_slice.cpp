#include "kinetic/internal/kinetic_slice.hpp"

#include <algorithm>
#include <chrono>

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
    case RebuildReason::cost:
      return "cost";
    case RebuildReason::frame_cost:
      return "frame_cost";
    case RebuildReason::no_cones:
      return "no_cones";
    case RebuildReason::count:
      break;
  }
  return "?";
}

KineticScratch::KineticScratch() = default;
KineticScratch::~KineticScratch() = default;

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// An infinite face (oo, a, b) walks the hull clockwise from a to b; the next one, (oo, b, c), from b to c.
FaceHandle next_hull_face(const Cdt& cdt, FaceHandle f) {
  return f->neighbor(Cdt::ccw(f->index(cdt.infinite_vertex())));
}
FaceHandle previous_hull_face(const Cdt& cdt, FaceHandle f) {
  return f->neighbor(Cdt::cw(f->index(cdt.infinite_vertex())));
}

/// The hull corner at b of the infinite face f = (oo, a, b): a -> b -> c.
struct HullCorner {
  VertexHandle a, b, c;
};

HullCorner hull_corner(const Cdt& cdt, FaceHandle f) {
  const int i = f->index(cdt.infinite_vertex());
  const FaceHandle g = next_hull_face(cdt, f);
  return {f->vertex(Cdt::ccw(i)), f->vertex(Cdt::cw(i)), g->vertex(Cdt::cw(g->index(cdt.infinite_vertex())))};
}

/// Whether (a, b) is one constrained edge of the triangulation.
bool is_constrained_edge(const Cdt& cdt, VertexHandle a, VertexHandle b) {
  FaceHandle f;
  int i = 0;
  return cdt.is_edge(a, b, f, i) && f->is_constrained(i);
}

/// Every chain edge between distinct points is a single constrained edge of the triangulation; `vertex_of`
/// maps a slice vertex to its triangulation vertex.
template <class VertexOf>
bool chains_are_edges(const Cdt& cdt, const std::vector<SliceEdge>& edges, VertexOf&& vertex_of) {
  for (const SliceEdge& e : edges) {
    const VertexHandle a = vertex_of(e.from), b = vertex_of(e.to);
    if (a != b && !is_constrained_edge(cdt, a, b)) return false;
  }
  return true;
}

/// Follows `slice`'s chain from the vertex after `from` while `in_run` holds (a vertex inside a chain: one
/// edge in, one out, by `degree`), collecting the vertices into `run`; returns the first vertex past them, or
/// -1 at the chain's end.
template <class InRun>
std::int32_t follow_run(const Slice& slice, const std::vector<Index>& degree, Index from, InRun&& in_run,
                        std::vector<Index>& run) {
  auto next = [&](Index x) {
    const std::int32_t e = slice.out_edge[x];
    return e < 0 ? -1 : static_cast<std::int32_t>(slice.edges[e].to);
  };
  run.clear();
  std::int32_t x = next(from);
  while (x >= 0 && in_run(x) && degree[x] == 2 && slice.in_edge[x] >= 0 &&
         run.size() < slice.vertices.size()) {
    run.push_back(x);
    x = next(x);
  }
  return x;
}

/// The fan swaps of an interval (docs/method.md §11.2, step 1): per vanishing slice vertex of `old`, the
/// slice vertex of `next` that takes its triangulation vertex (scratch.relabel, -1 for none), those new
/// vertices unmarked in scratch.is_born, and the old closing edges of runs that grow (scratch.unconstrain).
/// A run is followed only through slice vertices inside a chain (one edge in, one edge out), so a chain's
/// end or a non-manifold place is never relabeled. Returns the number of relabeled vertices.
std::size_t find_fan_swaps(const Slice& old, const Slice& next, KineticScratch& scratch) {
  scratch.relabel.assign(old.vertices.size(), -1);
  scratch.unconstrain.clear();
  // Chain edges at each slice vertex: 2, with an in and an out edge, is a vertex inside a chain.
  auto degrees = [](const Slice& slice, std::vector<Index>& degree) {
    degree.assign(slice.vertices.size(), 0);
    for (const SliceEdge& e : slice.edges) ++degree[e.from], ++degree[e.to];
  };
  degrees(old, scratch.degree_old);
  degrees(next, scratch.degree_next);
  std::size_t relabeled = 0;
  for (Index p = 0; p < old.vertices.size(); ++p) {
    const std::int32_t pn = scratch.new_of_old[p];
    if (pn < 0) continue;
    const std::int32_t x = follow_run(
        old, scratch.degree_old, p, [&](Index v) { return scratch.new_of_old[v] < 0; }, scratch.run_old);
    if (scratch.run_old.empty() || x < 0 || scratch.new_of_old[x] < 0) continue;  // not between survivors
    const std::int32_t y = follow_run(
        next, scratch.degree_next, Index(pn), [&](Index v) { return scratch.is_born[v] != 0; },
        scratch.run_new);
    if (scratch.run_new.empty() || y != scratch.new_of_old[x]) continue;  // not the same two survivors
    const std::size_t r = std::min(scratch.run_old.size(), scratch.run_new.size());
    for (std::size_t i = 0; i < r; ++i) {
      scratch.relabel[scratch.run_old[i]] = static_cast<std::int32_t>(scratch.run_new[i]);
      scratch.is_born[scratch.run_new[i]] = 0;
    }
    if (r < scratch.run_new.size()) scratch.unconstrain.emplace_back(scratch.run_old[r - 1], Index(x));
    relabeled += r;
  }
  return relabeled;
}

/// Matches the slices of frame k (`old`) and k+1 (scratch.next) by mesh edge: scratch.new_of_old (-1: the
/// slice vertex vanishes), scratch.born and scratch.is_born (the slice vertices that appear), and the mesh
/// edges that started or stopped crossing the plane appended to `changed_edges`. Returns how many vanish.
std::size_t match_slice_vertices(const Slice& old, std::size_t num_edges, KineticScratch& scratch,
                                 std::vector<Index>& changed_edges) {
  if (scratch.old_of_edge.size() != num_edges) scratch.old_of_edge.assign(num_edges, -1);
  for (Index x = 0; x < old.vertices.size(); ++x)
    scratch.old_of_edge[old.vertices[x].edge] = static_cast<std::int32_t>(x);
  scratch.new_of_old.assign(old.vertices.size(), -1);
  scratch.born.clear();
  scratch.is_born.assign(scratch.next.vertices.size(), 0);
  for (Index y = 0; y < scratch.next.vertices.size(); ++y) {
    const std::int32_t x = scratch.old_of_edge[scratch.next.vertices[y].edge];
    if (x >= 0)
      scratch.new_of_old[x] = static_cast<std::int32_t>(y);
    else {
      scratch.born.push_back(y);
      changed_edges.push_back(scratch.next.vertices[y].edge);
      scratch.is_born[y] = 1;
    }
  }
  for (Index x = 0; x < old.vertices.size(); ++x) {
    scratch.old_of_edge[old.vertices[x].edge] = -1;
    if (scratch.new_of_old[x] < 0) changed_edges.push_back(old.vertices[x].edge);
  }
  return old.vertices.size() + scratch.born.size() - scratch.next.vertices.size();
}

/// Step 1 of an interval (docs/method.md §11.2): in `tri`, restored at frame k, survivors and relabeled
/// vertices take their new ids; the old closing edges of growing runs stop being constraints; the vanishing
/// vertices that no fan swap relabels get id -1 and are listed in scratch.vanishing, their chain neighbours
/// marked in scratch.chain_loose.
void hand_over_vertices(const Slice& old, SliceTriangulation& tri, KineticScratch& scratch) {
  Cdt& cdt = tri.cdt_for_editing();
  for (const auto& [a, b] : scratch.unconstrain) {
    FaceHandle f;
    int i = 0;
    if (cdt.is_edge(tri.vertex_of(a), tri.vertex_of(b), f, i) && f->is_constrained(i))
      cdt.Cdt::Ctr::remove_constrained_edge(f, i);  // only the mark: no flips on the kept triangulation
  }
  scratch.vertex_of_new.assign(scratch.next.vertices.size(), VertexHandle());
  scratch.vanishing.clear();
  scratch.chain_loose.assign(scratch.next.vertices.size(), 0);
  auto new_id = [&](Index x) { return std::max(scratch.new_of_old[x], scratch.relabel[x]); };
  for (Index x = 0; x < old.vertices.size(); ++x) {
    const VertexHandle v = tri.vertex_of(x);
    const std::int32_t y = new_id(x);
    v->info().slice_vertex = y;
    if (y >= 0) {
      scratch.vertex_of_new[y] = v;
      continue;
    }
    scratch.vanishing.push_back(v);
    // Its chain neighbours lose their constrained edges to it.
    auto loosen = [&](Index n) {
      if (const std::int32_t z = new_id(n); z >= 0) scratch.chain_loose[z] = 1;
    };
    if (const std::int32_t e = old.in_edge[x]; e >= 0) loosen(old.edges[e].from);
    if (const std::int32_t e = old.out_edge[x]; e >= 0) loosen(old.edges[e].to);
  }
}

/// Step 3, first part: every kept vertex of `cdt` moves to its next point and the planned flips are made
/// (counted in counts.flipped). Returns repair_failed when the hull then winds more than once, else none.
RebuildReason move_kept_vertices(Cdt& cdt, KineticScratch& scratch, KineticCounts& counts) {
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v)
    v->set_point(cgal::to_point(scratch.next.vertices[v->info().slice_vertex].point));
  for (PlannedFlip& flip : scratch.flips)
    if (flip.face != FaceHandle()) {
      cdt.flip(flip.face, flip.index);
      ++counts.flipped;
    }
  return hull_winds_once(cdt) ? RebuildReason::none : RebuildReason::repair_failed;
}

/// Step 3, second part: the vertices taken out (appended to scratch.born) and the new ones inserted at their
/// next points, each located from a kept chain neighbour. Returns degenerate when one meets another slice
/// point, crossing when one lies on a chain edge, else none.
RebuildReason insert_born_vertices(Cdt& cdt, KineticScratch& scratch) {
  for (Index y = 0; y < scratch.next.vertices.size(); ++y)
    if (scratch.taken_out[y]) scratch.born.push_back(y);
  FaceHandle hint;
  for (Index y : scratch.born) {
    // Located from a kept chain neighbour when there is one (a short walk), else from the last insertion.
    for (const std::int32_t e : {scratch.next.out_edge[y], scratch.next.in_edge[y]}) {
      if (e < 0) continue;
      const SliceEdge& edge = scratch.next.edges[e];
      const VertexHandle w = scratch.vertex_of_new[edge.from == y ? edge.to : edge.from];
      if (w != VertexHandle()) {
        hint = w->face();
        break;
      }
    }
    const cgal::Point2 p = cgal::to_point(scratch.next.vertices[y].point);
    Cdt::Locate_type type;
    int li = 0;
    const FaceHandle at = cdt.locate(p, type, li, hint);
    if (type == Cdt::VERTEX) return RebuildReason::degenerate;  // meets another slice point
    if (type == Cdt::EDGE && at->is_constrained(li)) return RebuildReason::crossing;  // a chain
    const VertexHandle v = cdt.insert(p, type, at, li);
    v->info().slice_vertex = static_cast<int>(y);
    scratch.vertex_of_new[y] = v;
    hint = v->face();
  }
  return RebuildReason::none;
}

/// Step 3, last part: every chain edge that may not be a constrained edge yet inserted as one. Returns
/// crossing when the chains cross or touch (a chain edge no longer one constrained edge), else none.
RebuildReason constrain_loose_chains(Cdt& cdt, KineticScratch& scratch) {
  // Chain edges that may not be constrained edges yet: those of new and put-back vertices, and those
  // beside removed vertices (the closing edges of runs that shrank, the edges of critical crossings).
  for (Index y : scratch.born) scratch.chain_loose[y] = 1;
  const std::size_t vertices = cdt.number_of_vertices();
  bool inserted = false;
  for (const SliceEdge& e : scratch.next.edges)
    if (scratch.chain_loose[e.from] || scratch.chain_loose[e.to])
      inserted |= cgal::insert_constraint(cdt, scratch.vertex_of_new[e.from], scratch.vertex_of_new[e.to]) ==
                  cgal::ConstraintInsertion::inserted;
  // Chains that cross or touch: a chain edge that crosses another is split at a new vertex; one through a
  // slice point is split there; and a new slice point lying on a kept chain edge to within rounding
  // (located just off it, in a face) makes its own chain edge "cross" the kept one at a point CGAL snaps
  // to the new vertex, splitting the kept edge with no vertex added (tests/fuzz/regressions/fuzz_engines/
  // kept_chain_edge_lost.bin). So where CGAL inserted a constraint (marking an edge changes no other), every
  // chain edge, new or kept, must still be one constrained edge; else the slice is rebuilt, as crossing
  // chains are.
  if (inserted &&
      (cdt.number_of_vertices() != vertices ||
       !chains_are_edges(cdt, scratch.next.edges, [&](Index y) { return scratch.vertex_of_new[y]; })))
    return RebuildReason::crossing;
  return RebuildReason::none;
}

/// Step 2 of an interval (docs/method.md §11.2), on the triangulation in `scratch` at frame k's points: the
/// certificates at the next frame, the flips that repair them planned, and the removals of vertices.
/// Reservations of faces by planned flips live in their info().index (PlannedFlip).
class NextFrameCertifier {
 public:
  NextFrameCertifier(KineticScratch& scratch, KineticCounts& counts)
      : m_scratch(scratch),
        m_cdt(scratch.triangulation.cdt_for_editing()),
        m_next(scratch.next.vertices),
        m_counts(counts) {}

  /// Certifies face f at the next frame; a failure plans a flip or queues the vertex it takes out. Faces of
  /// a vanishing vertex are not certified: its removal replaces them.
  void certify(FaceHandle f);
  /// Removes v at frame k's points (the triangulation is valid there), cancelling the flips planned on its
  /// faces and queueing its neighbours for a recheck: every face the removal creates has its vertices among
  /// them. False when the triangulation is no longer 2D.
  bool remove(VertexHandle v);

 private:
  cgal::Point2 next_point(VertexHandle v) const {
    return cgal::to_point(m_next[v->info().slice_vertex].point);
  }
  bool is_gone(VertexHandle v) const {
    const int y = v->info().slice_vertex;
    return y < 0 || m_scratch.taken_out[y];
  }
  static bool is_free(FaceHandle f) { return f->info().index == -1; }
  void reserve(const PlannedFlip& flip);
  bool convex_corner(VertexHandle previous, VertexHandle x, VertexHandle following) const;
  bool plan_triangle_flip(FaceHandle f);
  bool plan_hull_flip(FaceHandle f);
  void cancel(int n);

  KineticScratch& m_scratch;
  Cdt& m_cdt;
  const std::vector<SliceVertex>& m_next;
  KineticCounts& m_counts;
};

/// Reserves the faces of `flip` (its number in info().index) and plans it.
void NextFrameCertifier::reserve(const PlannedFlip& flip) {
  const int n = static_cast<int>(m_scratch.flips.size());
  flip.face->info().index = flip.face->neighbor(flip.index)->info().index = n;
  if (flip.before != FaceHandle()) flip.before->info().index = n, flip.after->info().index = -2 - n;
  m_scratch.flips.push_back(flip);
}

/// Whether the hull corner (x_prev, x, x_next), walked in that order, is convex or straight with x between
/// its neighbours at the next frame (the hull-corner certificate).
bool NextFrameCertifier::convex_corner(VertexHandle previous, VertexHandle x, VertexHandle following) const {
  const cgal::Point2 a = next_point(previous), b = next_point(x), c = next_point(following);
  const CGAL::Orientation o = cgal::orientation(c, b, a);
  return o == CGAL::LEFT_TURN ||
         (o == CGAL::COLLINEAR && CGAL::collinear_are_strictly_ordered_along_line(a, b, c));
}

/// A failed triangle f repaired by flipping one of its edges at the next frame: the edge is not a chain
/// edge, the triangle across it is finite and free, none of the four vertices leaves, and the flip's two
/// triangles are positive at the next frame. (The flip then replaces f and its neighbour, which needs no
/// other repair.) Returns whether one qualifies. The new edge may join two vertices joined already (around
/// a vertex of degree 3 that leaves its triangle): flips edit the combinatorial structure, where that is a
/// second edge for a while, and the certificates leave none twice in the end (positive triangles covering
/// the hull once, docs/method.md §11.2): the triangle beside the old edge, with the new triangle's vertices
/// reversed, fails too and is flipped away across that edge, or takes out a vertex of the flip, which
/// cancels it (tests/kinetic_visibility_test.cpp, FlipsMayJoinVerticesJoinedAlready).
bool NextFrameCertifier::plan_triangle_flip(FaceHandle f) {
  for (int i = 0; i < 3; ++i)
    if (is_gone(f->vertex(i))) return false;
  for (int i = 0; i < 3; ++i) {
    if (f->is_constrained(i)) continue;
    const FaceHandle g = f->neighbor(i);
    if (m_cdt.is_infinite(g) || !is_free(g)) continue;
    const VertexHandle v = f->vertex(i), w = g->vertex(m_cdt.mirror_index(f, i));
    if (is_gone(w)) continue;
    const cgal::Point2 apex = next_point(v), p = next_point(w);
    if (cgal::orientation(apex, next_point(f->vertex(Cdt::ccw(i))), p) != CGAL::LEFT_TURN ||
        cgal::orientation(apex, p, next_point(f->vertex(Cdt::cw(i)))) != CGAL::LEFT_TURN)
      continue;
    reserve({f, i, FaceHandle(), FaceHandle()});
    return true;
  }
  return false;
}

/// A reflex hull corner at b, walked a -> b -> c (infinite faces f = (oo, a, b) and g = (oo, b, c)),
/// repaired by flipping the edge (oo, b): b leaves the hull inside the new triangle (a, b, c), positive at
/// the next frame exactly when the corner is strictly reflex. The hull corners at a and c change (a_prev
/// -> a -> c, a -> c -> c_next) and must be convex; the four hull faces from (oo, a_prev, a) to
/// (oo, c, c_next) must be free and no vertex among them leave, and a and c must not be joined yet.
bool NextFrameCertifier::plan_hull_flip(FaceHandle f) {
  const FaceHandle g = next_hull_face(m_cdt, f), before = previous_hull_face(m_cdt, f),
                   after = next_hull_face(m_cdt, g);
  const auto [a, b, c] = hull_corner(m_cdt, f);
  const VertexHandle a_prev = hull_corner(m_cdt, before).a, c_next = hull_corner(m_cdt, g).c;
  if (a_prev == c || !is_free(f) || !is_free(g) || !is_free(before) || !is_free(after)) return false;
  for (const VertexHandle v : {a_prev, a, b, c, c_next})
    if (is_gone(v)) return false;
  if (cgal::orientation(next_point(a), next_point(b), next_point(c)) != CGAL::LEFT_TURN ||
      !convex_corner(a_prev, a, c) || !convex_corner(a, c, c_next) || m_cdt.is_edge(a, c))
    return false;
  reserve({f, f->index(a), before, after});  // the edge (oo, b), opposite a
  return true;
}

/// Cancels flip n (a removal is about to change one of its faces); the certificate it repaired is checked
/// again with its vertices' faces.
void NextFrameCertifier::cancel(int n) {
  PlannedFlip& flip = m_scratch.flips[std::size_t(n)];
  for (const FaceHandle f : {flip.face, flip.face->neighbor(flip.index), flip.before, flip.after})
    if (f != FaceHandle()) f->info().index = -1;
  for (int i = 0; i < 3; ++i)
    if (const VertexHandle v = flip.face->vertex(i); !m_cdt.is_infinite(v) && !is_gone(v))
      m_scratch.recheck.push_back(v->info().slice_vertex);
  flip.face = FaceHandle();
}

void NextFrameCertifier::certify(FaceHandle f) {
  for (int i = 0; i < 3; ++i)
    if (!m_cdt.is_infinite(f->vertex(i)) && f->vertex(i)->info().slice_vertex < 0) return;
  if (f->info().index >= 0) return;  // replaced by a planned flip, or its hull corner checked by one
  VertexHandle out;
  if (m_cdt.is_infinite(f)) {
    // The hull corner (c, b, a) at b: convex, or straight with b between a and c.
    const HullCorner h = hull_corner(m_cdt, f);
    if (h.c->info().slice_vertex < 0) return;  // the next hull vertex vanishes
    ++m_counts.certificates;
    if (convex_corner(h.a, h.b, h.c)) return;
    if (plan_hull_flip(f)) {
      ++m_counts.certificates_failed;
      return;
    }
    out = h.b;
  } else {
    ++m_counts.certificates;
    const cgal::Point2 p0 = next_point(f->vertex(0)), p1 = next_point(f->vertex(1)),
                       p2 = next_point(f->vertex(2));
    if (cgal::orientation(p0, p1, p2) == CGAL::LEFT_TURN) return;
    if (plan_triangle_flip(f)) {
      ++m_counts.certificates_failed;
      return;
    }
    // The vertex that moved farthest since frame k.
    double farthest = -1.0;
    for (int i = 0; i < 3; ++i) {
      const VertexHandle v = f->vertex(i);
      const double d = CGAL::squared_distance(v->point(), next_point(v));
      if (d > farthest) farthest = d, out = v;
    }
  }
  ++m_counts.certificates_failed;
  const int y = out->info().slice_vertex;
  if (m_scratch.taken_out[y]) return;
  m_scratch.taken_out[y] = 1;
  m_scratch.take_out.push_back(out);
}

bool NextFrameCertifier::remove(VertexHandle v) {
  auto g = m_cdt.incident_faces(v), around = g;
  do
    if (const int n = g->info().index; n != -1) cancel(n >= 0 ? n : -2 - n);
  while (++g != around);
  auto u = m_cdt.incident_vertices(v), done = u;
  do
    if (!m_cdt.is_infinite(u) && u->info().slice_vertex >= 0)
      m_scratch.recheck.push_back(u->info().slice_vertex);
  while (++u != done);
  // Constrained_triangulation_2's operations, not the Delaunay ones: only the constraint marks are cleared
  // (the Delaunay version then flips edges beyond v's star, making faces that no neighbour of v would
  // recheck), and the star-shaped hole is filled by ears (the kept triangulation is not Delaunay, and the
  // Delaunay hole filling can cycle on it).
  m_cdt.Cdt::Ctr::remove_incident_constraints(v);
  m_cdt.Cdt::Ctr::remove(v);
  return m_cdt.dimension() == 2;
}

}  // namespace

void KineticSlice::build(const MeshTopology& topology, const MeshConnectivity& connectivity,
                         const Frame& frame, const SlicingPlane& plane, ConeStorage storage,
                         const PlaneFaces& faces, const FrameMarks& marks, KineticScratch& scratch) {
  m_storage = storage;
  const auto start = std::chrono::steady_clock::now();
  slice_mesh(topology, connectivity, frame, plane, faces.cloth, scratch.slicer, m_out.slice,
             marks.flat_edges);
  slice_mesh(topology, connectivity, frame, plane, faces.occluders, scratch.slicer, m_out.occluders,
             marks.flat_edges);
  try {
    finish_build(topology, frame, marks, scratch, true);
    m_rebuild_cost = per_slice_vertex(seconds_since(start));
    m_carry_cost = -1.0;
  } catch (...) {
    m_editable = false;
    m_kept.release();
    throw;
  }
}

void KineticSlice::finish_build(const MeshTopology& topology, const Frame& frame, const FrameMarks& marks,
                                KineticScratch& scratch, bool keep) {
  SliceTriangulation& tri = scratch.triangulation;
  m_unkept_check.reset();
  if (!offer_cones(topology, frame, marks, scratch)) {  // occluders only: no triangulation, nothing kept
    m_out.crossings = 0;
    m_editable = false;
    m_kept.release();
    return;
  }
  tri.build(m_out.slice);
  m_out.crossings = tri.crossings();
  m_editable = keep && tri.dimension() == 2 && m_out.crossings == 0 &&
               tri.cdt().number_of_vertices() == m_out.slice.vertices.size() &&
               chains_are_edges(tri.cdt(), m_out.slice.edges, [&](Index x) { return tri.vertex_of(x); });
  if (!m_editable && scratch.check_unkept) {
    std::string why;
    m_unkept_check = tri.check_invariants(&why) ? std::string() : (why.empty() ? "invalid" : why);
  }
  grow_cones(topology.contact_tolerance, scratch);
  if (m_editable)
    keep_triangulation(tri.cdt_for_editing(), m_kept);
  else
    m_kept.release();  // rebuilt at the next interval anyway (or not to be kept)
}

void KineticSlice::finish_frame(const MeshTopology& topology, const Frame& frame, const FrameMarks& marks,
                                KineticScratch& scratch) {
  std::swap(m_out.slice, scratch.next);
  scratch.triangulation.adopt_edits(m_out.slice);
  m_out.crossings = 0;
  if (!offer_cones(topology, frame, marks, scratch)) {  // carried into occluders only: not carried further
    m_editable = false;
    m_kept.release();
    return;
  }
  grow_cones(topology.contact_tolerance, scratch);
  keep_triangulation(scratch.triangulation.cdt_for_editing(), m_kept);
}

bool KineticSlice::offer_cones(const MeshTopology& topology, const Frame& frame, const FrameMarks& marks,
                               KineticScratch& scratch) {
  const auto start = std::chrono::steady_clock::now();
  m_offers =
      offer_plane_cones(topology.num_receivers(), m_storage, frame, marks.whole_fans, scratch.cones, m_out);
  m_cone_seconds = seconds_since(start);
  return m_offers;
}

void KineticSlice::grow_cones(double contact_tolerance, KineticScratch& scratch) {
  const auto start = std::chrono::steady_clock::now();
  compute_plane_cones(scratch.triangulation, contact_tolerance, scratch.cones, m_out);
  m_cone_seconds += seconds_since(start);
}

KineticCounts KineticSlice::advance(const MeshTopology& topology, const MeshConnectivity& connectivity,
                                    const Frame& next, const SlicingPlane& plane, const PlaneFaces& faces,
                                    const FrameMarks& marks, const KineticPolicy& policy,
                                    KineticScratch& scratch) {
  const auto start = std::chrono::steady_clock::now();
  KineticCounts counts;
  try {
    slice_mesh(topology, connectivity, next, plane, faces.occluders, scratch.slicer, m_out.occluders,
               marks.flat_edges);
    counts = carry(topology, connectivity, next, plane, faces.cloth, marks, policy, scratch);
  } catch (...) {
    m_editable = false;  // perhaps half-edited: the next interval rebuilds it
    m_kept.release();
    throw;
  }
  counts.cone_seconds = m_cone_seconds;
  const double seconds = seconds_since(start);
  counts.structure_seconds = seconds - m_cone_seconds;
  // What this interval cost per slice vertex, as the cost of carrying the slice (kept, or an attempt that
  // ended in a rebuild) or of rebuilding it outright; each averaged over the intervals that measured it. An
  // outright rebuild makes the carry cost unknown: the next carry is measured afresh.
  const double sample = per_slice_vertex(seconds);
  auto average = [&](double& cost) { cost = cost < 0 ? sample : 0.5 * (cost + sample); };
  if (m_attempted) {
    average(m_carry_cost);
  } else {
    average(m_rebuild_cost);
    m_carry_cost = -1.0;
  }
  return counts;
}

KineticCounts KineticSlice::rebuild_outright(const MeshTopology& topology,
                                             const MeshConnectivity& connectivity, const Frame& next,
                                             const SlicingPlane& plane, const PlaneFaces& faces,
                                             const FrameMarks& marks, bool keep, KineticScratch& scratch) {
  const auto start = std::chrono::steady_clock::now();
  KineticCounts counts;
  counts.slices_rebuilt = 1;
  ++counts.rebuilt_because[static_cast<std::size_t>(RebuildReason::frame_cost)];
  m_changed_edges.clear();
  m_carried = m_attempted = false;
  m_rebuilds_left = 0;  // the slice's own run of rebuilds is the engine's now
  m_carry_cost = -1.0;  // measured afresh when carried again
  try {
    slice_mesh(topology, connectivity, next, plane, faces.cloth, scratch.slicer, m_out.slice,
               marks.flat_edges);
    slice_mesh(topology, connectivity, next, plane, faces.occluders, scratch.slicer, m_out.occluders,
               marks.flat_edges);
    finish_build(topology, next, marks, scratch, keep);
  } catch (...) {
    m_editable = false;
    m_kept.release();
    throw;
  }
  counts.cone_seconds = m_cone_seconds;
  counts.structure_seconds = seconds_since(start) - m_cone_seconds;
  return counts;
}

void KineticSlice::rederive_triangulation(SliceTriangulation& out) const {
  if (m_editable) {
    RestoreScratch scratch;
    restore_triangulation(m_kept, m_out.slice, out.cdt_for_editing(), scratch);
    out.adopt_edits(m_out.slice);
  } else
    out.build(m_out.slice);  // what the interval built (deterministic); not kept
}

KineticCounts KineticSlice::carry(const MeshTopology& topology, const MeshConnectivity& connectivity,
                                  const Frame& next, const SlicingPlane& plane, std::span<const Index> faces,
                                  const FrameMarks& marks, const KineticPolicy& policy,
                                  KineticScratch& scratch) {
  KineticCounts counts;
  m_changed_edges.clear();
  m_attempted = false;
  const int retry = std::max(policy.retry_interval, 1);
  bool sliced = false;  // the next frame's slice is in scratch.next (else it is sliced into m_out.slice)
  auto rebuild = [&](RebuildReason reason) {
    const bool by_policy = reason == RebuildReason::policy || reason == RebuildReason::cost;
    m_carried = false;
    if (!by_policy) {
      m_rebuilds_left = 0;
    } else if (m_rebuilds_left > 0) {
      --m_rebuilds_left;
    } else {
      // Starts a run of outright rebuilds (this one and the rest), each run after a failed attempt longer.
      m_streak_reason = reason;
      m_rebuilds_left = (retry << m_backoff) - 1;
      m_backoff = std::min(m_backoff + 1, std::clamp(policy.max_retry_doublings, 0, 16));
    }
    counts.removed = counts.inserted = counts.relabeled = 0;  // not applied as local edits
    counts.slices_rebuilt = 1;
    ++counts.rebuilt_because[static_cast<std::size_t>(reason)];
    if (sliced)
      std::swap(m_out.slice, scratch.next);
    else  // into the slice's own buffer, as the static engine slices each plane into its own
      slice_mesh(topology, connectivity, next, plane, faces, scratch.slicer, m_out.slice, marks.flat_edges);
    // A slice the next interval rebuilds outright keeps nothing: it is built as the static engine builds it.
    finish_build(topology, next, marks, scratch, !(by_policy && m_rebuilds_left != 0));
    return counts;
  };
  // Rebuilt by the policy in the last interval(s): rebuilt outright until it is time to try again, for the
  // reason that started the run.
  if (m_rebuilds_left > 0) return rebuild(m_streak_reason);
  if (!m_editable) return rebuild(m_offers ? RebuildReason::degenerate : RebuildReason::no_cones);
  // Carrying this slice has cost more than rebuilding it (both measured on it): rebuilt, and tried again
  // after the retry interval (when the carry is measured afresh: unknown right after a rebuild).
  if (policy.measured_cost && m_carry_cost >= 0 && m_rebuild_cost >= 0 && m_carry_cost > m_rebuild_cost)
    return rebuild(RebuildReason::cost);
  if (m_carried) m_backoff = 0;  // the last interval carried it, and (where measured) that paid
  m_attempted = true;
  slice_mesh(topology, connectivity, next, plane, faces, scratch.slicer, scratch.next, marks.flat_edges);
  sliced = true;

  // Match slice vertices by mesh edge: survivors, and those that vanish or appear; then the fan swaps.
  const Slice& old = m_out.slice;
  SliceTriangulation& tri = scratch.triangulation;
  const std::size_t vanished = match_slice_vertices(old, connectivity.num_edges(), scratch, m_changed_edges);
  counts.relabeled = find_fan_swaps(old, scratch.next, scratch);
  scratch.born.erase(
      std::remove_if(scratch.born.begin(), scratch.born.end(), [&](Index y) { return !scratch.is_born[y]; }),
      scratch.born.end());
  counts.inserted = scratch.born.size();
  counts.removed = vanished - counts.relabeled;
  const std::size_t budget =
      2 + static_cast<std::size_t>(policy.max_edit_fraction * double(old.vertices.size()));
  if (counts.removed + counts.inserted > budget) return rebuild(RebuildReason::policy);
  // The kept triangulation, restored only now: a slice rebuilt for its edits above never needs it.
  restore_triangulation(m_kept, old, tri.cdt_for_editing(), scratch.restore);
  tri.map_vertices(old);

  // 1. Survivors and relabeled vertices take their new ids; the vanishing ones are marked for removal.
  hand_over_vertices(old, tri, scratch);
  // 2. Certify at the next frame, remove the vanishing vertices and take out those of failed certificates.
  if (const RebuildReason r =
          certify_at_next_frame(budget - counts.removed - counts.inserted, scratch, counts);
      r != RebuildReason::none)
    return rebuild(r);
  // 3. Kept vertices to their next points (a valid triangulation of them, if the hull winds once); then the
  // vertices taken out and the new ones, and their chain edges.
  Cdt& cdt = tri.cdt_for_editing();
  if (const RebuildReason r = move_kept_vertices(cdt, scratch, counts); r != RebuildReason::none)
    return rebuild(r);
  if (const RebuildReason r = insert_born_vertices(cdt, scratch); r != RebuildReason::none) return rebuild(r);
  if (const RebuildReason r = constrain_loose_chains(cdt, scratch); r != RebuildReason::none)
    return rebuild(r);
  m_carried = true;
  // (A run that grew leaves a new vertex inserted: its unmarked closing edge is counted there.)
  const bool structure_changed = counts.removed + counts.inserted + counts.reinserted + counts.flipped > 0;
  ++(structure_changed ? counts.slices_repaired : counts.slices_unchanged);
  finish_frame(topology, next, marks, scratch);
  return counts;
}

RebuildReason KineticSlice::certify_at_next_frame(std::size_t budget, KineticScratch& scratch,
                                                  KineticCounts& counts) {
  Cdt& cdt = scratch.triangulation.cdt_for_editing();
  scratch.taken_out.assign(scratch.next.vertices.size(), 0);
  scratch.take_out.clear();
  scratch.recheck.clear();
  scratch.flips.clear();
  NextFrameCertifier certifier(scratch, counts);
  // The restored faces are new (info().index -1: in no flip), as are those the removals make.
#if PLEAT_ASSERTS_ON  // no empty pass over the faces where assertions compile away
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f)
    PLEAT_ASSERT(f->info().index == -1, "a restored face is reserved by a flip");
#endif
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) certifier.certify(f);
  // More vertices to take out than the budget allows already: rebuild before removing any.
  if (scratch.take_out.size() > budget) return RebuildReason::policy;
  for (const VertexHandle v : scratch.vanishing)
    if (!certifier.remove(v)) return RebuildReason::degenerate;
  while (!scratch.take_out.empty() || !scratch.recheck.empty()) {
    for (const VertexHandle v : scratch.take_out) {
      if (++counts.reinserted > budget) return RebuildReason::policy;
      scratch.vertex_of_new[v->info().slice_vertex] = VertexHandle();
      if (!certifier.remove(v)) return RebuildReason::degenerate;
    }
    scratch.take_out.clear();
    // Neighbours by id: one queued after it was remembered is gone by now.
    std::sort(scratch.recheck.begin(), scratch.recheck.end());
    scratch.recheck.erase(std::unique(scratch.recheck.begin(), scratch.recheck.end()), scratch.recheck.end());
    for (const std::int32_t y : scratch.recheck) {
      if (scratch.taken_out[y]) continue;
      auto f = cdt.incident_faces(scratch.vertex_of_new[y]), done = f;
      do certifier.certify(f);
      while (++f != done);
    }
    scratch.recheck.clear();
  }
  return RebuildReason::none;
}

bool hull_winds_once(const Cdt& cdt) {
  // Along a hull polygon with no reflex corner, the lexicographically smallest point is passed once per turn.
  auto v = cdt.incident_vertices(cdt.infinite_vertex()), done = v;
  auto previous = v;
  --previous;
  int minima = 0;
  do {
    auto following = v;
    ++following;
    minima += CGAL::compare_xy(v->point(), previous->point()) == CGAL::SMALLER &&
              CGAL::compare_xy(v->point(), following->point()) == CGAL::SMALLER;
    previous = v;
  } while (++v != done);
  return minima == 1;
}

bool KineticSlice::check_invariants(std::string* why) const {
  auto fail = [&](const std::string& message) {
    if (why) *why = message;
    return false;
  };
  // A slice that is not editable (chains cross or touch, points merged, or not 2D) is rebuilt every interval
  // and keeps nothing; the triangulation it was built with was checked then (KineticScratch::check_unkept).
  if (!m_editable) {
    if (!m_kept.empty()) return fail("a slice that is rebuilt kept its triangulation");
    if (!m_unkept_check) {  // not checked in the interval: build it again (deterministic) and check that
      SliceTriangulation built;
      rederive_triangulation(built);
      return built.check_invariants(why);
    }
    return m_unkept_check->empty() || fail("the triangulation built for the interval: " + *m_unkept_check);
  }
  // Orientations, hull convexity and the triangulation's combinatorics: CGAL's check, inside this one (on a
  // copy whose corners, regions and windows are derived afresh: those checks test the derivation).
  SliceTriangulation tri;
  rederive_triangulation(tri);
  if (!tri.check_invariants(why)) return false;
  if (tri.dimension() < 2) return true;
  const Cdt& cdt = tri.cdt();
  // The constraints are exactly the chain edges between distinct points (several chain edges may join the
  // same two points where slice points coincide: a mesh edge lying in the plane).
  std::size_t constrained = 0;
  for (auto e = cdt.finite_edges_begin(); e != cdt.finite_edges_end(); ++e)
    constrained += cdt.is_constrained(*e);
  std::vector<std::pair<const void*, const void*>> chain_edges;
  for (const SliceEdge& e : m_out.slice.edges) {
    const VertexHandle a = tri.vertex_of(e.from), b = tri.vertex_of(e.to);
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
