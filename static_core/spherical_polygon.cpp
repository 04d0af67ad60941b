// Spherical polygons: hemisphere clipping, Lambert's formula, Arvo's vector irradiance, the cosine-weighted
// first moment and the solid angle (docs/method.md §9).
//
// Closed forms used here (P a spherical polygon with unit vertices v_i, counter-clockwise about its
// interior, edges minor arcs; K = {t w : 0 <= t <= 1, w in P} the solid cone over it; the side of K over
// edge i is a circular sector of radius 1, angle theta_i, outward normal -Gamma_i):
//  * Divergence theorem with the constant field e_j on K:  integral_P w dw = 1/2 sum theta_i Gamma_i
//    (Arvo 1995, "vector irradiance"); Lambert's formula is its component along n.
//  * With the field x_j e_k (divergence delta_jk, volume of K = Omega/3) and the sector's first moment
//    integral_sector x dA = 1/3 tan(theta/2) (a + b):
//      integral_P w w^T dw = Omega/3 I + 1/3 sum tan(theta_i/2) (v_i + v_i+1) Gamma_i^T,
//    and tan(theta/2) Gamma = (a x b) / (1 + a.b), so the cosine-weighted moment about n is
//      integral_P w (n.w) dw = Omega/3 n + 1/3 sum (v_i + v_i+1) (n . (v_i x v_i+1)) / (1 + v_i . v_i+1).
//    (This is the first/second-moment edge sum of Arvo's irradiance tensors, derived afresh here.)
//  * Solid angle: fan of signed Van Oosterom–Strackee triangles from an apex c. The fan's 2-chain has
//    multiplicity 0 at -c, so its sum is Omega - 4 pi * winding(-c): reducing modulo 4 pi gives Omega, and
//    the same identity with apex -w gives an exact point-in-polygon test for w.
#include "static_core/spherical_polygon.hpp"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

namespace pleat {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTwoPi = 2.0 * kPi;
constexpr double kFourPi = 4.0 * kPi;
constexpr double kMaxHorizonStep = 0.5 * kPi;  // horizon arcs are cut into steps of at most a quarter turn

enum NodeKind : int { kVertex = 0, kEntry = 1, kExit = 2 };

/// theta * Gamma for the minor arc a -> b (zero for a degenerate arc).
glm::dvec3 angle_weighted_edge_normal(const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 c = glm::cross(a, b);
  const double s = glm::length(c);
  if (s == 0.0) return glm::dvec3(0.0);
  return (std::atan2(s, glm::dot(a, b)) / s) * c;
}

/// Signed solid angle of the spherical triangle (a, b, c) with minor-arc sides (Van Oosterom–Strackee).
double triangle_solid_angle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  const double num = glm::dot(a, glm::cross(b, c));
  const double den = 1.0 + glm::dot(a, b) + glm::dot(b, c) + glm::dot(c, a);
  if (num == 0.0 && den <= 0.0) return 0.0;  // degenerate (an antipodal pair): measure zero
  return 2.0 * std::atan2(num, den);
}

/// Sum of the signed fan triangles (apex, v_i, v_i+1).
double fan_solid_angle(const SphericalPolygon& poly, const glm::dvec3& apex) {
  double sum = 0.0;
  const std::size_t n = poly.size();
  for (std::size_t i = 0; i < n; ++i) sum += triangle_solid_angle(apex, poly[i], poly[(i + 1) % n]);
  return sum;
}

/// An orthonormal pair (e1, e2) with e1 x e2 = n.
void horizon_frame(const glm::dvec3& n, glm::dvec3& e1, glm::dvec3& e2) {
  const glm::dvec3 helper = std::abs(n.x) < 0.6   ? glm::dvec3(1, 0, 0)
                            : std::abs(n.y) < 0.6 ? glm::dvec3(0, 1, 0)
                                                  : glm::dvec3(0, 0, 1);
  e1 = glm::normalize(glm::cross(helper, n));
  e2 = glm::cross(n, e1);
}

/// Counter-clockwise angle from azimuth a to azimuth b, in [0, 2 pi).
double ccw_angle(double from, double to) {
  double d = to - from;
  if (!(d > -kTwoPi && d < kTwoPi)) d = std::fmod(d, kTwoPi);  // else fmod would return d itself
  if (d < 0.0) d += kTwoPi;
  return d;
}

