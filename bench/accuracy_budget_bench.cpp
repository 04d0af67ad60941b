// Where the cones' error comes from (project issue 12, step 1): an error budget against ray-traced truth, by
// replacing one stage of Stewart's pipeline at a time with an oracle or a denser setting.
//
// For each sequence (every real one in data/ at its last frame, the generated kinds at 3,025 vertices at
// frame 6 of 48) the error |A − A_ref| over every vertex and both sides, against Embree with --reference-rays
// rays, of:
//   paper       the paper's engine: 6 axis orientations, planes one average edge apart, each slice vertex's
//               cone stored on the nearer endpoint of its edge (ConeStorage::NearerEndpoint), vertices
//               without a cone in an orientation filled from the nearest vertex that has one; split into
//               vertices that have their own cone in every orientation and those filled in at least one (the
//               fill's share);
//   settings    the engine with other orientation sets (the paper's 6 axis-aligned ones, or n spread over the
//               hemisphere: relaxed to evenly spaced lines, the default, or on the Fibonacci spiral they
//               start from), plane spacings and storage rules (ConeStorage::NearestOnFan: the nearest cut of
//               the vertex's own edges per orientation; InterpolatedOnFan: the cuts below and
//               above blended; AimedOnFan, the default: their horizon points blended and aimed at from the
//               vertex), what each buys and at what cost (CPU ms, one thread);
//   vertex      an oracle: for every vertex and orientation, a plane of that orientation through the vertex
//               itself (offset by 1e-3 edge so that it cuts the vertex's own edges), and the 2D cone of the
//               slice vertex on the vertex's edge nearest to it — no offset between slice point and vertex,
//               no fill; the 3D assembly is the engine's. With 6, 12 and 24 orientations: what remains at 24
//               is the 3D reconstruction's own error (the 2D information is then dense). On a sample of about
//               --oracle-sample vertices (every k-th; default 1000), with the paper's engine on the same
//               sample.
//   quadrature  on the oracle's 2D cones, A integrated from them directly instead of through the 3D cone:
//               per plane, the integral of max(0, n . d) over the cone's directions d on its great circle,
//               summed over the planes and divided by the same sums over whole circles (a great-circle
//               quadrature of the hemisphere, exact for a fully open or fully closed vertex). It needs no
//               grouping, no polygon and no chords: where it is no better than the 3D cone, the error left
//               is in the 2D information (too few great circles), not in the 3D reconstruction.
// Writes DIR/accuracy_budget.md and .csv; progress on stderr. Plain executable.
//
// Flags: --out DIR (default bench/results), --sequences a,b (default: real ones, then
// curtain,roll,flag,sleeve),
// --reference-rays K (default 4096), --orientations 6,12,24 (of the vertex oracle), --oracle-sample N,
// --settings 8:0.5:interpolated-on-fan,8:0.75:nearest-on-fan:spiral,... (instead of the built-in list),
// --quick (curtain only, 256 rays, oracle at 6 orientations on 100 vertices: the test suite's run).
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "bench/bench_args.hpp"
#include "bench/coherence/matched_error.hpp"
#include "bench/coherence/plan_setting.hpp"
#include "bench/coherence/report.hpp"
#include "bench/coherence/sequences.hpp"
#include "bench/coherence/stopwatch.hpp"
#include "shading/embree_scene.hpp"
#include "shading/ray_visibility.hpp"
#include "sim_io/cloth_generators.hpp"
#include "static_core/cone_assembly.hpp"
#include "static_core/internal/slice_cones.hpp"
#include "static_core/internal/slice_triangulation.hpp"
#include "static_core/mesh_slicer.hpp"
#include "static_core/visibility.hpp"

