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
  return {direction_angle(from), width, float(glm::length(from)), float(glm::length(to))};
}

Wedge thin_wedge_between(const glm::dvec2& from, const glm::dvec2& to) {
  double width = std::atan2(from.x * to.y - from.y * to.x, glm::dot(from, to));
  // The exact turn is left, so the true width is in (0, pi): a negative value is rounding of a width
  // next to 0 or next to pi.
  if (width < 0) width = width < -kTwoPi / 4 ? kTwoPi / 2 : 0.0;
  return {direction_angle(from), width, float(glm::length(from)), float(glm::length(to))};
}

void split_into_intervals(std::span<const Wedge> wedges, std::vector<AngularInterval>& out) {
  out.clear();
  for (const Wedge& w : wedges) {
    if (!(w.width > 0)) continue;
    if (w.width >= kTwoPi - kAngleTolerance) {
      out.clear();
      out.push_back({0.0, kTwoPi});
      return;
    }
    const double s = wrap_angle(w.start), e = s + w.width;
    if (e <= kTwoPi) {
      out.push_back({s, e, w.start_reach, w.end_reach});
    } else {  // the cut at 2pi is no end: merge_into_wedges joins the two pieces again
      out.push_back({s, kTwoPi, w.start_reach, INFINITY});
      out.push_back({0.0, e - kTwoPi, INFINITY, w.end_reach});
    }
  }
  std::sort(out.begin(), out.end(), [](const AngularInterval& a, const AngularInterval& b) {
    return a.lo < b.lo || (a.lo == b.lo && a.hi < b.hi);
  });
}

void merge_into_wedges(std::vector<AngularInterval>& iv, std::vector<Wedge>& out) {
  std::size_t m = 0;
  for (std::size_t i = 0; i < iv.size(); ++i) {
    if (m > 0 && iv[i].lo <= iv[m - 1].hi + kAngleTolerance) {
      if (iv[i].hi > iv[m - 1].hi) iv[m - 1].hi = iv[i].hi, iv[m - 1].hi_reach = iv[i].hi_reach;
    } else {
      iv[m++] = iv[i];
    }
  }
  iv.resize(m);
  if (m == 0) return;
  if (m == 1 && iv[0].lo <= kAngleTolerance && iv[0].hi >= kTwoPi - kAngleTolerance) {
    out.push_back({0.0, kTwoPi});
    return;
  }
  const bool wraps = m > 1 && iv.front().lo <= kAngleTolerance && iv.back().hi >= kTwoPi - kAngleTolerance;
  for (std::size_t i = wraps ? 1 : 0; i < m; ++i) {
    AngularInterval x = iv[i];
    if (wraps && i + 1 == m) x.hi = kTwoPi + iv.front().hi, x.hi_reach = iv.front().hi_reach;
    if (x.hi - x.lo > 0) out.push_back({x.lo, x.hi - x.lo, x.lo_reach, x.hi_reach});
  }
  // Sorted by start: the intervals were, and the wrapping wedge is the last one.
}

void unite_wedges(std::span<const Wedge> wedges, std::vector<AngularInterval>& scratch,
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
  intersect_intervals(s.x, s.y, s.z);
  merge_into_wedges(s.z, out);
}

void intersect_intervals(std::span<const AngularInterval> a, std::span<const AngularInterval> b,
                         std::vector<AngularInterval>& out) {
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    const AngularInterval &x = a[i], &y = b[j];
    const AngularInterval& from = x.lo >= y.lo ? x : y;
    const AngularInterval& to = x.hi <= y.hi ? x : y;
    // Ends that coincide to within the tolerance are one end: it keeps a horizon's reach if either has one
    // (INFINITY: none), whichever rounding put further in.
    const float lo_reach =
        std::abs(x.lo - y.lo) <= kAngleTolerance ? std::min(x.lo_reach, y.lo_reach) : from.lo_reach;
    const float hi_reach =
        std::abs(x.hi - y.hi) <= kAngleTolerance ? std::min(x.hi_reach, y.hi_reach) : to.hi_reach;
    if (to.hi - from.lo > kAngleTolerance) out.push_back({from.lo, to.hi, lo_reach, hi_reach});
    (x.hi < y.hi) ? ++i : ++j;
  }
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

