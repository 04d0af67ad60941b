#include "static_core/angular_set.hpp"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

namespace pleat {

double wrap_angle(double a) {
  // fmod returns a itself within a turn (exactly): the library call only for the rest (and NaN).
  if (!(a > -kTwoPi && a < kTwoPi)) a = std::fmod(a, kTwoPi);
  if (a < 0) a += kTwoPi;
  if (a >= kTwoPi) a = 0.0;
  return a;
}

double direction_angle(const glm::dvec2& d) { return wrap_angle(std::atan2(d.y, d.x)); }

Wedge wedge_between(const glm::dvec2& from, const glm::dvec2& to) {
  double width = std::atan2(from.x * to.y - from.y * to.x, glm::dot(from, to));
  if (width <= 0) width += kTwoPi;
  return {direction_angle(from), width};
}

Wedge thin_wedge_between(const glm::dvec2& from, const glm::dvec2& to) {
  double width = std::atan2(from.x * to.y - from.y * to.x, glm::dot(from, to));
  // The exact turn is left, so the true width is in (0, pi): a negative value is rounding of a width
  // next to 0 or next to pi.
  if (width < 0) width = width < -kTwoPi / 4 ? kTwoPi / 2 : 0.0;
  return {direction_angle(from), width};
}

namespace {

/// Splits wedges into linear intervals of [0, 2pi], sorted; a full turn gives [0, 2pi] alone.
void split_into_intervals(std::span<const Wedge> wedges, std::vector<std::pair<double, double>>& out) {
  out.clear();
  for (const Wedge& w : wedges) {
    if (!(w.width > 0)) continue;
    if (w.width >= kTwoPi - kAngleTolerance) {
      out.clear();
      out.emplace_back(0.0, kTwoPi);
      return;
    }
    const double s = wrap_angle(w.start), e = s + w.width;
    if (e <= kTwoPi) {
      out.emplace_back(s, e);
    } else {
      out.emplace_back(s, kTwoPi);
      out.emplace_back(0.0, e - kTwoPi);
    }
  }
  std::sort(out.begin(), out.end());
}

/// Merges sorted intervals in place (touching within kAngleTolerance), then appends them to `out` as
/// wedges, joining the interval that ends at 2pi with the one that starts at 0.
void merge_into_wedges(std::vector<std::pair<double, double>>& iv, std::vector<Wedge>& out) {
  std::size_t m = 0;
  for (std::size_t i = 0; i < iv.size(); ++i) {
    if (m > 0 && iv[i].first <= iv[m - 1].second + kAngleTolerance)
      iv[m - 1].second = std::max(iv[m - 1].second, iv[i].second);
    else
      iv[m++] = iv[i];
  }
  iv.resize(m);
  if (m == 0) return;
  if (m == 1 && iv[0].first <= kAngleTolerance && iv[0].second >= kTwoPi - kAngleTolerance) {
    out.push_back({0.0, kTwoPi});
    return;
  }
  const bool wraps =
      m > 1 && iv.front().first <= kAngleTolerance && iv.back().second >= kTwoPi - kAngleTolerance;
  for (std::size_t i = wraps ? 1 : 0; i < m; ++i) {
    auto [a, b] = iv[i];
    if (wraps && i + 1 == m) b = kTwoPi + iv.front().second;
    if (b - a > 0) out.push_back({a, b - a});
  }
  // Sorted by start: the intervals were, and the wrapping wedge is the last one.
}

}  // namespace

void unite_wedges(std::span<const Wedge> wedges, std::vector<std::pair<double, double>>& scratch,
                  std::vector<Wedge>& out) {
  split_into_intervals(wedges, scratch);
  merge_into_wedges(scratch, out);
}

void intersect_wedges(std::span<const Wedge> a, std::span<const Wedge> b, WedgeScratch& s,
                      std::vector<Wedge>& out) {
  // Normalize each side (union), split both into sorted intervals of [0, 2pi], intersect pairwise.
  s.a.clear();
  unite_wedges(a, s.intervals, s.a);
  split_into_intervals(s.a, s.x);
  s.b.clear();
  unite_wedges(b, s.intervals, s.b);
  split_into_intervals(s.b, s.y);
  s.z.clear();
  std::size_t i = 0, j = 0;
  while (i < s.x.size() && j < s.y.size()) {
    const double lo = std::max(s.x[i].first, s.y[j].first), hi = std::min(s.x[i].second, s.y[j].second);
    if (hi - lo > kAngleTolerance) s.z.emplace_back(lo, hi);
    (s.x[i].second < s.y[j].second) ? ++i : ++j;
  }
  merge_into_wedges(s.z, out);
}

namespace {

/// The signed turn from angle x to angle y the shorter way round, in [-pi, pi]. (remainder returns the
/// difference itself, exactly, within half a turn, a tie included: the library call only for the rest.)
double signed_turn(double x, double y) {
  const double d = y - x;
  return std::abs(d) <= kTwoPi / 2 ? d : std::remainder(d, kTwoPi);
}

bool is_full_turn(std::span<const Wedge> w) {
  return w.size() == 1 && w[0].width >= kTwoPi - kAngleTolerance;
}

}  // namespace

bool blend_wedges(std::span<const Wedge> a, std::span<const Wedge> b, double t, WedgeScratch& s,
                  std::vector<Wedge>& out) {
  const std::size_t k = a.size();
  if (b.size() != k) return false;
  if (k == 0) return true;
  if (is_full_turn(a) || is_full_turn(b)) {
    if (!(is_full_turn(a) && is_full_turn(b))) return false;
    out.push_back({0.0, kTwoPi});
    return true;
  }
  // The cyclic shift r (a[i] with b[(i + r) % k]) that moves the ends least in total.
  std::size_t shift = 0;
  double least = INFINITY;
  for (std::size_t r = 0; r < k; ++r) {
    double cost = 0;
    for (std::size_t i = 0; i < k && cost < least; ++i) {
      const Wedge& x = a[i];
      const Wedge& y = b[(i + r) % k];
      cost += std::abs(signed_turn(x.start, y.start)) + std::abs(signed_turn(x.end(), y.end()));
    }
    if (cost < least) least = cost, shift = r;
  }
  s.a.clear();
  for (std::size_t i = 0; i < k; ++i) {
    const Wedge& x = a[i];
    const Wedge& y = b[(i + shift) % k];
    const double turn_start = signed_turn(x.start, y.start), turn_end = signed_turn(x.end(), y.end());
    if (std::abs(turn_start) > kMaxBlendTurn || std::abs(turn_end) > kMaxBlendTurn) return false;
    // The ends' shorter turns must describe y's own width (not y's complement or a wrapped-around one).
    if (std::abs(x.width + turn_end - turn_start - y.width) > 1e-9) return false;
    const double width = x.width + t * (y.width - x.width);
    if (width > 0) s.a.push_back({wrap_angle(x.start + t * turn_start), width});
  }
  unite_wedges(s.a, s.intervals, out);
  return true;
}

bool is_united(std::span<const Wedge> wedges) {
  for (std::size_t i = 0; i < wedges.size(); ++i) {
    if (!(wedges[i].width > 0) || wedges[i].start < 0 || wedges[i].start >= kTwoPi) return false;
    if (i + 1 < wedges.size() && !(wedges[i].end() + kAngleTolerance < wedges[i + 1].start)) return false;
  }
  return wedges.size() < 2 || wedges.back().end() + kAngleTolerance < wedges.front().start + kTwoPi;
}

void clip_to_half_turn(std::span<const Wedge> wedges, double h, std::vector<Wedge>& out) {
  constexpr double kHalfTurn = kTwoPi / 2;
  for (const Wedge& w : wedges) {
    if (w.width >= kTwoPi - kAngleTolerance) {
      out.push_back({h, kHalfTurn});
      continue;
    }
    const double d = wrap_angle(w.start - h);  // the wedge is [d, d + width] relative to h
    auto piece = [&](double lo, double hi) {
      if (hi - lo > kAngleTolerance) out.push_back({wrap_angle(h + lo), hi - lo});
    };
    if (d < kHalfTurn) piece(d, std::min(d + w.width, kHalfTurn));
    if (d + w.width > kTwoPi) piece(0.0, std::min(d + w.width - kTwoPi, kHalfTurn));
  }
}

std::vector<std::pair<double, double>> AngularSet::to_intervals(std::span<const Wedge> wedges) {
  std::vector<std::pair<double, double>> out;
  split_into_intervals(wedges, out);
  return out;
}

AngularSet AngularSet::from_intervals(std::vector<std::pair<double, double>> iv) {
  std::sort(iv.begin(), iv.end());
  AngularSet set;
  merge_into_wedges(iv, set.m_wedges);
  return set;
}

AngularSet AngularSet::from_wedges(const std::vector<Wedge>& wedges) {
  return from_intervals(to_intervals(wedges));
}

AngularSet AngularSet::full() {
  AngularSet set;
  set.m_wedges.push_back({0.0, kTwoPi});
  return set;
}

double AngularSet::measure() const {
  double m = 0.0;
  for (const Wedge& w : m_wedges) m += w.width;
  return m;
}

AngularSet AngularSet::unite(const AngularSet& other) const {
  auto iv = intervals();
  const auto more = other.intervals();
  iv.insert(iv.end(), more.begin(), more.end());
  return from_intervals(std::move(iv));
}

AngularSet AngularSet::complement() const {
  const auto iv = intervals();  // sorted and disjoint: m_wedges is normalized
  std::vector<std::pair<double, double>> out;
  double cursor = 0.0;
  for (const auto& [a, b] : iv) {
    if (a > cursor + kAngleTolerance) out.emplace_back(cursor, a);
    cursor = std::max(cursor, b);
  }
  if (cursor < kTwoPi - kAngleTolerance) out.emplace_back(cursor, kTwoPi);
  return from_intervals(std::move(out));
}

AngularSet AngularSet::intersect(const AngularSet& other) const {
  WedgeScratch scratch;
  AngularSet set;
  intersect_wedges(m_wedges, other.m_wedges, scratch, set.m_wedges);
  return set;
}

AngularSet AngularSet::subtract(const AngularSet& other) const { return intersect(other.complement()); }

bool AngularSet::contains(double angle) const {
  angle = wrap_angle(angle);
  for (const Wedge& w : m_wedges) {
    double d = angle - w.start;
    if (d < 0) d += kTwoPi;
    if (d <= w.width + kAngleTolerance || kTwoPi - d <= kAngleTolerance) return true;
  }
  return false;
}

}  // namespace pleat