/// Appends the points strictly between x and the point `angle` further counter-clockwise about n along
/// the horizon, so that every step is at most a quarter turn. x must be on the horizon.
void append_horizon_arc(const glm::dvec3& x, const glm::dvec3& n, double angle, SphericalPolygon& out) {
  const int steps = std::max(1, static_cast<int>(std::ceil(angle / kMaxHorizonStep)));
  const glm::dvec3 y = glm::cross(n, x);  // x rotated a quarter turn counter-clockwise about n
  for (int k = 1; k < steps; ++k) {
    const double phi = angle * k / steps;
    out.push_back(std::cos(phi) * x + std::sin(phi) * y);
  }
}

/// The point where the minor arc a -> b meets the horizon of n (da = n.a and db = n.b of opposite signs),
/// projected exactly onto the horizon.
glm::dvec3 horizon_crossing(const glm::dvec3& a, const glm::dvec3& b, double da, double db,
                            const glm::dvec3& n) {
  glm::dvec3 p = std::abs(db) * a + std::abs(da) * b;
  p -= glm::dot(p, n) * n;
  const double len = glm::length(p);
  if (len == 0.0) return a;  // cannot happen for a minor arc; keep the vertex
  return p / len;
}

/// Winding number about n of the orthographic projection of the polygon's vertices onto the plane
/// orthogonal to n (Sunday's crossing rule, no trigonometry). When the origin lies on an edge's line where
/// that edge crosses the reference ray, the count is ambiguous: then the answer is +1 or -1 by the sign of
/// integral_P n.w, which is all the callers need (for a boundary on one side of the horizon it is >= 0 when
/// P lies within the hemisphere of n or holds all of it, < 0 when P holds -n or lies strictly below).
int projected_winding(const SphericalPolygon& poly, const glm::dvec3& n) {
  glm::dvec3 e1, e2;
  horizon_frame(n, e1, e2);
  const std::size_t count = poly.size();
  int winding = 0;
  double ax = glm::dot(poly[count - 1], e1), ay = glm::dot(poly[count - 1], e2);
  for (std::size_t i = 0; i < count; ++i) {
    const double bx = glm::dot(poly[i], e1), by = glm::dot(poly[i], e2);
    const double cross = ax * by - ay * bx;
    if (ay <= 0.0) {
      if (by > 0.0) {
        if (cross == 0.0) return glm::dot(n, vector_irradiance(poly)) >= 0.0 ? 1 : -1;
        if (cross > 0.0) ++winding;
      }
    } else if (by <= 0.0) {
      if (cross == 0.0) return glm::dot(n, vector_irradiance(poly)) >= 0.0 ? 1 : -1;
      if (cross < 0.0) --winding;
    }
    ax = bx;
    ay = by;
  }
  return winding;
}

}  // namespace

/// Counter-clockwise angle about n along the horizon from crossing x to crossing e, in [0, 2 pi]. Two
/// crossings that round to (nearly) the same point, e.g. where a polygon dips 1e-20 below the horizon at
/// one vertex, are ordered by the exact sign of n . (x' x e') expanded over the unrounded arcs they lie on
/// (x' = wa a + wb b never formed, so the tiny weights keep their relative precision): e just
/// counter-clockwise of x gives ~0, just clockwise gives the full turn.
double HemisphereClipper::crossing_ccw_angle(const Node& x, const Node& e, const glm::dvec3& n) {
  constexpr double kTie = 1e-9;
  const double angle = ccw_angle(x.azimuth, e.azimuth);
  if (angle > kTie && angle < kTwoPi - kTie) return angle;
  auto det = [&](const glm::dvec3& u, const glm::dvec3& v) { return glm::dot(n, glm::cross(u, v)); };
  const double orientation = x.wa * e.wa * det(x.a, e.a) + x.wa * e.wb * det(x.a, e.b) +
                             x.wb * e.wa * det(x.b, e.a) + x.wb * e.wb * det(x.b, e.b);
  if (orientation > 0.0) return angle <= kTie ? angle : 0.0;
  if (orientation < 0.0) return angle >= kTwoPi - kTie ? angle : kTwoPi;
  return 0.0;
}

SphericalPolygon hemisphere_polygon(const glm::dvec3& n) {
  glm::dvec3 e1, e2;
  horizon_frame(n, e1, e2);
  return {e1, e2, -e1, -e2};
}