namespace {

/// The end at angle `blended` (reach `blended_reach`), re-aimed from `eye` at the horizon point `point` when
/// it has one and the turn stays within kMaxAimTurn. Returns the signed turn applied and sets the reach.
double aim_end(double blended, const glm::dvec2* point, const glm::dvec2& eye, float& reach) {
  if (!point) return 0.0;
  const glm::dvec2 d = *point - eye;
  const double length = glm::length(d);
  if (!(length > 0)) return 0.0;
  const double turn = signed_turn(blended, direction_angle(d));
  if (!(std::abs(turn) <= kMaxAimTurn)) return 0.0;
  reach = float(length);
  return turn;
}

/// blend_wedges, and with `aim` each end whose reaches are finite on both sides moved to the direction from
/// aim->eye to the blend of the two horizon points (aim_wedges).
struct Aim {
  glm::dvec2 apex_a, apex_b, eye;
  double gap;                             ///< plane b's offset minus plane a's
  std::vector<HorizonTangent>* tangents;  ///< null: none wanted
};

/// Whether wedge x can move to wedge y: each end by at most kMaxBlendTurn the shorter way round, and those
/// turns describing y's own width (not y's complement or a wrapped-around one). Sets the ends' turns.
bool can_move(const Wedge& x, const Wedge& y, double& turn_start, double& turn_end) {
  turn_start = signed_turn(x.start, y.start);
  turn_end = signed_turn(x.end(), y.end());
  return std::abs(turn_start) <= kMaxBlendTurn && std::abs(turn_end) <= kMaxBlendTurn &&
         std::abs(x.width + turn_end - turn_start - y.width) <= 1e-9;
}

/// The ends' total turn when every a[i] moves to b[(i + r) % k] (both of k wedges); infinite when one cannot
/// (can_move).
double shift_cost(std::span<const Wedge> a, std::span<const Wedge> b, std::size_t r) {
  double cost = 0, turn_start, turn_end;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!can_move(a[i], b[(i + r) % a.size()], turn_start, turn_end)) return INFINITY;
    cost += std::abs(turn_start) + std::abs(turn_end);
  }
  return cost;
}

/// The cyclic shift r (a[i] with b[(i + r) % k], both of k wedges) that moves the ends least in total, valid
/// or not (blend_or_aim refuses an invalid one: the sets do not match).
std::size_t least_turn_shift(std::span<const Wedge> a, std::span<const Wedge> b) {
  const std::size_t k = a.size();
  std::size_t shift = 0;
  double least = INFINITY;
  for (std::size_t r = 0; r < k; ++r) {
    double cost = 0, turn_start, turn_end;
    for (std::size_t i = 0; i < k && cost < least; ++i) {
      can_move(a[i], b[(i + r) % k], turn_start, turn_end);  // the turns, whether or not it can
      cost += std::abs(turn_start) + std::abs(turn_end);
    }
    if (cost < least) least = cost, shift = r;
  }
  return shift;
}

