// What share of the work could take a shortcut (issue 41, "measure before building"): a census of the slice
// regions and of the 3D cones, on the frames the frame-coherence benchmark measures.
//
// For each sequence (every real one in data/ in its scene, the generated kinds at --sizes), the last of
// --frames frames, sliced by the default plan, every slice triangulated (SliceTriangulation, as the static
// engine does):
//   corners     every region corner, by its region's kind:
//                 closed      no window: its cones are empty
//                 pocket      one window, no holes, and a boundary monotone along the window (walking it from
//                             one window end to the other, the projections onto the window never turn back):
//                             the funnel wedges are tangents to the hull of the chain seen so far, a sweep
//                             with a hull stack (issue 41, item 1)
//                 one window  one window, no holes, not monotone (a fold that curls back over itself)
//                 windows     several windows, no holes
//                 holes       a region with holes
//   slices      slices all of whose regions are closed or pockets, and their slice vertices: those need no
//               constrained triangulation if their regions can be found without one;
//   3D cones    every vertex and side of the cloth by the number of pieces of its cone (0, 1, 2+), and the
//               share of 2D cones with one wedge (what a single-piece fast assembly would take, item 2).
// Writes DIR/region_census.md; progress on stderr. Plain executable.
//
// Flags: --out DIR (default bench/results), --sequences a,b (default: real ones, then
// curtain,roll,flag,sleeve),
// --sizes n,... (generated kinds; default 3025,29929), --frames N (default 8), --cloth-alone (real sequences
// without their colliders), --quick (curtain 3025, 3 frames).
#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/bench_args.hpp"
#include "bench/coherence/report.hpp"
#include "bench/coherence/sequences.hpp"
#include "static_core/internal/slice_triangulation.hpp"
#include "static_core/mesh_connectivity.hpp"
#include "static_core/mesh_slicer.hpp"
#include "static_core/visibility.hpp"

namespace pleat::bench {
namespace {

namespace fs = std::filesystem;

enum RegionKind { kClosed, kPocket, kOneWindow, kWindows, kHoles, kKinds };
constexpr const char* kKindNames[kKinds] = {"closed", "pocket", "one window", "windows", "holes"};

/// The boundary of a region without holes and with one window, walked from the window's left end b around
/// the region's inside back to its right end a: true when the walk's projections onto a -> b never increase
/// (each step moves towards a or stays level), i.e. the chain is monotone along the window.
bool monotone_along_window(const cgal::Cdt& cdt, const SliceWindow& window) {
  const cgal::VertexHandle a = window.face->vertex(cgal::Cdt::ccw(window.index));
  const cgal::VertexHandle b = window.face->vertex(cgal::Cdt::cw(window.index));
  const double ux = b->point().x() - a->point().x(), uy = b->point().y() - a->point().y();
  auto projection = [&](cgal::VertexHandle v) {
    return (v->point().x() - a->point().x()) * ux + (v->point().y() - a->point().y()) * uy;
  };
  // At vertex v in face f, having arrived across edge (f, in): rotate about v through the region until a
  // separator edge, whose other end is the next boundary vertex.
  cgal::FaceHandle f = window.face;
  cgal::VertexHandle v = b;
  int in = window.index;
  double last = projection(b);
  for (std::size_t steps = 0; steps < 4 * cdt.number_of_faces() + 8; ++steps) {
    const int iv = f->index(v);
    // The other edge of f at v: f's edges at v are opposite ccw(iv) and cw(iv); `in` is one of them.
    const int out = in == cgal::Cdt::ccw(iv) ? cgal::Cdt::cw(iv) : cgal::Cdt::ccw(iv);
    if (is_separator(cdt, f, out)) {
      // The separator's far end: the vertex of f that is neither v nor opposite it.
      const cgal::VertexHandle w = f->vertex(3 - iv - out);
      const double p = projection(w);
      if (p > last) return false;
      last = p;
      if (w == a) return true;
      // Continue at w, in the same face, having arrived across edge `out`.
      v = w;
      in = out;
      continue;
    }
    const cgal::FaceHandle g = f->neighbor(out);
    in = cdt.mirror_index(f, out);
    f = g;
  }
  return false;  // did not close: count as not monotone
}

struct Census {
  std::array<std::size_t, kKinds> corners{};
  std::size_t slices = 0, simple_slices = 0;
  std::size_t slice_vertices = 0, simple_slice_vertices = 0;
  std::array<std::size_t, 3> pieces{};  // 0, 1, 2+
  std::size_t vertex_sides = 0;
};

RegionKind kind_of(const cgal::Cdt& cdt, const SliceRegion& region) {
  if (region.has_holes) return kHoles;
  if (region.windows.empty()) return kClosed;
  if (region.windows.size() > 1) return kWindows;
  return monotone_along_window(cdt, region.windows[0]) ? kPocket : kOneWindow;
}

Census census_of(const Sequence& s, const Frame& frame, const SlicingPlan& plan) {
  Census c;
  const MeshConnectivity connectivity(s.topology);
  const auto candidates = candidate_faces_per_plane(s.topology, frame, plan);
  SlicerScratch scratch;
  Slice slice;
  SliceTriangulation triangulation;
  std::vector<RegionKind> kinds;
  for (std::size_t p = 0; p < plan.planes.size(); ++p) {
    slice_mesh(s.topology, connectivity, frame, plan.planes[p], candidates[p], scratch, slice);
    if (slice.vertices.empty()) continue;
    triangulation.build(slice);
    ++c.slices;
    c.slice_vertices += slice.vertices.size();
    if (triangulation.dimension() < 2) continue;
    kinds.assign(triangulation.num_regions(), kClosed);
    bool simple = true;
    for (std::size_t r = 0; r < triangulation.num_regions(); ++r) {
      kinds[r] = kind_of(triangulation.cdt(), triangulation.region(r));
      simple = simple && (kinds[r] == kClosed || kinds[r] == kPocket);
    }
    for (std::size_t k = 0; k < triangulation.num_corners(); ++k)
      ++c.corners[kinds[triangulation.corner_region(int(k))]];
    if (simple) ++c.simple_slices, c.simple_slice_vertices += slice.vertices.size();
  }
  const FrameVisibility vis = compute_visibility(s.topology, frame, plan, VisibilityParams{false});
  for (int side = 0; side < 2; ++side)
    for (Index v = 0; v < s.cloth.num_vertices; ++v) {
      ++c.vertex_sides;
      ++c.pieces[std::min<std::size_t>(vis.cones[side][v].pieces.size(), 2)];
    }
  return c;
}

std::string percent(std::size_t part, std::size_t whole) {
  return format("%.1f%%", whole ? 100.0 * double(part) / double(whole) : 0.0);
}

int run(int argc, char** argv) {
  fs::path out_dir = "bench/results";
  const fs::path data = fs::path(PLEAT_BENCH_SOURCE_DIR) / "data";
  std::vector<std::string> names;
  std::vector<Index> sizes{3025, 29929};
  int frames = 8;
  bool quick = false, in_scene = true;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--out")
      out_dir = next_value(argc, argv, i);
    else if (arg == "--sequences")
      names = split(next_value(argc, argv, i));
    else if (arg == "--sizes") {
      sizes.clear();
      for (const auto& n : split(next_value(argc, argv, i))) sizes.push_back(Index(std::stoul(n)));
    } else if (arg == "--frames")
      frames = std::stoi(next_value(argc, argv, i));
    else if (arg == "--quick")
      quick = true;
    else if (arg == "--cloth-alone")
      in_scene = false;
    else
      throw std::invalid_argument("unknown flag '" + arg +
                                  "' (see the top of bench/region_census_bench.cpp)");
  }
  if (quick) names = {"curtain"}, sizes = {3025}, frames = 3;
  if (names.empty()) names = default_sequences(data);