std::size_t HemisphereClipper::clip(const SphericalPolygon& poly, const glm::dvec3& n,
                                    SphericalPolygonList& out) {
  const std::size_t count = poly.size();
  if (count < 3) return 0;
  m_dots.resize(count);
  std::size_t inside = 0;
  for (std::size_t i = 0; i < count; ++i) {
    m_dots[i] = glm::dot(n, poly[i]);
    if (m_dots[i] >= 0.0) ++inside;
  }
  if (inside == count || inside == 0) return clip_uncrossed(poly, n, inside, out);
  list_crossings(poly, n);
  pair_crossings(n);
  return walk_cycles(n, out);
}

std::size_t HemisphereClipper::clip_uncrossed(const SphericalPolygon& poly, const glm::dvec3& n,
                                              std::size_t inside, SphericalPolygonList& out) {
  const std::size_t count = poly.size();
  // The boundary does not cross the horizon, so the open hemisphere beyond it (inside == count) or the
  // closed hemisphere (inside == 0) is entirely in the polygon or entirely outside it. Which one: the
  // winding number about n of the boundary's orthographic projection onto the horizon plane (seen from
  // n, a minor arc projects to less than half an ellipse centred on the origin, so its chord leaves the
  // origin on the same side): +1 when P holds n, -1 when it holds -n, 0 otherwise.
  const int winding = projected_winding(poly, n);
  if (inside == count) {
    SphericalPolygon& piece = out.push();
    if (winding != -1) {
      piece.assign(poly.begin(), poly.end());
      return 1;
    }
    // P holds the other hemisphere: P cap H is the hemisphere with the complement of P cut out, a region
    // with a hole. One weakly simple polygon: the horizon all the way round from h0, a bridge up the
    // meridian to the lowest vertex v_k, the polygon's boundary from v_k back to v_k, and the bridge down.
    std::size_t k = 0;
    for (std::size_t i = 1; i < count; ++i)
      if (m_dots[i] < m_dots[k]) k = i;
    glm::dvec3 h0 = poly[k] - m_dots[k] * n;
    const double len = glm::length(h0);
    if (len > 0.0) {
      h0 /= len;
    } else {
      glm::dvec3 e1, e2;
      horizon_frame(n, e1, e2);
      h0 = e1;
    }
    piece.push_back(h0);
    append_horizon_arc(h0, n, kTwoPi, piece);
    piece.push_back(h0);
    for (std::size_t i = 0; i <= count; ++i) piece.push_back(poly[(k + i) % count]);
    return 1;
  }
  if (winding != 1) return 0;
  glm::dvec3 e1, e2;
  horizon_frame(n, e1, e2);
  SphericalPolygon& piece = out.push();
  piece.assign({e1, e2, -e1, -e2});
  return 1;
}

void HemisphereClipper::list_crossings(const SphericalPolygon& poly, const glm::dvec3& n) {
  const std::size_t count = poly.size();
  // Sutherland–Hodgman pass: kept vertices and crossing points, in polygon order.
  glm::dvec3 e1, e2;
  horizon_frame(n, e1, e2);
  m_nodes.clear();
  m_entries.clear();
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t j = (i + 1) % count;
    const bool in_a = m_dots[i] >= 0.0;
    const bool in_b = m_dots[j] >= 0.0;
    if (in_a) m_nodes.push_back({poly[i], kVertex, 0.0, -1, 0.0, {}, {}, 0.0, 0.0});
    if (in_a != in_b) {
      const glm::dvec3 p = horizon_crossing(poly[i], poly[j], m_dots[i], m_dots[j], n);
      const double azimuth = std::atan2(glm::dot(p, e2), glm::dot(p, e1));
      if (!in_a) m_entries.push_back(static_cast<int>(m_nodes.size()));
      m_nodes.push_back({p, in_a ? kExit : kEntry, azimuth, -1, 0.0, poly[i], poly[j], std::abs(m_dots[j]),
                         std::abs(m_dots[i])});
    }
  }
}