/// `fewer` (united, not a full turn) with the one wedge or the one gap it lacks against `more` (one wedge
/// more, not a full turn) put in, into s.pad, and the shift that matches them (a[i] with b[(i + shift) % k]):
/// either a wedge of `more` whose middle lies in a gap of `fewer`, put in as a wedge of width 0 there and
/// matched to it (a gap closing between the planes), or a gap of `more` whose middle lies in a wedge of
/// `fewer`, put in as a cut of that wedge into two that touch there, matched to the gap's two sides (an
/// occluder rising between the planes). Of every candidate whose match is valid (can_move), the one whose
/// ends turn least. The put-in ends have no reach (nothing is aimed at them). False when there is none.
bool pad_to_match(std::span<const Wedge> fewer, std::span<const Wedge> more, WedgeScratch& s,
                  std::size_t& shift) {
  const std::size_t k = more.size();
  double best = INFINITY;
  // s.trial's wedge `at` is the one matched to more[i]: the shift follows.
  auto offer = [&](std::size_t at, std::size_t i) {
    const std::size_t r = (i + k - at) % k;
    const double cost = shift_cost(s.trial, more, r);
    if (cost < best) best = cost, shift = r, s.pad.swap(s.trial);
  };
  auto inside = [](double angle, const Wedge& w) {
    const double d = wrap_angle(angle - w.start);
    return d > 0 && d < w.width;
  };
  for (std::size_t i = 0; i < k; ++i) {  // a wedge fewer lacks, in one of its gaps
    const double middle = wrap_angle(more[i].start + more[i].width / 2);
    if (std::any_of(fewer.begin(), fewer.end(), [&](const Wedge& w) { return inside(middle, w); })) continue;
    const std::size_t at =
        std::size_t(std::upper_bound(fewer.begin(), fewer.end(), middle,
                                     [](double x, const Wedge& w) { return x < w.start; }) -
                    fewer.begin());
    s.trial.assign(fewer.begin(), fewer.begin() + at);
    s.trial.push_back({middle, 0.0});
    s.trial.insert(s.trial.end(), fewer.begin() + at, fewer.end());
    offer(at, i);
  }
  if (k >= 2)
    for (std::size_t i = 0; i < k; ++i) {  // a gap fewer lacks: between more[i] and its successor
      const double gap = wrap_angle(more[(i + 1) % k].start - more[i].end());
      const double middle = wrap_angle(more[i].end() + gap / 2);
      for (std::size_t j = 0; j < fewer.size(); ++j) {
        if (!inside(middle, fewer[j])) continue;
        const double d = wrap_angle(middle - fewer[j].start);
        s.trial.assign(fewer.begin(), fewer.begin() + j);
        s.trial.push_back({fewer[j].start, d, fewer[j].start_reach, INFINITY});
        s.trial.push_back({middle, fewer[j].width - d, INFINITY, fewer[j].end_reach});
        s.trial.insert(s.trial.end(), fewer.begin() + j + 1, fewer.end());
        offer(j, i);
      }
    }
  return best < INFINITY;
}

bool blend_or_aim(std::span<const Wedge> a, std::span<const Wedge> b, double t, const Aim* aim,
                  WedgeScratch& s, std::vector<Wedge>& out) {
  if (a.empty() && b.empty()) return true;
  if (is_full_turn(a) || is_full_turn(b)) {
    if (!(is_full_turn(a) && is_full_turn(b))) return false;
    out.push_back({0.0, kTwoPi});
    return true;
  }
  std::size_t shift = 0;       // a[i] is matched with b[(i + shift) % k]
  if (a.size() != b.size()) {  // one wedge or one gap more on one side: put it in on the other
    // (Not against an empty set: measured worse, docs/method.md §7.)
    if (a.empty() || b.empty() || (a.size() + 1 != b.size() && b.size() + 1 != a.size())) return false;
    const bool a_fewer = a.size() < b.size();
    if (!pad_to_match(a_fewer ? a : b, a_fewer ? b : a, s, shift)) return false;
    (a_fewer ? a : b) = s.pad;
    if (!a_fewer) shift = (a.size() - shift) % a.size();  // the match seen from a
  } else {
    shift = least_turn_shift(a, b);
  }
  const std::size_t k = a.size();
  s.a.clear();
  for (std::size_t i = 0; i < k; ++i) {
    const Wedge& x = a[i];
    const Wedge& y = b[(i + shift) % k];
    double turn_start, turn_end;
    if (!can_move(x, y, turn_start, turn_end)) return false;
    double start = x.start + t * turn_start;
    double width = x.width + t * (y.width - x.width);
    float start_reach = INFINITY, end_reach = INFINITY;
    if (aim) {
      // The horizon points of the matched ends, blended: where the occluding silhouette crosses the plane
      // through the eye, to first order.
      struct Points {
        glm::dvec2 x, y, blend;
      };
      auto point = [&](double ax, float rx, double ay, float ry, Points& p) -> const glm::dvec2* {
        if (!std::isfinite(rx) || !std::isfinite(ry)) return nullptr;
        p.x = aim->apex_a + double(rx) * glm::dvec2(std::cos(ax), std::sin(ax));
        p.y = aim->apex_b + double(ry) * glm::dvec2(std::cos(ay), std::sin(ay));
        p.blend = p.x + t * (p.y - p.x);
        return &p.blend;
      };
      Points ps{}, pe{};
      const double ds =
          aim_end(start, point(x.start, x.start_reach, y.start, y.start_reach, ps), aim->eye, start_reach);
      const double de =
          aim_end(start + width, point(x.end(), x.end_reach, y.end(), y.end_reach, pe), aim->eye, end_reach);
      start += ds;
      width = std::min(width + de - ds, kTwoPi);
      // The horizon's great circle at an aimed end: through the eye and both horizon points (the aimed
      // direction, towards their blend, lies in it).
      auto tangent = [&](const Points& p, double angle) {
        const glm::dvec3 to_x(p.x - aim->eye, -t * aim->gap), to_y(p.y - aim->eye, (1 - t) * aim->gap);
        const glm::dvec3 n = glm::cross(to_x, to_y);
        const double length = glm::length(n);
        if (length > 1e-12 * glm::length(to_x) * glm::length(to_y))
          aim->tangents->push_back({wrap_angle(angle), n / length});
      };
      if (aim->tangents && aim->gap != 0 && width > 0) {
        if (std::isfinite(start_reach)) tangent(ps, start);
        if (std::isfinite(end_reach)) tangent(pe, start + width);
      }
    }
    if (width > 0) s.a.push_back({wrap_angle(start), width, start_reach, end_reach});
  }
  unite_wedges(s.a, s.intervals, out);
  return true;
}

}  // namespace

