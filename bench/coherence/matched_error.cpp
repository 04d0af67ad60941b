// Error statistics, flicker and log-log matched-error interpolation for the frame-coherence benchmark.
#include "bench/coherence/matched_error.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pleat::bench {

namespace {

void check_shapes(std::span<const SkyValues> a, std::span<const SkyValues> ref) {
  if (a.size() != ref.size()) throw std::invalid_argument("error statistics: frame counts differ");
  for (std::size_t f = 0; f < a.size(); ++f)
    if (a[f].size() != ref[f].size()) throw std::invalid_argument("error statistics: value counts differ");
}

double lerp(double a, double b, double f) { return a + f * (b - a); }

}  // namespace

ErrorStats error_stats(std::span<const SkyValues> a, std::span<const SkyValues> ref) {
  check_shapes(a, ref);
  std::vector<double> e;
  for (std::size_t f = 0; f < a.size(); ++f)
    for (std::size_t i = 0; i < a[f].size(); ++i)
      if (std::isfinite(ref[f][i])) e.push_back(std::abs(a[f][i] - ref[f][i]));
  ErrorStats s;
  s.count = e.size();
  if (e.empty()) return s;
  double sum = 0;
  for (double x : e) sum += x;
  s.mean = sum / double(e.size());
  const std::size_t k = static_cast<std::size_t>(std::ceil(0.95 * double(e.size()))) - 1;
  std::nth_element(e.begin(), e.begin() + std::ptrdiff_t(k), e.end());
  s.p95 = e[k];
  return s;
}

double flicker(std::span<const SkyValues> a, std::span<const SkyValues> ref) {
  check_shapes(a, ref);
  double sum = 0;
  std::size_t count = 0;
  for (std::size_t f = 0; f + 1 < a.size(); ++f)
    for (std::size_t i = 0; i < a[f].size(); ++i) {
      if (!std::isfinite(ref[f][i]) || !std::isfinite(ref[f + 1][i])) continue;
      sum += std::abs((a[f + 1][i] - a[f][i]) - (ref[f + 1][i] - ref[f][i]));
      ++count;
    }
  return count ? sum / double(count) : NAN;
}

MatchedRays matched_rays(std::span<const Rung> ladder, double target) {
  if (ladder.empty()) throw std::invalid_argument("matched_rays: empty ladder");
  for (std::size_t i = 0; i < ladder.size(); ++i) {
    const Rung& r = ladder[i];
    if (!(r.rays > 0 && r.ms > 0 && r.error > 0) || (i > 0 && !(ladder[i - 1].rays < r.rays)))
      throw std::invalid_argument("matched_rays: rungs need ascending rays and positive times and errors");
  }
  MatchedRays m;
  const Rung& first = ladder.front();
  if (first.error <= target) {
    m.bound = first.error == target ? MatchedRays::Bound::Inside : MatchedRays::Bound::Below;
    m.rays = first.rays, m.ms = first.ms, m.flicker = first.flicker;
    return m;
  }
  for (std::size_t i = 1; i < ladder.size(); ++i) {
    const Rung& lo = ladder[i - 1];
    const Rung& hi = ladder[i];
    if (hi.error > target) continue;
    // lo.error > target >= hi.error: interpolate in log-log.
    const double f = (std::log(target) - std::log(lo.error)) / (std::log(hi.error) - std::log(lo.error));
    m.rays = std::exp(lerp(std::log(lo.rays), std::log(hi.rays), f));
    m.ms = std::exp(lerp(std::log(lo.ms), std::log(hi.ms), f));
    m.flicker = std::isfinite(lo.flicker) && std::isfinite(hi.flicker) && lo.flicker > 0 && hi.flicker > 0
                    ? std::exp(lerp(std::log(lo.flicker), std::log(hi.flicker), f))
                    : NAN;
    return m;
  }
  const Rung& last = ladder.back();
  m.bound = MatchedRays::Bound::Above;
  m.rays = last.rays, m.ms = last.ms, m.flicker = last.flicker;
  return m;
}

}  // namespace pleat::bench