void HemisphereClipper::pair_crossings(const glm::dvec3& n) {
  // Pair each exit with the first entry counter-clockwise along the horizon (the horizon arcs inside the
  // polygon start at exits and end at entries). If rounding made that pairing not one-to-one, fall back to
  // Sutherland–Hodgman's pairing with the next entry in polygon order.
  const int num_nodes = static_cast<int>(m_nodes.size());
  m_used.assign(num_nodes, 0);
  bool one_to_one = true;
  for (int x = 0; x < num_nodes; ++x) {
    if (m_nodes[x].kind != kExit) continue;
    int best = -1;
    double best_angle = kTwoPi + 1.0;
    for (int e : m_entries) {
      const double a = crossing_ccw_angle(m_nodes[x], m_nodes[e], n);
      if (a < best_angle) best_angle = a, best = e;
    }
    m_nodes[x].partner = best;
    m_nodes[x].arc = best_angle;
    if (m_used[best]) one_to_one = false;
    m_used[best] = 1;
  }
  if (!one_to_one) {
    for (int x = 0; x < num_nodes; ++x) {
      if (m_nodes[x].kind != kExit) continue;
      int e = (x + 1) % num_nodes;
      while (m_nodes[e].kind != kEntry) e = (e + 1) % num_nodes;
      m_nodes[x].partner = e;
      m_nodes[x].arc = crossing_ccw_angle(m_nodes[x], m_nodes[e], n);
    }
  }
}

std::size_t HemisphereClipper::walk_cycles(const glm::dvec3& n, SphericalPolygonList& out) {
  const int num_nodes = static_cast<int>(m_nodes.size());
  // Walk the cycles: from an entry along the polygon to the next exit, then along the horizon to its entry.
  m_used.assign(num_nodes, 0);
  std::size_t appended = 0;
  for (int start : m_entries) {
    if (m_used[start]) continue;
    SphericalPolygon& piece = out.push();
    int cur = start;
    for (int guard = 0; guard <= num_nodes; ++guard) {
      m_used[cur] = 1;
      int j = cur;
      while (true) {
        piece.push_back(m_nodes[j].p);
        if (m_nodes[j].kind == kExit) break;
        j = (j + 1) % num_nodes;
      }
      const int next = m_nodes[j].partner;
      append_horizon_arc(m_nodes[j].p, n, m_nodes[j].arc, piece);
      if (next == start || m_used[next]) break;
      cur = next;
    }
    if (piece.size() < 3) {
      --out.size;  // a touching point or a sliver of no area
      continue;
    }
    ++appended;
  }
  return appended;
}

SphericalPolygon clip_to_hemisphere(const SphericalPolygon& poly, const glm::dvec3& n) {
  HemisphereClipper clipper;
  SphericalPolygonList pieces;
  const std::size_t count = clipper.clip(poly, n, pieces);
  if (count == 0) return {};
  if (count == 1) return pieces[0];
  // Join the components with bridges along the horizon: each piece starts on the horizon (at an entry, or
  // at a horizon vertex for the whole hemisphere), the bridge goes there counter-clockwise and comes back
  // the same way reversed, so the bridge edges cancel in every boundary integral.
  glm::dvec3 e1, e2;
  horizon_frame(n, e1, e2);
  auto azimuth = [&](const glm::dvec3& p) { return std::atan2(glm::dot(p, e2), glm::dot(p, e1)); };
  SphericalPolygon result = pieces[0];
  const glm::dvec3 s0 = pieces[0][0];
  SphericalPolygon bridge;
  for (std::size_t k = 1; k < count; ++k) {
    const glm::dvec3 sk = pieces[k][0];
    bridge.clear();
    append_horizon_arc(s0, n, ccw_angle(azimuth(s0), azimuth(sk)), bridge);
    result.push_back(s0);
    result.insert(result.end(), bridge.begin(), bridge.end());
    result.insert(result.end(), pieces[k].begin(), pieces[k].end());
    result.push_back(sk);
    result.insert(result.end(), bridge.rbegin(), bridge.rend());
  }
  return result;
}

glm::dvec3 vector_irradiance(const SphericalPolygon& poly) {
  glm::dvec3 sum(0.0);
  const std::size_t n = poly.size();
  for (std::size_t i = 0; i < n; ++i) sum += angle_weighted_edge_normal(poly[i], poly[(i + 1) % n]);
  return 0.5 * sum;
}

double projected_solid_angle(const SphericalPolygon& poly, const glm::dvec3& n) {
  return glm::dot(n, vector_irradiance(poly));
}

glm::dvec3 cosine_weighted_moment(const SphericalPolygon& poly, const glm::dvec3& n) {
  return cosine_weighted_moment(poly, n, solid_angle(poly));
}