namespace pleat::bench {
namespace {

namespace fs = std::filesystem;

constexpr Index kGeneratedSize = 3025;
constexpr std::size_t kGeneratedFrame = 6;  // of the generated kinds (as in tests/visibility_accuracy_test)
constexpr double kOracleOffset = 1e-3;      // of the average edge length

struct Result {
  std::string sequence, variant;
  double ms = NAN;  // wall time of the variant's cone computation (all threads)
  ErrorStats err;
  double bias = NAN;
  double share = NAN;  // fraction of the values in this row
};

/// |A − A_ref| statistics over the values selected by `keep` (index into [front..., back...]).
template <class Keep>
Result compare(const SkyValues& a, const SkyValues& ref, Keep keep) {
  SkyValues x, r;
  double bias = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (keep(i)) x.push_back(a[i]), r.push_back(ref[i]), bias += a[i] - ref[i];
  Result out;
  out.err = error_stats(std::vector<SkyValues>{x}, std::vector<SkyValues>{r});
  out.bias = x.empty() ? NAN : bias / double(x.size());
  out.share = a.empty() ? NAN : double(x.size()) / double(a.size());
  return out;
}

SkyValues sky_of(const std::array<std::vector<ConeMeasures>, 2>& m) {
  SkyValues a;
  for (int s = 0; s < 2; ++s)
    for (const ConeMeasures& c : m[s]) a.push_back(c.sky_visibility);
  return a;
}

/// A from 2D cones without a 3D cone (the quadrature row above): sum over planes of the integral of
/// max(0, n . d) over the cone's directions, over the same sum for whole circles (2 |n projected| each).
/// `closed_planes` are planes through the vertex whose cone on this side is empty.
double quadrature_sky(std::span<const PlanarCone> cones, std::span<const SlicingPlane* const> closed_planes,
                      const glm::dvec3& n) {
  double num = 0, den = 0;
  std::vector<Wedge> united, clipped;
  std::vector<AngularInterval> intervals;
  auto circle = [&](const SlicingPlane& plane) {  // n projected into the plane's (u, w) frame
    const glm::dvec2 m(glm::dot(plane.u, n), glm::dot(plane.w, n));
    den += 2 * glm::length(m);
    return m;
  };
  for (const PlanarCone& c : cones) {
    const glm::dvec2 m = circle(*c.plane);
    const double len = glm::length(m);
    if (len < 1e-12) continue;
    const double phi0 = std::atan2(m.y, m.x);
    united.clear();
    unite_wedges(c.wedges, intervals, united);
    clipped.clear();
    clip_to_half_turn(united, wrap_angle(phi0 - kTwoPi / 4), clipped);
    for (const Wedge& w : clipped) num += len * (std::sin(w.end() - phi0) - std::sin(w.start - phi0));
  }
  for (const SlicingPlane* p : closed_planes) circle(*p);
  return den > 0 ? std::clamp(num / den, 0.0, 1.0) : 0.0;
}

/// The vertex oracle: per vertex and orientation, the 2D cone from a plane through the vertex.
/// Only vertices 0, stride, 2 stride, ... are computed (the others keep default measures).
std::array<std::vector<ConeMeasures>, 2> vertex_plane_cones(const MeshTopology& topology, const Frame& frame,
                                                            int orientations, Index stride,
                                                            SkyValues* quadrature = nullptr) {
  const SlicingPlan directions = make_diffuse_plan(topology, frame, {orientations, 0.0, 1});
  const std::size_t n = topology.num_vertices, o_count = directions.orientations.size();
  const double eps = kOracleOffset * average_edge_length(topology, frame);
  const MeshConnectivity connectivity(topology);
  std::vector<Index> all_faces(topology.triangles.size());
  for (std::size_t f = 0; f < all_faces.size(); ++f) all_faces[f] = Index(f);
  std::vector<SlicingPlane> planes(n * o_count);
  std::vector<std::array<std::vector<Wedge>, 2>> wedges(n * o_count);
  std::vector<char> found(n * o_count, 0);
  struct Workspace {
    SlicerScratch slicer;
    Slice slice;
    SliceTriangulation triangulation;
    SliceConeScratch scratch;
    SliceCones cones;
  };
  tbb::enumerable_thread_specific<Workspace> workspaces;
  tbb::parallel_for(std::size_t(0), n * o_count, [&](std::size_t key) {
    const Index v = Index(key / o_count);
    const int o = int(key % o_count);
    if (v % stride != 0) return;
    const glm::dvec3& normal = directions.orientations[o];
    Workspace& ws = workspaces.local();
    for (double shift : {-eps, eps}) {  // below the vertex first: it cuts the edges to lower neighbours
      const SlicingPlane plane = make_plane(normal, glm::dot(normal, frame.positions[v]) + shift, o);
      slice_mesh(topology, connectivity, frame, plane, all_faces, ws.slicer, ws.slice);
      std::int64_t best = -1;
      for (std::size_t x = 0; x < ws.slice.vertices.size(); ++x) {
        const SliceVertex& sv = ws.slice.vertices[x];
        if (sv.nearer == v && (best < 0 || sv.distance < ws.slice.vertices[best].distance))
          best = std::int64_t(x);
      }
      if (best < 0) continue;
      ws.triangulation.build(ws.slice);
      compute_slice_cones(ws.slice, ws.triangulation, ws.scratch, ws.cones);
      planes[key] = plane;
      found[key] = 1;
      for (int side = 0; side < 2; ++side) {
        const auto c = ws.cones.cone(Index(best), static_cast<Side>(side));
        wedges[key][side].assign(c.begin(), c.end());
      }
      return;
    }
  });
  const auto normals = vertex_normals(topology, frame);
  std::array<std::vector<ConeMeasures>, 2> out;
  out[0].resize(n);
  out[1].resize(n);
  if (quadrature) quadrature->assign(2 * n, 0.0);
  tbb::parallel_for(std::size_t(0), n, [&](std::size_t v) {
    if (v % stride != 0) return;
    for (int side = 0; side < 2; ++side) {
      std::vector<PlanarCone> cones;
      std::vector<const SlicingPlane*> closed;
      for (std::size_t o = 0; o < o_count; ++o) {
        const std::size_t key = v * o_count + o;
        if (!wedges[key][side].empty())
          cones.push_back({&planes[key], wedges[key][side]});
        else if (found[key])
          closed.push_back(&planes[key]);
      }
      const glm::dvec3 side_normal = side_sign(static_cast<Side>(side)) * normals[v];
      out[side][v] = measure_cone(assemble_cone(cones, side_normal), side_normal);
      if (quadrature) (*quadrature)[side * n + v] = quadrature_sky(cones, closed, side_normal);
    }
  });
  return out;
}

/// Per vertex: whether it has a cone of its own (it is the nearer endpoint of a slice vertex) in every
/// orientation of `plan`.
std::vector<bool> own_in_every_orientation(const MeshTopology& topology, const Frame& frame,
                                           const SlicingPlan& plan) {
  const MeshConnectivity connectivity(topology);
  std::vector<std::vector<char>> own(plan.orientations.size(), std::vector<char>(topology.num_vertices, 0));
  for (const SlicingPlane& plane : plan.planes)
    for (Index v : cone_recipients(topology, connectivity, frame, plane)) own[plane.orientation][v] = 1;
  std::vector<bool> all(topology.num_vertices, true);
  for (const auto& o : own)
    for (Index v = 0; v < topology.num_vertices; ++v) all[v] = all[v] && o[v];
  return all;
}

int run(int argc, char** argv) {
  fs::path out_dir = "bench/results";
  const fs::path data = fs::path(PLEAT_BENCH_SOURCE_DIR) / "data";
  std::vector<std::string> sequences;
  int reference_rays = 4096;
  std::vector<int> oracle_orientations{6, 12, 24};
  constexpr auto kPaper = ConeStorage::NearerEndpoint, kFan = ConeStorage::NearestOnFan,
                 kBlend = ConeStorage::InterpolatedOnFan, kAim = ConeStorage::AimedOnFan;
  std::vector<Setting> settings{
      setting(6, 1.0, kPaper),        setting(6, 0.5, kPaper),         setting(12, 1.0, kPaper),
      setting(6, 1.0, kFan),          setting(8, 1.0, kFan),           setting(8, 0.75, kFan),
      setting(12, 1.0, kFan),         setting(12, 0.5, kFan),          setting(6, 1.0, kBlend),
      setting(8, 1.0, kBlend),        setting(8, 0.75, kBlend, false), setting(8, 0.75, kBlend),
      setting(8, 0.5, kBlend, false), setting(8, 0.5, kBlend),         setting(8, 0.45, kBlend),
      setting(10, 0.5, kBlend),       setting(12, 0.75, kBlend),       setting(12, 0.5, kBlend, false),
      setting(12, 0.5, kBlend),       setting(8, 0.75, kAim),          setting(8, 0.5, kAim),
      setting(12, 0.5, kAim),         setting(16, 0.75, kAim)};
  Index oracle_sample = 1000;
  bool quick = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--out")
      out_dir = next_value(argc, argv, i);
    else if (arg == "--sequences")
      sequences = split(next_value(argc, argv, i));
    else if (arg == "--reference-rays")
      reference_rays = std::stoi(next_value(argc, argv, i));
    else if (arg == "--orientations") {
      oracle_orientations.clear();
      for (const auto& s : split(next_value(argc, argv, i))) oracle_orientations.push_back(std::stoi(s));
    } else if (arg == "--settings") {
      settings.clear();
      for (const auto& item : split(next_value(argc, argv, i)))
        settings.push_back(parse_setting(item, "--settings"));
    } else if (arg == "--oracle-sample")
      oracle_sample = Index(std::stoi(next_value(argc, argv, i)));
    else if (arg == "--quick")
      quick = true;
    else
      throw std::invalid_argument("unknown flag '" + arg +
                                  "' (see the top of bench/accuracy_budget_bench.cpp)");
  }
  if (quick) {
    if (sequences.empty()) sequences = {"curtain"};
    reference_rays = 256;
    oracle_orientations = {6};
    oracle_sample = 100;
  }
  if (sequences.empty()) sequences = default_sequences(data);
  const Stopwatch run_watch;
  const SourceState source = read_source_state();
  std::vector<Result> results;
  for (const std::string& name : sequences) {
    const Sequence seq = make_sequence(name, kGeneratedSize, data);
    const std::size_t k = seq.real ? seq.native_available - 1 : kGeneratedFrame;
    const Frame frame = seq.native(k);
    const MeshTopology& topology = seq.topology;
    std::fprintf(stderr, "[accuracy_budget] %s (%u vertices), frame %zu of its measured range\n",
                 name.c_str(), topology.num_vertices, k);
    SkyValues reference;
    {
      EmbreeScene scene(topology, frame);
      RayVisibilityParams params;
      params.rays_per_vertex = reference_rays;
      params.seed = 0x5eed4096;
      reference = [&] {
        const auto r =
            ray_cast_sky_visibility(scene, topology, frame, vertex_normals(topology, frame), params);
        SkyValues a(r[0]);
        a.insert(a.end(), r[1].begin(), r[1].end());
        return a;
      }();
    }
    const std::size_t n = topology.num_vertices;
    auto add = [&](Result r, const std::string& variant, double ms) {
      r.sequence = name, r.variant = variant, r.ms = ms;
      std::fprintf(stderr,
                   "[accuracy_budget] %s %-40s mean %.4f p95 %.4f bias %+.4f (%.0f%% of values) %.0f ms\n",
                   name.c_str(), variant.c_str(), r.err.mean, r.err.p95, r.bias, 100 * r.share, ms);
      results.push_back(r);
    };
    for (const Setting& s : settings) {
      const int orientations = s.plan.orientations;
      const double spacing_edges = s.plan.spacing_in_edges;
      if (quick && orientations != 6) continue;
      SlicingPlan plan = make_diffuse_plan(topology, frame, s.plan);
      plan.storage = s.storage;
      plan.reconstruction = s.reconstruction;
      StaticVisibility engine(topology, plan, VisibilityParams{false});
      engine.compute(frame);  // warm-up: buffers grow
      const Stopwatch watch;
      const FrameVisibility& vis = engine.compute(frame);
      const double ms = watch.process_cpu_ms();
      const SkyValues a = sky_of(vis.measures);
      const std::string label = format(
          "%s%d %s, %g edge apart, %s%s",
          orientations == 6 && spacing_edges == 1 && s.storage == kPaper ? "paper: " : "", orientations,
          orientations == 6 ? "axis orientations"
          : s.plan.relaxed  ? "spread orientations"
                            : "spread orientations on the spiral",
          spacing_edges, cone_storage_name(s.storage),
          s.reconstruction == ConeReconstruction::Grouped ? "" : ", nearest-circle");
      add(compare(a, reference, [](std::size_t) { return true; }), label, ms);
      if (orientations == 6 && spacing_edges == 1.0 && s.storage == kPaper) {
        const std::vector<bool> own = own_in_every_orientation(topology, frame, plan);
        add(compare(a, reference, [&](std::size_t i) { return bool(own[i % n]); }),
            "  of which: vertices with own cones in all", ms);
        add(compare(a, reference, [&](std::size_t i) { return !own[i % n]; }),
            "  of which: vertices filled in ≥ 1 orientation", ms);
      }
    }
    const Index stride = std::max<Index>(1, (topology.num_vertices + oracle_sample - 1) / oracle_sample);
    auto sampled = [&](std::size_t i) { return (i % n) % stride == 0; };
    if (stride >
        1) {  // the paper's engine on the oracle's sample, so that the two are compared on the same values
      SlicingPlan plan = make_diffuse_plan(topology, frame, {});
      plan.storage = ConeStorage::NearerEndpoint;
      add(compare(sky_of(compute_visibility(topology, frame, plan).measures), reference, sampled),
          format("paper, on the oracle's sample (every %u-th vertex)", stride), NAN);
    }
    for (int o : oracle_orientations) {
      const Stopwatch watch;
      SkyValues q;
      const SkyValues a = sky_of(vertex_plane_cones(topology, frame, o, stride, &q));
      add(compare(a, reference, sampled), format("oracle: a plane through the vertex, %d orientations", o),
          watch.wall_ms());
      add(compare(q, reference, sampled),
          format("oracle's 2D cones, A by great-circle quadrature (no 3D cone), %d orientations", o), NAN);
    }
  }

