#include "static_core/internal/nearest_circle.hpp"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "static_core/cone_assembly.hpp"
#include "static_core/cone_rules.hpp"

namespace pleat {
namespace {

/// Cells are built over parts of an arc at most this wide, so that every edge of a cell (an envelope arc or a
/// meridian) is well short of a half-turn and stays on one sheet, and a part (within a lune of this width)
/// never holds a whole hemisphere.
constexpr double kMaxPart = 3 * kTwoPi / 8;
/// Circles whose normals are this close to parallel (as 1 − |cos|) are one circle.
constexpr double kSameCircle = 1e-12;
/// The cache of envelopes holds at most this many sets of circles (a plan has a few: the vertices that lack a
/// cone in some orientations make the others).
constexpr std::size_t kCachedSets = 64;
/// A cell vertex this close below a clipping plane (as a sine) counts as on it: the circles' points on the
/// horizon's own circle, the envelopes' points where a circle crosses it.
constexpr double kOnBoundary = 1e-12;

using Circle = NearestCircleAssembler::Circle;
using EnvelopePiece = NearestCircleAssembler::EnvelopePiece;

glm::dvec3 on_circle(const Circle& c, double phi) { return std::cos(phi) * c.u + std::sin(phi) * c.w; }

/// The angle of direction d in circle c's frame, in [0, 2pi); NAN for a direction along its normal.
double angle_in(const Circle& c, const glm::dvec3& d) {
  const double x = glm::dot(d, c.u), y = glm::dot(d, c.w);
  if (!(x * x + y * y > 1e-28 * glm::dot(d, d))) return NAN;
  return wrap_angle(std::atan2(y, x));
}

/// The index of the envelope piece that holds angle phi (any real).
std::size_t piece_at(const std::vector<EnvelopePiece>& envelope, double phi) {
  phi = wrap_angle(phi);
  const auto after = std::upper_bound(envelope.begin(), envelope.end(), phi,
                                      [](double p, const EnvelopePiece& e) { return p < e.phi; });
  return after == envelope.begin() ? envelope.size() - 1 : std::size_t(after - envelope.begin()) - 1;
}

}  // namespace

glm::dvec3 NearestCircleAssembler::envelope_point(const CircleSet& set, std::size_t k, int sheet,
                                                  const EnvelopePiece& piece, double phi) {
  const Circle& c = set.circles[k];
  const double s = sheet == 0 ? 1.0 : -1.0;
  if (piece.circle < 0) return s * c.n;
  const glm::dvec3 d = on_circle(c, phi);
  const glm::dvec3& nj = set.circles[piece.circle].n;
  const double a = glm::dot(d, nj), b = glm::dot(c.n, nj);
  // tan τ = σ a / (1 − σ b), of sign s on its own side of the pinch (rounding aside).
  const double x = std::max(0.0, s * piece.sigma * a) / (1 - piece.sigma * b);
  return glm::normalize(d + s * x * c.n);
}

void NearestCircleAssembler::make_envelopes(CircleSet& set) {
  const std::size_t m = set.circles.size();
  set.envelope.assign(2 * m, {});
  std::vector<double> candidates;
  std::vector<glm::dvec3> curves;  // n_k − σ n_j, per (j, σ)
  std::vector<std::pair<int, int>> curve_of;
  for (std::size_t k = 0; k < m; ++k) {
    const Circle& c = set.circles[k];
    curves.clear();
    curve_of.clear();
    candidates.assign(1, 0.0);
    for (std::size_t j = 0; j < m; ++j) {
      if (j == k) continue;
      for (const int sigma : {1, -1}) {
        curves.push_back(c.n - double(sigma) * set.circles[j].n);
        curve_of.emplace_back(int(j), sigma);
      }
      // Where circle j crosses circle k, every curve of j pinches to the circle.
      const double at = angle_in(c, glm::cross(c.n, set.circles[j].n));
      if (!std::isnan(at)) candidates.insert(candidates.end(), {at, wrap_angle(at + kTwoPi / 2)});
    }
    // Where two curves cross (both points of their great circles' intersection, on either sheet).
    for (std::size_t p = 0; p < curves.size(); ++p)
      for (std::size_t q = p + 1; q < curves.size(); ++q) {
        const double at = angle_in(c, glm::cross(curves[p], curves[q]));
        if (!std::isnan(at)) candidates.insert(candidates.end(), {at, wrap_angle(at + kTwoPi / 2)});
      }
    std::sort(candidates.begin(), candidates.end());
    candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    for (int sheet = 0; sheet < 2; ++sheet) {
      const double s = sheet == 0 ? 1.0 : -1.0;
      std::vector<EnvelopePiece>& envelope = set.envelope[2 * k + sheet];
      // Between consecutive candidates one curve is the least: read it at the middle.
      for (std::size_t i = 0; i < candidates.size(); ++i) {
        const double from = candidates[i];
        const double to = i + 1 < candidates.size() ? candidates[i + 1] : candidates[0] + kTwoPi;
        const glm::dvec3 d = on_circle(c, 0.5 * (from + to));
        EnvelopePiece best{from, -1, 0};
        double least = INFINITY;
        for (std::size_t j = 0; j < m; ++j) {
          if (j == k) continue;
          const double a = glm::dot(d, set.circles[j].n), b = glm::dot(c.n, set.circles[j].n);
          const int sigma = s * a >= 0 ? 1 : -1;
          const double x = std::abs(a) / (1 - sigma * b);
          if (x < least) least = x, best = {from, int(j), sigma};
        }
        if (envelope.empty() || envelope.back().circle != best.circle || envelope.back().sigma != best.sigma)
          envelope.push_back(best);
      }
      // The turn is cyclic: a first piece (from the candidate 0) continuing the last is the last.
      if (envelope.size() > 1 && envelope.back().circle == envelope.front().circle &&
          envelope.back().sigma == envelope.front().sigma)
        envelope.erase(envelope.begin());
      for (EnvelopePiece& piece : envelope) piece.start = envelope_point(set, k, sheet, piece, piece.phi);
    }
  }
}

const NearestCircleAssembler::CircleSet& NearestCircleAssembler::circle_set() {
  auto same = [&](const CircleSet& set) {
    if (set.circles.size() != m_circles.size()) return false;
    for (std::size_t k = 0; k < m_circles.size(); ++k)
      if (set.circles[k].n != m_circles[k].n || set.circles[k].u != m_circles[k].u ||
          set.circles[k].w != m_circles[k].w)
        return false;
    return true;
  };
  for (const CircleSet& set : m_cache)
    if (same(set)) return set;
  if (m_cache.size() >= kCachedSets) m_cache.clear();
  CircleSet& set = m_cache.emplace_back();
  set.circles = m_circles;
  make_envelopes(set);
  return set;
}

void NearestCircleAssembler::gather_circles(std::span<const PlanarCone> cones) {
  m_circles.clear();
  for (auto& wedges : m_circle_wedges) wedges.clear();
  for (const PlanarCone& cone : cones) {
    const SlicingPlane& plane = *cone.plane;
    std::size_t k = 0;
    while (k < m_circles.size() && !(std::abs(glm::dot(m_circles[k].n, plane.normal)) > 1 - kSameCircle)) ++k;
    if (k == m_circles.size()) {
      m_circles.push_back({plane.normal, plane.u, plane.w,
                           glm::dot(glm::cross(plane.u, plane.w), plane.normal) > 0 ? 1.0 : -1.0});
      if (m_circle_wedges.size() < m_circles.size()) m_circle_wedges.emplace_back();
    }
    const Circle& c = m_circles[k];
    std::vector<Wedge>& into = m_circle_wedges[k];
    if (plane.u == c.u && plane.w == c.w) {
      into.insert(into.end(), cone.wedges.begin(), cone.wedges.end());
      continue;
    }
    // Another frame of the same circle: a rotation, or a reflection, of the angles.
    const double turn = std::atan2(glm::dot(plane.u, c.w), glm::dot(plane.u, c.u));
    const bool reflected = glm::dot(glm::cross(plane.u, plane.w), glm::cross(c.u, c.w)) < 0;
    for (Wedge w : cone.wedges) {
      w.start = wrap_angle(reflected ? turn - w.start - w.width : turn + w.start);
      if (reflected) std::swap(w.start_reach, w.end_reach);
      into.push_back(w);
    }
  }
}

bool NearestCircleAssembler::make_cell(const CircleSet& set, std::size_t k, double a, double b) {
  const Circle& c = set.circles[k];
  SphericalPolygon& cell = m_cell;
  cell.clear();
  auto add = [&](const glm::dvec3& d) {
    if (cell.empty() || glm::dot(cell.back(), d) < 1 - 1e-15) cell.push_back(d);
  };
  for (int sheet : {1, 0}) {
    const std::vector<EnvelopePiece>& envelope = set.envelope[2 * k + sheet];
    const std::size_t n = envelope.size(), i = piece_at(envelope, a);
    // The breakpoints in (a, b) start pieces i + 1, ..., i + count (cyclically).
    const double base = a - wrap_angle(a);  // a's turn: breakpoint phi + base (+ 2 pi) follows a
    std::size_t count = 0;
    while (count + 1 < n) {
      double phi = envelope[(i + count + 1) % n].phi + base;
      while (phi <= a) phi += kTwoPi;
      if (!(phi < b)) break;
      ++count;
    }
    const glm::dvec3 at_a = envelope_point(set, k, sheet, envelope[i], a);
    const glm::dvec3 at_b = envelope_point(set, k, sheet, envelope[piece_at(envelope, b)], b);
    if (sheet == 1) {  // lower, from a to b
      add(at_a);
      for (std::size_t step = 1; step <= count; ++step) add(envelope[(i + step) % n].start);
      add(at_b);
      add(on_circle(c, b));
    } else {  // upper, from b back to a
      add(at_b);
      for (std::size_t step = count; step >= 1; --step) add(envelope[(i + step) % n].start);
      add(at_a);
      add(on_circle(c, a));
    }
  }
  while (cell.size() > 1 && glm::dot(cell.back(), cell.front()) > 1 - 1e-15) cell.pop_back();
  if (cell.size() < 3) return false;
  // Along the lower sheet with increasing φ the cell is on the left when (u, w, n) is right-handed.
  if (c.handed < 0) std::reverse(cell.begin(), cell.end());
  return true;
}

void NearestCircleAssembler::clip_cell(const glm::dvec3& side_normal,
                                       std::span<const glm::dvec3> half_spaces) {
  m_parts.clear();
  m_parts.push() = m_cell;
  auto clip_all = [&](const glm::dvec3& h) {
    // A vertex within rounding of the boundary is put just inside it: the clipper reads the sign of
    // each vertex, and zeros or noise about zero would make crossings of no length.
    for (std::size_t q = 0; q < m_parts.size; ++q)
      for (glm::dvec3& d : m_parts[q]) {
        const double up = glm::dot(d, h);
        if (std::abs(up) < kOnBoundary) d = glm::normalize(d + (kOnBoundary - up) * h);
      }
    m_next.clear();
    for (std::size_t q = 0; q < m_parts.size; ++q) {
      const SphericalPolygon& part = m_parts[q];
      // Minor arcs between points of an open hemisphere stay in it, so a part whose vertices are all
      // inside is kept whole, and one whose vertices are all outside is dropped: it does not hold the
      // whole half-space (a part lies in a lune of width kMaxPart, of area under 2 pi), and the
      // clipper's test for that case is undecided where a vertex lies at the opposite pole (as the
      // cells' corners can).
      int below = 0;
      for (const glm::dvec3& d : part) below += glm::dot(d, h) < 0;
      if (below == 0)
        m_next.push() = part;
      else if (below < static_cast<int>(part.size()))
        m_clipper.clip(part, h, m_next);
    }
    std::swap(m_parts, m_next);
  };
  clip_all(side_normal);
  for (const glm::dvec3& h : half_spaces) clip_all(h);
}

void NearestCircleAssembler::assemble(std::span<const PlanarCone> cones, const glm::dvec3& side_normal,
                                      std::span<const glm::dvec3> half_spaces, VisibilityCone& result) {
  // 1. One circle per plane normal (up to sign); each cone's wedges in its circle's frame.
  gather_circles(cones);
  m_irradiance.clear();
  m_solid_angle.clear();
  std::size_t out = 0;
  auto emit = [&](const SphericalPolygon& piece) {
    if (piece.size() < 3) return;
    const glm::dvec3 irradiance = vector_irradiance(piece);
    const double area = pleat::solid_angle(piece, irradiance);
    // A piece lies in a hemisphere: more than 2 pi is a sliver of no width that rounding turned inside out.
    if (!(area > 0) || area > kTwoPi + 1e-9) return;
    if (result.pieces.size() <= out) result.pieces.emplace_back();
    result.pieces[out++].assign(piece.begin(), piece.end());
    m_irradiance.push_back(irradiance);
    m_solid_angle.push_back(area);
  };
  if (m_circles.empty()) {
    result.pieces.clear();
    return;
  }
  const CircleSet& set = circle_set();
  for (std::size_t k = 0; k < m_circles.size(); ++k) {
    m_united.clear();
    unite_wedges(m_circle_wedges[k], m_intervals, m_united);
    for (const Wedge& wedge : m_united) {
      const int parts = std::max(1, static_cast<int>(std::ceil(wedge.width / kMaxPart - 1e-12)));
      for (int p = 0; p < parts; ++p) {
        const double a = wedge.start + wedge.width * p / parts;
        const double b = p + 1 == parts ? wedge.end() : wedge.start + wedge.width * (p + 1) / parts;
        // 2. The cell over [a, b]; 3. its part in the side's hemisphere and the occluding planes'
        // half-spaces.
        if (!make_cell(set, k, a, b)) continue;
        clip_cell(side_normal, half_spaces);
        for (std::size_t q = 0; q < m_parts.size; ++q) emit(m_parts[q]);
      }
    }
  }
  result.pieces.resize(out);
}

namespace {

/// The nearest-circle rule's reconstructor: the assembler and its measures.
class NearestCircleReconstructor final : public ConeReconstructor {
 public:
  void assemble(std::span<const PlanarCone> cones, const glm::dvec3& side_normal,
                std::span<const glm::dvec3> half_spaces, VisibilityCone& result,
                ConeMeasures* measures) override {
    m_assembler.assemble(cones, side_normal, half_spaces, result);
    if (measures)
      *measures =
          measures_of_pieces(result, m_assembler.irradiance(), m_assembler.solid_angle(), side_normal);
  }

 private:
  NearestCircleAssembler m_assembler;
};

}  // namespace

namespace rules {
extern const ConeReconstructionRule kNearestCircle{
    "nearest-circle",
    "every direction takes the visibility of the nearest point of the nearest slicing circle: exact "
    "polygons, no grouping rules",
    [] { return std::unique_ptr<ConeReconstructor>(std::make_unique<NearestCircleReconstructor>()); }};
}  // namespace rules

}  // namespace pleat