glm::dvec3 cosine_weighted_moment(const SphericalPolygon& poly, const glm::dvec3& n,
                                  double poly_solid_angle) {
  const std::size_t count = poly.size();
  if (count < 3) return glm::dvec3(0.0);
  glm::dvec3 edges(0.0);
  for (std::size_t i = 0; i < count; ++i) {
    const glm::dvec3& a = poly[i];
    const glm::dvec3& b = poly[(i + 1) % count];
    const double den = 1.0 + glm::dot(a, b);
    if (den <= 0.0) continue;  // antipodal pair: not a minor arc (precondition), contributes nothing
    edges += (glm::dot(n, glm::cross(a, b)) / den) * (a + b);
  }
  return (poly_solid_angle / 3.0) * n + edges / 3.0;
}

double solid_angle(const SphericalPolygon& poly) { return solid_angle(poly, vector_irradiance(poly)); }

double solid_angle(const SphericalPolygon& poly, const glm::dvec3& irradiance) {
  if (poly.size() < 3) return 0.0;
  // Apex: the mean direction of the polygon (its vector irradiance), which lies inside most polygons met
  // here, so the fan triangles are all positive and small; the result is exact modulo 4 pi for any apex.
  const double len = glm::length(irradiance);
  const glm::dvec3 apex = len > 0.0 ? irradiance / len : poly[0];
  // Sum of the fan's 2 atan2(num_i, den_i), modulo 4 pi, with one atan2: the argument of the product of the
  // complex numbers den_i + i num_i is the sum of the atan2s modulo 2 pi. Each factor has modulus at most 4,
  // so the product is rescaled by a power of two (exact, no rounding) only when it leaves [2^-256, 2^256].
  double re = 1.0, im = 0.0;
  const std::size_t n = poly.size();
  for (std::size_t i = 0; i < n; ++i) {
    const glm::dvec3& b = poly[i];
    const glm::dvec3& c = poly[(i + 1) % n];
    const double num = glm::dot(apex, glm::cross(b, c));
    const double den = 1.0 + glm::dot(apex, b) + glm::dot(b, c) + glm::dot(c, apex);
    if (num == 0.0 && den <= 0.0) continue;  // degenerate (an antipodal pair): measure zero
    const double r = re * den - im * num, m = re * num + im * den;
    if (r == 0.0 && m == 0.0) continue;  // a zero factor: no argument
    re = r;
    im = m;
    const double size = std::max(std::abs(re), std::abs(im));
    if (size > 0x1p256 || size < 0x1p-256) {
      int exponent = 0;
      std::frexp(size, &exponent);
      re = std::ldexp(re, -exponent);
      im = std::ldexp(im, -exponent);
    }
  }
  double omega = 2.0 * std::atan2(im, re);  // in (-2 pi, 2 pi]
  if (omega < 0.0) omega += kFourPi;
  // A zero-area polygon (a sliver, or bridges only) can sum to -1e-17: report it as 0, not 4 pi.
  if (omega > kFourPi * (1.0 - 1e-13)) omega -= kFourPi;
  return std::max(0.0, omega);
}

BoundingCap bounding_cap(const SphericalPolygon& poly, double poly_solid_angle) {
  // A cap narrower than a hemisphere is convex: it holds the minor arcs between its points, so the whole
  // boundary, and the winding count is constant (0 for the polygon about its small side) beyond it. The
  // polygon is about its small side when its solid angle is at most the cap's, 2 pi (1 - min_cos); 1e-3
  // keeps the cap clear of a hemisphere, where that count would be decided by rounding (a fan sum near 2 pi).
  constexpr double kMinCos = 1e-3;
  glm::dvec3 sum(0.0);
  for (const glm::dvec3& p : poly) sum += p;
  const double length = glm::length(sum);
  if (poly.size() < 3 || !(length > 0)) return {};
  BoundingCap cap{sum / length, 1.0};
  for (const glm::dvec3& p : poly) cap.min_cos = std::min(cap.min_cos, glm::dot(p, cap.centre));
  if (!(cap.min_cos > kMinCos) || !(poly_solid_angle <= kTwoPi * (1.0 - cap.min_cos) + 1e-9)) return {};
  return cap;
}

bool contains_direction(const SphericalPolygon& poly, const glm::dvec3& w) {
  return contains_direction(poly, w, solid_angle(poly));
}

bool contains_direction(const SphericalPolygon& poly, const glm::dvec3& w, double poly_solid_angle) {
  if (poly.size() < 3) return false;
  const double winding = (poly_solid_angle - fan_solid_angle(poly, -w)) / kFourPi;
  return std::lround(winding) > 0;
}

}  // namespace pleat
