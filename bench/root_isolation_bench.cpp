// Cost of root isolation (kinetic/root_isolation.hpp) on the certificates the kinetic engine builds:
// orientations of three slice points moving linearly between two frames (kinetic/moving_orientation.hpp,
// planar_orientation_certificate: degree 2), as KineticSlice certifies every triangle at the start of an
// interval.
//
// Input: the bundled drape (data/drape/drape.obj + drape.pc2, 3,111 vertices), samples 40 -> 41, the CLI's
// default plan on sample 40 (make_diffuse_plan: 6 orientations, spacing = average edge length). Every finite
// triangle of every plane's constrained triangulation at 40 whose three slice vertices survive to 41 (matched
// by mesh edge) gives one certificate; most hold over the interval (the common case), the rest are left
// "undecided" by the interval filter. Everything the timed loops read is prepared once, outside them.
//
// Benchmarks (one thread; the counter s_per_certificate is seconds per certificate):
//   BM_FilterOnly              stage (a) alone, certainly_no_root, on built certificates the filter decides.
//   BM_CertificateFromPoints   the same certificates from their six points: the interval enclosure
//                              (planar_orientation_certificate), then first_root_after from t = 0.
//   BM_FirstFailure            the engine's whole decision (first_failure from t = 0, as a triangle) on every
//                              certificate. Counters: certificates, undecided_fraction.
//   BM_RootIsolationUndecided  first_root_after from t = 0 on the certificates the filter leaves undecided:
//                              interval subdivision, exact arithmetic where it cannot decide. Counters: how
//                              many each stage decided (by_filter, by_subdivision, by_exact), with_root.
//   BM_ExactOrientationPolynomial  the exact polynomial of an undecided certificate (Gmpzf, then Gmpq).
//   BM_EventSimpleRoot         one certificate with a simple root (a point crossing the line through two
//                              others): subdivision, then a lazily narrowed RootTime.
//   BM_EventSimpleRootExact    the same event in exact arithmetic alone (exact polynomial, then stage (c)).
//   BM_CompareDistinct         ordering two event times with disjoint enclosures.
//   BM_CompareTie              an exact tie: the same algebraic time from two polynomials (gcd).
//
// Flags of ours (before Google Benchmark's own):
//   --pleat_data=DIR   the repository's data/ (default: found from this source file's path)
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <vector>

#include "bench/bench_args.hpp"
#include "kinetic/moving_orientation.hpp"
#include "kinetic/root_isolation.hpp"
#include "sim_io/mesh_sequence.hpp"
#include "static_core/mesh_slicer.hpp"
#include "static_core/slice_triangulation.hpp"
#include "static_core/slicing_plan.hpp"