  std::ofstream md;
  std::vector<std::string> rows;
  for (const std::string& name : names) {
    const bool real = is_real_sequence(name, data);
    for (Index size : real ? std::vector<Index>{0} : sizes) {
      const Sequence s = make_sequence(name, size, data, in_scene);
      const std::vector<Frame> f = make_frames(s, 1.0, frames);
      const SlicingPlan plan = default_plan(s, f.front());
      const Census c = census_of(s, f.back(), plan);
      const std::size_t corners = std::accumulate(c.corners.begin(), c.corners.end(), std::size_t(0));
      std::string row =
          "| " + name + (real ? "" : format(" %u", size)) + " | " + std::to_string(c.slice_vertices);
      for (int k = 0; k < kKinds; ++k) row += " | " + percent(c.corners[k], corners);
      row += " | " + percent(c.simple_slices, c.slices) + " | " +
             percent(c.simple_slice_vertices, c.slice_vertices);
      for (int k = 0; k < 3; ++k) row += " | " + percent(c.pieces[k], c.vertex_sides);
      row += " |";
      std::printf("%s\n", row.c_str());
      rows.push_back(row);
    }
  }
  fs::create_directories(out_dir);
  md.open(out_dir / "region_census.md");
  const SourceState source = read_source_state();
  md << "# Census of slice regions and 3D cones (issue 41: what a shortcut could take)\n\n"
     << "Written by `build/bench/region_census_bench" << (quick ? " --quick" : "") << "` on commit "
     << source.commit << (source.dirty.empty() ? "" : " plus uncommitted changes")
     << " (bench/region_census_bench.cpp defines every column). The last of " << frames
     << " frames of each sequence (real ones " << (in_scene ? "in their scene" : "without their colliders")
     << "), the default plan. Corners: every region corner "
        "of every slice, by its region's kind. Slices: those whose regions are all closed or pockets, and "
        "their share of the slice vertices. Pieces: the cloth's vertex sides by the pieces of their 3D "
        "cone.\n\n"
     << "| sequence | slice vertices | closed | pocket | one window, not monotone | several windows | "
     << "holes | simple slices | their slice vertices | 0 pieces | 1 piece | 2+ pieces |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const std::string& row : rows) md << row << '\n';
  std::printf("region_census: wrote %s\n", (out_dir / "region_census.md").c_str());
  return 0;
}

}  // namespace
}  // namespace pleat::bench

int main(int argc, char** argv) {
  return pleat::bench::run_main("region_census_bench", pleat::bench::run, argc, argv);
}
