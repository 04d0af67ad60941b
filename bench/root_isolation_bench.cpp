// Cost of the kinetic layer's certificate filter and root isolation (kinetic/root_isolation.hpp).
// Inputs imitate cloth between two frames: slice vertices ~1 cm apart moving ~1 mm, so that most
// certificates hold (the common case); the event cases are separate benchmarks. Deterministic inputs.
#include <benchmark/benchmark.h>

#include <glm/geometric.hpp>
#include <random>
#include <vector>

#include "kinetic/certificate_polynomial.hpp"
#include "kinetic/root_isolation.hpp"

namespace pleat::kinetic {
namespace {

SlicingPlane bench_plane() {
  SlicingPlane p;
  p.normal = glm::normalize(glm::dvec3(1, 1, 0));
  p.u = glm::normalize(glm::cross(glm::dvec3(0, 0, 1), p.normal));
  p.w = glm::cross(p.normal, p.u);
  p.offset = 0.25;
  return p;
}

/// A slice vertex near `at` (in the plane) on an edge ~1 cm long, both endpoints moving up to `move`.
SliceVertexMotion edge_near(const SlicingPlane& plane, const glm::dvec3& at, double move, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0), h(0.002, 0.008);
  const glm::dvec3 c = at - (glm::dot(plane.normal, at) - plane.offset) * plane.normal;
  const glm::dvec3 up = c + h(rng) * plane.normal, down = c - h(rng) * plane.normal;
  const auto jitter = [&] { return glm::dvec3(u(rng), u(rng), u(rng)) * move; };
  return {up, up + jitter(), down, down + jitter()};
}

/// Triangles of slice vertices (~1 cm) whose orientation keeps its sign over the interval.
struct Workload {
  SlicingPlane plane = bench_plane();
  std::vector<std::array<SliceVertexMotion, 3>> triangles;
  std::vector<std::array<SliceVertexTrack, 3>> tracks;
  std::vector<CertificatePolynomial> certificates;
};

const Workload& no_event_workload() {
  static const Workload w = [] {
    Workload w;
    std::mt19937 rng(20261121);
    std::uniform_real_distribution<double> pos(-1.0, 1.0);
    while (w.triangles.size() < 4096) {
      const glm::dvec3 base(pos(rng), pos(rng), pos(rng));
      const std::array<SliceVertexMotion, 3> t{edge_near(w.plane, base, 0.001, rng),
                                               edge_near(w.plane, base + 0.01 * w.plane.u, 0.001, rng),
                                               edge_near(w.plane, base + 0.01 * w.plane.w, 0.001, rng)};
      const CertificatePolynomial c = orientation_certificate(w.plane, t[0], t[1], t[2]);
      if (!certainly_no_root(c)) continue;
      w.triangles.push_back(t);
      w.tracks.push_back({track_slice_vertex(w.plane, t[0]), track_slice_vertex(w.plane, t[1]),
                          track_slice_vertex(w.plane, t[2])});
      w.certificates.push_back(c);
    }
    return w;
  }();
  return w;
}

/// Stage (a) alone on a built certificate.
void BM_FilterOnly(benchmark::State& state) {
  const Workload& w = no_event_workload();
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(certainly_no_root(w.certificates[i]));
    i = (i + 1) % w.certificates.size();
  }
}
BENCHMARK(BM_FilterOnly);

/// The per-certificate cost when slice-vertex tracks are shared: build the degree-5 enclosure, run
/// first_root_after (no event).
void BM_CertificateFromTracks(benchmark::State& state) {
  const Workload& w = no_event_workload();
  const RootTime t0;
  std::size_t i = 0;
  for (auto _ : state) {
    const auto& t = w.tracks[i];
    benchmark::DoNotOptimize(first_root_after(orientation_certificate(w.plane, t[0], t[1], t[2]), t0));
    i = (i + 1) % w.tracks.size();
  }
}
BENCHMARK(BM_CertificateFromTracks);

/// One slice-vertex track (shared by the ~6 certificates of a slice vertex).
void BM_SliceVertexTrack(benchmark::State& state) {
  const Workload& w = no_event_workload();
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(track_slice_vertex(w.plane, w.triangles[i][0]));
    i = (i + 1) % w.triangles.size();
  }
}
BENCHMARK(BM_SliceVertexTrack);

/// Everything from raw positions: three tracks, the enclosure, the filter.
void BM_CertificateFromPositions(benchmark::State& state) {
  const Workload& w = no_event_workload();
  const RootTime t0;
  std::size_t i = 0;
  for (auto _ : state) {
    const auto& t = w.triangles[i];
    benchmark::DoNotOptimize(first_root_after(orientation_certificate(w.plane, t[0], t[1], t[2]), t0));
    i = (i + 1) % w.triangles.size();
  }
}
BENCHMARK(BM_CertificateFromPositions);

void BM_PlaneSide(benchmark::State& state) {
  const Workload& w = no_event_workload();
  const RootTime t0;
  std::size_t i = 0;
  for (auto _ : state) {
    const auto& m = w.triangles[i][0];
    benchmark::DoNotOptimize(first_root_after(plane_side_certificate(w.plane, m.above0, m.above1), t0));
    i = (i + 1) % w.triangles.size();
  }
}
BENCHMARK(BM_PlaneSide);

/// A certificate with an event (a simple root found by the subdivision; exact polynomial, narrowed RootTime).
void BM_EventSimpleRoot(benchmark::State& state) {
  const SlicingPlane plane = bench_plane();
  std::mt19937 rng(7);
  const glm::dvec3 base(0.1, 0.2, 0.3);
  // The third vertex crosses the line through the first two.
  SliceVertexMotion a = edge_near(plane, base, 0.0, rng),
                    b = edge_near(plane, base + 0.01 * plane.u, 0.0, rng);
  SliceVertexMotion c = edge_near(plane, base + 0.005 * plane.u + 0.003 * plane.w, 0.0, rng);
  c.above1 -= 0.009 * plane.w;
  c.below1 -= 0.009 * plane.w;
  const CertificatePolynomial cert = orientation_certificate(plane, a, b, c);
  IsolationStage stage;
  if (!first_root_after(cert, RootTime(), &stage)) state.SkipWithError("no event");
  state.SetLabel(stage == IsolationStage::subdivision ? "subdivision" : "exact");
  for (auto _ : state) benchmark::DoNotOptimize(first_root_after(cert, RootTime()));
}
BENCHMARK(BM_EventSimpleRoot);

/// The exact polynomial of an orientation certificate (built only when the filter fails).
void BM_ExactOrientationPolynomial(benchmark::State& state) {
  const Workload& w = no_event_workload();
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(w.certificates[i].exact());
    i = (i + 1) % w.certificates.size();
  }
}
BENCHMARK(BM_ExactOrientationPolynomial);

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

BENCHMARK_MAIN();