namespace pleat::kinetic {
namespace {

namespace fs = std::filesystem;

fs::path g_data = fs::path(__FILE__).parent_path().parent_path() / "data";
constexpr std::size_t kDrapeFrame = 40;  // samples 40 and 41 of the bundled drape

using Triple = std::array<MovingPoint, 3>;

struct Workload {
  std::vector<Triple> triples;                   // every certificate of the interval
  std::vector<CertificatePolynomial> decided;    // built, and certainly without a zero on [0, 1] (the filter)
  std::vector<Triple> decided_points;            // their points
  std::vector<CertificatePolynomial> undecided;  // built, left undecided by the filter
};

const Workload& drape_workload() {
  static const Workload w = [] {
    Workload w;
    const MeshSequence seq = load_sequence(g_data / "drape" / "drape.obj", g_data / "drape" / "drape.pc2");
    const MeshTopology& topology = seq.topology();
    const Frame frame0 = seq.frame(kDrapeFrame), frame1 = seq.frame(kDrapeFrame + 1);
    const SlicingPlan plan = make_diffuse_plan(topology, frame0, DiffusePlanParams{});  // the CLI's defaults
    const MeshEdges edges(topology);
    const auto faces0 = candidate_faces_per_plane(topology, frame0, plan);
    const auto faces1 = candidate_faces_per_plane(topology, frame1, plan);
    SlicerScratch scratch;
    Slice slice, next;
    SliceTriangulation tri;
    std::vector<std::int32_t> next_of_edge(edges.endpoints.size(), -1);
    for (std::size_t p = 0; p < plan.planes.size(); ++p) {
      slice_mesh(topology, edges, frame0, plan.planes[p], faces0[p], scratch, slice);
      slice_mesh(topology, edges, frame1, plan.planes[p], faces1[p], scratch, next);
      tri.build(slice);
      if (tri.dimension() != 2) continue;
      for (Index y = 0; y < next.vertices.size(); ++y) next_of_edge[next.vertices[y].edge] = std::int32_t(y);
      const cgal::Cdt& cdt = tri.cdt();
      for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
        Triple t;
        bool kept = true;
        for (int i = 0; i < 3 && kept; ++i) {
          const int x = f->vertex(i)->info().slice_vertex;  // -1: a crossing point of two chains
          const std::int32_t y = x < 0 ? -1 : next_of_edge[slice.vertices[x].edge];
          kept = y >= 0;
          if (kept) t[i] = {cgal::to_glm(f->vertex(i)->point()), next.vertices[y].point};
        }
        if (kept) w.triples.push_back(t);
      }
      for (const SliceVertex& v : next.vertices) next_of_edge[v.edge] = -1;
    }
    for (const Triple& t : w.triples) {
      CertificatePolynomial c = orientation_certificate(t[0], t[1], t[2]);
      if (certainly_no_root(c)) {
        w.decided.push_back(std::move(c));
        w.decided_points.push_back(t);
      } else {
        w.undecided.push_back(std::move(c));
      }
    }
    if (w.decided.empty() || w.undecided.empty()) {
      std::fprintf(stderr, "root_isolation_bench: no certificates from %s\n", (g_data / "drape").c_str());
      std::exit(2);
    }
    return w;
  }();
  return w;
}

benchmark::Counter per_certificate(double n) {
  return benchmark::Counter(n, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

/// Stage (a) alone on a built certificate.
void BM_FilterOnly(benchmark::State& state) {
  const Workload& w = drape_workload();
  std::size_t none = 0;
  for (auto _ : state) {
    none = 0;
    for (const CertificatePolynomial& c : w.decided) none += certainly_no_root(c);
    benchmark::DoNotOptimize(none);
  }
  state.counters["certificates"] = double(w.decided.size());
  state.counters["s_per_certificate"] = per_certificate(double(w.decided.size()));
}
BENCHMARK(BM_FilterOnly);

/// The enclosure from the points, then first_root_after (no event: the filter decides).
void BM_CertificateFromPoints(benchmark::State& state) {
  const Workload& w = drape_workload();
  const RootTime t0;
  std::size_t roots = 0;
  for (auto _ : state) {
    roots = 0;
    for (const Triple& t : w.decided_points)
      roots += first_root_after(orientation_certificate(t[0], t[1], t[2]), t0).has_value();
    benchmark::DoNotOptimize(roots);
  }
  state.counters["certificates"] = double(w.decided_points.size());
  state.counters["s_per_certificate"] = per_certificate(double(w.decided_points.size()));
}
BENCHMARK(BM_CertificateFromPoints);

/// KineticSlice's decision at the start of the interval, on every certificate.
void BM_FirstFailure(benchmark::State& state) {
  const Workload& w = drape_workload();
  const RootTime t0;
  std::size_t filtered = 0;
  for (auto _ : state) {
    filtered = 0;
    for (const Triple& t : w.triples) {
      const CertificateFailure f = first_failure(t, t0, true);
      filtered += f.decided_by == CertificateFailure::DecidedBy::filter;
      benchmark::DoNotOptimize(f.time);
    }
  }
  state.counters["certificates"] = double(w.triples.size());
  state.counters["undecided_fraction"] = double(w.triples.size() - filtered) / double(w.triples.size());
  state.counters["s_per_certificate"] = per_certificate(double(w.triples.size()));
}
BENCHMARK(BM_FirstFailure);

/// Stages (b) and (c) on the certificates the filter cannot decide.
void BM_RootIsolationUndecided(benchmark::State& state) {
  const Workload& w = drape_workload();
  const RootTime t0;
  std::array<std::size_t, 3> by{};
  std::size_t roots = 0;
  for (auto _ : state) {
    by = {};
    roots = 0;
    for (const CertificatePolynomial& c : w.undecided) {
      IsolationStage stage = IsolationStage::filter;
      roots += first_root_after(c, t0, &stage).has_value();
      ++by[static_cast<std::size_t>(stage)];
    }
    benchmark::DoNotOptimize(roots);
  }
  state.counters["certificates"] = double(w.undecided.size());
  state.counters["by_filter"] = double(by[0]);
  state.counters["by_subdivision"] = double(by[1]);
  state.counters["by_exact"] = double(by[2]);
  state.counters["with_root"] = double(roots);
  state.counters["s_per_certificate"] = per_certificate(double(w.undecided.size()));
}
BENCHMARK(BM_RootIsolationUndecided);

/// The exact polynomial of a certificate (built only where intervals cannot decide).
void BM_ExactOrientationPolynomial(benchmark::State& state) {
  const Workload& w = drape_workload();
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(w.undecided[i].exact());
    i = (i + 1) % w.undecided.size();
  }
}
BENCHMARK(BM_ExactOrientationPolynomial);

/// A certificate with an event: c crosses the line through a and b (a simple root found by the subdivision,
/// then a lazily narrowed RootTime).
void BM_EventSimpleRoot(benchmark::State& state) {
  const MovingPoint a{{0.1, 0.2}, {0.1003, 0.2001}}, b{{0.11, 0.2}, {0.1101, 0.2002}};
  const MovingPoint c{{0.105, 0.203}, {0.1052, 0.194}};
  const CertificatePolynomial cert = orientation_certificate(a, b, c);
  IsolationStage stage;
  if (!first_root_after(cert, RootTime(), &stage)) state.SkipWithError("no event");
  state.SetLabel(stage == IsolationStage::subdivision ? "subdivision" : "exact");
  for (auto _ : state) benchmark::DoNotOptimize(first_root_after(cert, RootTime()));
}
BENCHMARK(BM_EventSimpleRoot);

/// The same event found in exact arithmetic alone (the exact polynomial, then stage (c)): what the lazy path
/// saves.
void BM_EventSimpleRootExact(benchmark::State& state) {
  const MovingPoint a{{0.1, 0.2}, {0.1003, 0.2001}}, b{{0.11, 0.2}, {0.1101, 0.2002}};
  const MovingPoint c{{0.105, 0.203}, {0.1052, 0.194}};
  const CertificatePolynomial cert = orientation_certificate(a, b, c);
  for (auto _ : state) benchmark::DoNotOptimize(first_root_after(cert.exact(), RootTime()));
}
BENCHMARK(BM_EventSimpleRootExact);

/// Ordering two event times whose double enclosures are disjoint (the usual event-queue comparison).
void BM_CompareDistinct(benchmark::State& state) {
  const auto a = first_root_after(ExactPolynomial::from_roots({Rational(1, 3), Rational(3)}), RootTime());
  const auto b =
      first_root_after(ExactPolynomial::from_roots({Rational(1, 3) + Rational(1, 1000000)}, 2), RootTime());
  for (auto _ : state) benchmark::DoNotOptimize(compare(*a, *b));
}
BENCHMARK(BM_CompareDistinct);

/// A tie: the same algebraic time from two polynomials (gcd path).
void BM_CompareTie(benchmark::State& state) {
  const ExactPolynomial q({Rational(-1, 2), Rational(0), Rational(1)});
  const auto a = first_root_after(q * ExactPolynomial::from_roots({Rational(3)}), RootTime());
  const auto b = first_root_after(q * ExactPolynomial::from_roots({Rational(-2), Rational(5)}), RootTime());
  for (auto _ : state) benchmark::DoNotOptimize(compare(*a, *b));
}
BENCHMARK(BM_CompareTie);

}  // namespace
}  // namespace pleat::kinetic

int main(int argc, char** argv) {
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    if (const char* v = pleat::bench::flag_value(argv[i], "--pleat_data"))
      pleat::kinetic::g_data = v;
    else
      argv[kept++] = argv[i];
  }
  argc = kept;
  // One thread: nothing here is parallel, and no TBB worker may run beside the timed loops.
  tbb::global_control control(tbb::global_control::max_allowed_parallelism, 1);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 2;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