bool blend_wedges(std::span<const Wedge> a, std::span<const Wedge> b, double t, WedgeScratch& s,
                  std::vector<Wedge>& out) {
  return blend_or_aim(a, b, t, nullptr, s, out);
}

bool aim_wedges(std::span<const Wedge> a, const glm::dvec2& apex_a, std::span<const Wedge> b,
                const glm::dvec2& apex_b, double t, const glm::dvec2& eye, WedgeScratch& s,
                std::vector<Wedge>& out, double gap, std::vector<HorizonTangent>* tangents) {
  const Aim aim{apex_a, apex_b, eye, gap, tangents};
  return blend_or_aim(a, b, t, &aim, s, out);
}

void complement_wedges(std::span<const Wedge> wedges, std::vector<Wedge>& out) {
  if (wedges.empty()) {
    out.push_back({0.0, kTwoPi});
    return;
  }
  const std::size_t first = out.size();
  for (std::size_t i = 0; i < wedges.size(); ++i) {
    const double from = wedges[i].end();
    const double to = i + 1 < wedges.size() ? wedges[i + 1].start : wedges.front().start + kTwoPi;
    if (to - from > kAngleTolerance) out.push_back({wrap_angle(from), to - from});
  }
  std::sort(out.begin() + static_cast<long>(first), out.end(),
            [](const Wedge& a, const Wedge& b) { return a.start < b.start; });
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
    auto piece = [&](double lo, float lo_reach, double hi, float hi_reach) {
      if (hi - lo > kAngleTolerance) out.push_back({wrap_angle(h + lo), hi - lo, lo_reach, hi_reach});
    };
    const double e = d + w.width;
    if (d < kHalfTurn)
      e <= kHalfTurn ? piece(d, w.start_reach, e, w.end_reach) : piece(d, w.start_reach, kHalfTurn, INFINITY);
    if (e > kTwoPi)
      e - kTwoPi <= kHalfTurn ? piece(0.0, INFINITY, e - kTwoPi, w.end_reach)
                              : piece(0.0, INFINITY, kHalfTurn, INFINITY);
  }
}

std::vector<std::pair<double, double>> AngularSet::to_intervals(std::span<const Wedge> wedges) {
  std::vector<AngularInterval> iv;
  split_into_intervals(wedges, iv);
  std::vector<std::pair<double, double>> out;
  out.reserve(iv.size());
  for (const AngularInterval& x : iv) out.emplace_back(x.lo, x.hi);
  return out;
}

AngularSet AngularSet::from_intervals(std::vector<std::pair<double, double>> pairs) {
  std::sort(pairs.begin(), pairs.end());
  std::vector<AngularInterval> iv;
  iv.reserve(pairs.size());
  for (const auto& [lo, hi] : pairs) iv.push_back({lo, hi});
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
  AngularSet set;
  complement_wedges(m_wedges, set.m_wedges);
  return set;
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