  fs::create_directories(out_dir);
  {
    std::ofstream csv(out_dir / "accuracy_budget.csv");
    csv << "sequence,variant,ms,mean_err,p95_err,bias,share\n";
    for (const Result& r : results)
      csv << r.sequence << ",\"" << r.variant << "\"," << r.ms << ',' << r.err.mean << ',' << r.err.p95 << ','
          << r.bias << ',' << r.share << '\n';
  }
  std::ofstream md(out_dir / "accuracy_budget.md");
  md << "# Error budget of the cones\n\nWritten by `build/bench/accuracy_budget_bench"
     << (quick ? " --quick" : "") << "` (bench/accuracy_budget_bench.cpp explains every variant) on commit "
     << source.commit << (source.dirty.empty() ? "" : " plus uncommitted changes") << ", in "
     << format("%.0f", run_watch.wall_ms() / 1000)
     << " s. Error = |A − A_ref| over every vertex and both sides "
     << "against Embree with " << reference_rays
     << " rays; real sequences at their last frame, generated ones at " << kGeneratedSize
     << " vertices, frame " << kGeneratedFrame << ". ms = CPU time of one frame's cones on "
     << "one thread (the oracle: wall time on all threads; it is not an engine, its time only says what it "
        "costs)."
     << "\n\n";
  md << "| sequence | variant | mean | p95 | bias | share of values | ms |\n|---|---|---|---|---|---|---|\n";
  for (const Result& r : results)
    md << "| " << r.sequence << " | " << r.variant << " | " << format("%.4f", r.err.mean) << " | "
       << format("%.4f", r.err.p95) << " | " << format("%+.4f", r.bias) << " | "
       << format("%.0f%%", 100 * r.share) << " | "
       << (std::isfinite(r.ms) ? format("%.0f", r.ms) : std::string("–")) << " |\n";
  std::printf("accuracy_budget: wrote %s\n", (out_dir / "accuracy_budget.md").c_str());
  return 0;
}

}  // namespace
}  // namespace pleat::bench

int main(int argc, char** argv) {
  return pleat::bench::run_main("accuracy_budget_bench", pleat::bench::run, argc, argv);
}
