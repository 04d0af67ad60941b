// The compact form a kinetic slice keeps its triangulation in between frames (kinetic/kept_triangulation.hpp)
// against the triangulation it was kept from: restored, it is a valid constrained Delaunay triangulation
// (CGAL's is_valid) with the same vertices at the same points, the same triangles and the same constrained
// edges, face by face in the same order, and the regions, windows and corners derived from it are the
// original's. On random chains (holes, dangling chains, grid-snapped collinear points) and on slices of
// random folded height fields; a slice that a kinetic slice would not keep (merged points, crossing chains,
// fewer than two dimensions) is skipped, and a fixed batch checks that enough are kept.
#include "kinetic/internal/kept_triangulation.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <string>

#include "oracles/random_slices.hpp"
#include "static_core/internal/slice_triangulation.hpp"

namespace pleat {
namespace {

/// What a kinetic slice keeps: a 2D triangulation with one vertex per slice vertex and no crossing point.
bool keepable(const Slice& slice, const SliceTriangulation& t) {
  return t.dimension() == 2 && t.crossings() == 0 && t.cdt().number_of_vertices() == slice.vertices.size();
}

/// "" when the round trip gives the original back, else what differs.
std::string round_trip(const Slice& slice, SliceTriangulation& original) {
  kinetic::KeptTriangulation kept;
  kinetic::keep_triangulation(original.cdt_for_editing(), kept);
  if (kept.num_faces() != original.cdt().tds().number_of_faces()) return "face count";
  SliceTriangulation restored;
  kinetic::RestoreScratch scratch;
  kinetic::restore_triangulation(kept, slice, restored.cdt_for_editing(), scratch);
  const cgal::Cdt& a = original.cdt();
  const cgal::Cdt& b = restored.cdt();
  if (a.number_of_vertices() != b.number_of_vertices()) return "vertex count";
  for (auto f = a.all_faces_begin(), g = b.all_faces_begin(); f != a.all_faces_end(); ++f, ++g) {
    if (g == b.all_faces_end()) return "fewer faces";
    for (int i = 0; i < 3; ++i) {
      const bool inf_f = a.is_infinite(f->vertex(i)), inf_g = b.is_infinite(g->vertex(i));
      if (inf_f != inf_g ||
          (!inf_f && f->vertex(i)->info().slice_vertex != g->vertex(i)->info().slice_vertex))
        return "a face's vertices differ";
      if (f->is_constrained(i) != g->is_constrained(i)) return "a constraint differs";
    }
  }
  if (!b.is_valid()) return "the restored triangulation is not valid";
  restored.adopt_edits(slice);  // (after the checks above: it assumes a consistent triangulation)
  for (Index x = 0; x < slice.vertices.size(); ++x)
    if (original.vertex_of(x)->point() != restored.vertex_of(x)->point()) return "a vertex moved";
  if (original.num_regions() != restored.num_regions() || original.num_corners() != restored.num_corners())
    return "regions or corners differ";
  for (std::size_t r = 0; r < original.num_regions(); ++r) {
    const SliceRegion p = original.region(r), q = restored.region(r);
    if (p.faces.size() != q.faces.size() || p.windows.size() != q.windows.size() ||
        p.has_holes != q.has_holes)
      return "a region differs";
  }
  // Kept again, the restored triangulation gives the same arrays.
  kinetic::KeptTriangulation again;
  kinetic::keep_triangulation(restored.cdt_for_editing(), again);
  if (again.vertices != kept.vertices || again.neighbors != kept.neighbors ||
      again.constrained != kept.constrained)
    return "keeping the restored triangulation gives other arrays";
  return {};
}

RC_GTEST_PROP(KeptTriangulation, RestoresTheTriangulationOnRandomChains, ()) {
  std::mt19937_64 rng(*rc::gen::arbitrary<std::uint64_t>());
  const Slice slice = test::random_chain_slice(rng);
  SliceTriangulation t;
  t.build(slice);
  RC_PRE(keepable(slice, t));
  const std::string why = round_trip(slice, t);
  RC_ASSERT(why.empty());
}

RC_GTEST_PROP(KeptTriangulation, RestoresTheTriangulationOnSlicedSurfaces, ()) {
  for (const Slice& slice : test::random_surface_slices(*rc::gen::arbitrary<std::uint64_t>(), 4)) {
    SliceTriangulation t;
    t.build(slice);
    if (!keepable(slice, t)) continue;
    const std::string why = round_trip(slice, t);
    RC_ASSERT(why.empty());
  }
}

TEST(KeptTriangulation, MostRandomChainSlicesAreKeepable) {
  std::mt19937_64 rng(20261126);
  int kept = 0;
  for (int i = 0; i < 200; ++i) {
    const Slice slice = test::random_chain_slice(rng);
    SliceTriangulation t;
    t.build(slice);
    if (!keepable(slice, t)) continue;
    ++kept;
    EXPECT_EQ(round_trip(slice, t), "");
  }
  EXPECT_GE(kept, 50);  // a third: the properties above skip the rest (merged points, mostly)
}

}  // namespace
}  // namespace pleat
