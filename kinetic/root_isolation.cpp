#include "kinetic/root_isolation.hpp"

#include <CGAL/FPU.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <utility>

#include "static_core/assert.hpp"

namespace pleat::kinetic {

/// A rational value, or the unique simple root of p in (lo, hi) with p(lo) of sign `sign_lo`. p is either
/// given, or built on first use from `source` (a certificate: most event times are ordered by their double
/// enclosures alone and never need the exact polynomial).
struct RootTime::Exact {
  bool rational = false;
  Rational value;
  std::vector<Interval> p_interval;  ///< enclosures of p's monomial coefficients (filtered evaluation)
  Rational lo, hi;
  int sign_lo = 0;
  std::optional<CertificatePolynomial> source;

  const ExactPolynomial& poly() const {
    std::call_once(m_once, [this] {
      if (source) m_p = source->exact();
    });
    return m_p;
  }
  void set_poly(ExactPolynomial p) { m_p = std::move(p); }

 private:
  mutable std::once_flag m_once;
  mutable ExactPolynomial m_p;
};

struct RootTimeAccess {
  static RootTime make(std::shared_ptr<const RootTime::Exact> e, double lo, double hi) {
    RootTime t;
    t.m_exact = std::move(e);
    t.m_lo = lo;
    t.m_hi = hi;
    return t;
  }
  static const RootTime::Exact* exact(const RootTime& t) { return t.m_exact.get(); }
};

namespace {

constexpr int kSubdivisionDepth = 6;
/// A lazy root's enclosure wider than this after interval narrowing is narrowed with exact arithmetic.
constexpr double kLazyWidth = 1e-11;

int sign_of(const Rational& r) { return static_cast<int>(CGAL::sign(r)); }

std::vector<Interval> interval_coefficients(const ExactPolynomial& p) {
  std::vector<Interval> out;
  out.reserve(p.coefficients().size());
  for (const Rational& c : p.coefficients()) out.emplace_back(CGAL::to_interval(c));
  return out;
}

/// Horner in interval arithmetic; the caller holds CGAL::Protect_FPU_rounding<true>.
Interval horner(const std::vector<Interval>& c, const Interval& x) {
  Interval r(0);
  for (auto it = c.rbegin(); it != c.rend(); ++it) r = r * x + *it;
  return r;
}

/// Sign of the enclosure (0: undecided), under upward rounding.
int certain_sign(const Interval& v) { return v.inf() > 0 ? 1 : (v.sup() < 0 ? -1 : 0); }

constexpr int kUndecided = 2;

/// Exact sign of e's polynomial at the double x: interval Horner first, then Gmpq, unless `allow_exact` is
/// false (then kUndecided when the intervals cannot decide).
int filtered_sign(const RootTime::Exact& e, double x, bool allow_exact = true) {
  {
    CGAL::Protect_FPU_rounding<true> upward;
    const int s = certain_sign(horner(e.p_interval, Interval(x)));
    if (s != 0) return s;
  }
  return allow_exact ? e.poly().sign_at(Rational(x)) : kUndecided;
}

/// Narrows e's isolating interval to a few ulps: a guess from plain double bisection (untrusted), then a
/// bracket around it whose signs are verified exactly (filtered), widened by 8x until it holds. Every tested
/// point shrinks the interval on its side, so the result is always a valid isolating interval. Returns the
/// root when a tested double is exactly a root. For a lazy time (exact polynomial not built), only interval
/// evaluation is used, and narrowing stops where it cannot decide (the enclosure stays a little wider).
std::optional<double> narrow(RootTime::Exact& e) {
  const bool allow_exact = !e.source.has_value();
  std::vector<double> pd;
  for (const Interval& c : e.p_interval) pd.push_back(c.inf() + (c.sup() - c.inf()) / 2);
  const auto eval = [&](double x) {
    double r = 0.0;
    for (auto it = pd.rbegin(); it != pd.rend(); ++it) r = r * x + *it;
    return r;
  };
  double a = CGAL::to_interval(e.lo).first, b = CGAL::to_interval(e.hi).second;
  for (int i = 0; i < 200; ++i) {
    const double m = a + (b - a) / 2;
    if (!(m > a && m < b)) break;
    const double v = eval(m);
    if (v == 0.0) {
      a = b = m;
      break;
    }
    if ((v > 0) == (e.sign_lo > 0))
      a = m;
    else
      b = m;
  }
  const double guess = a + (b - a) / 2;
  double delta = std::max(std::nextafter(std::abs(guess), INFINITY) - std::abs(guess),
                          std::numeric_limits<double>::denorm_min());
  // Tests the double x strictly inside (lo, hi); returns false when x was outside or is a root (then *root).
  const auto test = [&](double x, bool& moved, std::optional<double>& root) {
    moved = false;
    const Rational q(x);
    if (!(q > e.lo && q < e.hi)) return;
    const int s = filtered_sign(e, x, allow_exact);
    if (s == kUndecided) return;
    if (s == 0) {
      root = x;
      return;
    }
    if (s == e.sign_lo)
      e.lo = q;
    else
      e.hi = q;
    moved = true;
  };
  for (int k = 0; k < 30; ++k, delta *= 8) {
    std::optional<double> root;
    bool left_moved = false, right_moved = false;
    test(guess - delta, left_moved, root);
    if (root) return root;
    test(guess + delta, right_moved, root);
    if (root) return root;
    const bool left_ok = CGAL::to_interval(e.lo).first >= guess - delta;
    const bool right_ok = CGAL::to_interval(e.hi).second <= guess + delta;
    if (left_ok && right_ok) break;  // (lo, hi) is within [guess - delta, guess + delta]
  }
  // Finish by verified bisection at doubles until no double lies strictly inside the bracket.
  for (int i = 0; i < 64; ++i) {
    const double lo_d = CGAL::to_interval(e.lo).first, hi_d = CGAL::to_interval(e.hi).second;
    const double m = lo_d + (hi_d - lo_d) / 2;
    std::optional<double> root;
    bool moved = false;
    test(m, moved, root);
    if (root) return root;
    if (!moved) break;
  }
  return std::nullopt;
}

RootTime from_exact(std::shared_ptr<RootTime::Exact> e) {
  const double lo = CGAL::to_interval(e->rational ? e->value : e->lo).first;
  const double hi = CGAL::to_interval(e->rational ? e->value : e->hi).second;
  return RootTimeAccess::make(std::move(e), lo, hi);
}

/// Monomial coefficient enclosures of sum_k h[k] t^k (1 - t)^(n - k); under upward rounding.
std::vector<Interval> monomial_enclosure(const CertificatePolynomial& c) {
  static constexpr long kC[6][6] = {{1, 0, 0, 0, 0, 0}, {1, 1, 0, 0, 0, 0}, {1, 2, 1, 0, 0, 0},
                                    {1, 3, 3, 1, 0, 0}, {1, 4, 6, 4, 1, 0}, {1, 5, 10, 10, 5, 1}};
  const int n = c.degree();
  std::vector<Interval> a(n + 1, Interval(0));
  for (int k = 0; k <= n; ++k)
    for (int i = 0; i <= n - k; ++i) {
      const Interval term = c.enclosure()[k] * Interval(static_cast<double>(kC[n - k][i]));
      a[k + i] = i % 2 == 0 ? a[k + i] + term : a[k + i] - term;
    }
  return a;
}

/// The root of certificate c in (a, b), certified simple and unique by interval Bernstein coefficients
/// (c(a) of sign sign_a, c(b) of the other); the exact polynomial is built only if ever needed.
RootTime lazy_root(const CertificatePolynomial& c, double a, double b, int sign_a) {
  auto e = std::make_shared<RootTime::Exact>();
  {
    CGAL::Protect_FPU_rounding<true> upward;
    e->p_interval = monomial_enclosure(c);
  }
  e->source = c;
  e->lo = Rational(a);
  e->hi = Rational(b);
  e->sign_lo = sign_a;
  if (const std::optional<double> root = narrow(*e)) return RootTime(*root);
  // Intervals could not narrow it well (tiny coefficients, clustered roots): finish with the exact
  // polynomial, so that every time's enclosure is narrow (its approximate() value is used for geometric
  // choices).
  if (CGAL::to_double(e->hi - e->lo) > kLazyWidth) {
    e->poly();
    e->source.reset();
    if (const std::optional<double> root = narrow(*e)) return RootTime(*root);
  }
  return from_exact(std::move(e));
}

/// An exact-arithmetic view of a time: a rational, or a bracket that bisection refines (local copies).
struct Bracket {
  bool rational = false;
  Rational value;
  const RootTime::Exact* e = nullptr;
  Rational lo, hi;

  explicit Bracket(const RootTime& t) {
    const RootTime::Exact* x = RootTimeAccess::exact(t);
    if (x == nullptr || x->rational) {
      rational = true;
      value = x == nullptr ? Rational(t.lower_bound()) : x->value;
    } else {
      e = x;
      lo = x->lo;
      hi = x->hi;
    }
  }
  /// One exact bisection step.
  void refine() {
    const Rational m = (lo + hi) / Rational(2);
    const int s = e->poly().sign_at(m);
    if (s == 0) {
      rational = true;
      value = m;
    } else if (s == e->sign_lo) {
      lo = m;
    } else {
      hi = m;
    }
  }
};

/// compare(alpha, r) for an algebraic bracket and a rational.
int compare_bracket_rational(const Bracket& a, const Rational& r) {
  if (r <= a.lo) return 1;
  if (r >= a.hi) return -1;
  const int s = a.e->poly().sign_at(r);
  if (s == 0) return 0;
  return s == a.e->sign_lo ? 1 : -1;  // same sign as at lo: the root lies in (r, hi)
}

int compare_brackets(Bracket a, Bracket b) {
  if (a.rational && b.rational) return static_cast<int>(CGAL::compare(a.value, b.value));
  if (b.rational) return compare_bracket_rational(a, b.value);
  if (a.rational) return -compare_bracket_rational(b, a.value);
  if (a.hi <= b.lo) return -1;
  if (b.hi <= a.lo) return 1;
  // Overlapping isolating intervals: equal iff the gcd vanishes in the overlap (it has at most one root
  // there, and none at its ends since those are ends of isolating intervals).
  const ExactPolynomial g = ExactPolynomial::gcd(a.e->poly(), b.e->poly());
  if (g.degree() >= 1) {
    const Rational lo = std::max(a.lo, b.lo), hi = std::min(a.hi, b.hi);
    if (g.sign_at(lo) * g.sign_at(hi) < 0) return 0;
  }
  // Distinct: bisect until the intervals separate (terminates because the roots differ).
  for (;;) {
    if (a.rational || b.rational) return compare_brackets(a, b);
    if (a.hi <= b.lo) return -1;
    if (b.hi <= a.lo) return 1;
    if (a.hi - a.lo >= b.hi - b.lo)
      a.refine();
    else
      b.refine();
  }
}

int variations(const std::vector<Rational>& c) {
  int v = 0, last = 0;
  for (const Rational& x : c) {
    const int s = sign_of(x);
    if (s == 0) continue;
    if (last != 0 && s != last) ++v;
    last = s;
  }
  return v;
}

/// Exact de Casteljau split at the midpoint.
void split(const std::vector<Rational>& c, std::vector<Rational>& left, std::vector<Rational>& right) {
  const std::size_t n = c.size() - 1;
  std::vector<Rational> tmp = c;
  left.assign(n + 1, Rational(0));
  right.assign(n + 1, Rational(0));
  left[0] = tmp[0];
  right[n] = tmp[n];
  const Rational half(1, 2);
  for (std::size_t r = 1; r <= n; ++r) {
    for (std::size_t i = 0; i + r <= n; ++i) tmp[i] = (tmp[i] + tmp[i + 1]) * half;
    left[r] = tmp[0];
    right[n - r] = tmp[n - r];
  }
}

/// The root of a squarefree s in (a, b) where s(a), s(b) != 0 and exactly one root lies in between.
RootTime make_root(const ExactPolynomial& s, const Rational& a, const Rational& b) {
  if (s.degree() == 1) return RootTime::rational(-s.coefficient(0) / s.coefficient(1));
  return RootTime::algebraic(s, a, b);
}

/// Left-first exact search of the squarefree s on (a, b) (bern: its Bernstein coefficients there; s(a),
/// s(b) != 0); stops at the first root after t0.
bool search(const ExactPolynomial& s, const Rational& a, const Rational& b, const std::vector<Rational>& bern,
            const RootTime& t0, std::optional<RootTime>& found) {
  if (b <= Rational(t0.lower_bound())) return false;  // every root here is < t0
  const int v = variations(bern);
  if (v == 0) return false;
  if (v == 1) {
    RootTime r = make_root(s, a, b);
    if (compare(r, t0) > 0) {
      found = std::move(r);
      return true;
    }
    return false;
  }
  const Rational m = (a + b) / Rational(2);
  std::vector<Rational> left, right;
  split(bern, left, right);
  if (!CGAL::is_zero(left.back()))
    return search(s, a, m, left, t0, found) || search(s, m, b, right, t0, found);
  // A rational root at the midpoint: deflate, so that no interval end is ever a root.
  const ExactPolynomial d = s.deflate(m);
  if (d.degree() >= 1 && search(d, a, m, d.bernstein(a, m), t0, found)) return true;
  RootTime rm = RootTime::rational(m);
  if (compare(rm, t0) > 0) {
    found = std::move(rm);
    return true;
  }
  return d.degree() >= 1 && search(d, m, b, d.bernstein(m, b), t0, found);
}

enum class Subdivision { no_root, found, unknown };

/// Stage (b): interval de Casteljau on [0, 1], left first, depth-limited, no allocation.
Subdivision subdivide(const CertificatePolynomial& p, double t0_lo, double t0_hi, double& found_a,
                      double& found_b, int& found_sign) {
  struct Piece {
    double a, b;
    int depth;
    std::array<Interval, kMaxCertificateDegree + 1> c;
  };
  static constexpr long kBinomial5[6][6] = {{1, 0, 0, 0, 0, 0}, {1, 1, 0, 0, 0, 0}, {1, 2, 1, 0, 0, 0},
                                            {1, 3, 3, 1, 0, 0}, {1, 4, 6, 4, 1, 0}, {1, 5, 10, 10, 5, 1}};
  const int n = p.degree();
  CGAL::Protect_FPU_rounding<true> upward;
  std::array<Piece, 2 * kSubdivisionDepth + 4> stack;
  int top = 0;
  Piece& root = stack[top++];
  root.a = 0.0;
  root.b = 1.0;
  root.depth = 0;
  for (int k = 0; k <= n; ++k) root.c[k] = p.enclosure()[k] / Interval(static_cast<double>(kBinomial5[n][k]));
  while (top > 0) {
    const Piece piece = stack[--top];
    if (piece.b <= t0_lo) continue;
    bool all_pos = true, all_neg = true, all_certain = true;
    int v = 0, last = 0;
    for (int k = 0; k <= n; ++k) {
      const int s = certain_sign(piece.c[k]);
      all_pos = all_pos && s > 0;
      all_neg = all_neg && s < 0;
      if (s == 0) {
        all_certain = false;
        continue;
      }
      if (last != 0 && s != last) ++v;
      last = s;
    }
    if (all_pos || all_neg) continue;
    if (piece.a > t0_hi && all_certain && v == 1) {
      found_a = piece.a;
      found_b = piece.b;
      found_sign = certain_sign(piece.c[0]);
      return Subdivision::found;
    }
    if (piece.depth >= kSubdivisionDepth) return Subdivision::unknown;
    const double m = piece.a + (piece.b - piece.a) * 0.5;  // exact: dyadic ends of depth <= 6
    Piece left{piece.a, m, piece.depth + 1, {}}, right{m, piece.b, piece.depth + 1, {}};
    std::array<Interval, kMaxCertificateDegree + 1> tmp = piece.c;
    left.c[0] = tmp[0];
    right.c[n] = tmp[n];
    for (int r = 1; r <= n; ++r) {
      for (int i = 0; i + r <= n; ++i) tmp[i] = (tmp[i] + tmp[i + 1]) * Interval(0.5);
      left.c[r] = tmp[0];
      right.c[n - r] = tmp[n - r];
    }
    stack[top++] = right;
    stack[top++] = left;
  }
  return Subdivision::no_root;
}

}  // namespace

// ---- RootTime -------------------------------------------------------------------------------------------

RootTime::RootTime(double t) : m_lo(t), m_hi(t) {
  PLEAT_ASSERT(std::isfinite(t), "RootTime of a non-finite double");
}

RootTime RootTime::rational(const Rational& t) {
  const std::pair<double, double> iv = CGAL::to_interval(t);
  if (iv.first == iv.second) return RootTime(iv.first);
  auto e = std::make_shared<Exact>();
  e->rational = true;
  e->value = t;
  return from_exact(std::move(e));
}

RootTime RootTime::algebraic(const ExactPolynomial& p, const Rational& lo, const Rational& hi) {
  PLEAT_ASSERT(lo < hi, "empty isolating interval");
  const int s_lo = p.sign_at(lo);
  PLEAT_ASSERT(s_lo * p.sign_at(hi) < 0, "no sign change over the isolating interval");
  if (p.degree() == 1) return rational(-p.coefficient(0) / p.coefficient(1));
  auto e = std::make_shared<Exact>();
  e->set_poly(p);
  e->p_interval = interval_coefficients(p);
  e->lo = lo;
  e->hi = hi;
  e->sign_lo = s_lo;
  if (const std::optional<double> root = narrow(*e)) return RootTime(*root);
  return from_exact(std::move(e));
}

bool RootTime::is_rational() const { return m_exact == nullptr || m_exact->rational; }

Rational RootTime::rational_value() const {
  PLEAT_ASSERT(is_rational(), "rational_value() of an algebraic time");
  return m_exact == nullptr ? Rational(m_lo) : m_exact->value;
}

double RootTime::approximate() const {
  if (m_exact == nullptr) return m_lo;
  if (m_exact->rational) return CGAL::to_double(m_exact->value);
  return m_lo + (m_hi - m_lo) / 2;
}

const ExactPolynomial& RootTime::polynomial() const {
  PLEAT_ASSERT(!is_rational(), "polynomial() of a rational time");
  return m_exact->poly();
}
const Rational& RootTime::isolating_lower() const {
  PLEAT_ASSERT(!is_rational(), "isolating_lower() of a rational time");
  return m_exact->lo;
}
const Rational& RootTime::isolating_upper() const {
  PLEAT_ASSERT(!is_rational(), "isolating_upper() of a rational time");
  return m_exact->hi;
}

int compare(const RootTime& a, const RootTime& b) {
  if (a.m_hi < b.m_lo) return -1;
  if (b.m_hi < a.m_lo) return 1;
  if (a.m_exact == nullptr && b.m_exact == nullptr) return a.m_lo < b.m_lo ? -1 : (b.m_lo < a.m_lo ? 1 : 0);
  return compare_brackets(Bracket(a), Bracket(b));
}

std::ostream& operator<<(std::ostream& out, const RootTime& t) {
  out << "t~" << t.approximate();
  if (t.m_exact == nullptr) return out << " (double)";
  if (t.m_exact->rational) return out << " (rational " << t.m_exact->value << ")";
  out << " (root of degree " << t.m_exact->poly().degree() << " in [" << t.m_lo << ", " << t.m_hi << "])";
  return out;
}

// ---- Signs at exact times -------------------------------------------------------------------------------

int sign_at(const ExactPolynomial& p, const RootTime& t) {
  if (p.is_zero()) return 0;
  const RootTime::Exact* e = RootTimeAccess::exact(t);
  if (e == nullptr) return p.sign_at(Rational(t.lower_bound()));
  if (e->rational) return p.sign_at(e->value);
  {
    const std::vector<Interval> pi = interval_coefficients(p);
    CGAL::Protect_FPU_rounding<true> upward;
    const int s = certain_sign(horner(pi, Interval(t.lower_bound(), t.upper_bound())));
    if (s != 0) return s;
  }
  // t is a root of p iff gcd(p, e.p) changes sign over the isolating interval (its ends are no roots).
  const ExactPolynomial g = ExactPolynomial::gcd(p, e->poly());
  if (g.degree() >= 1 && g.sign_at(e->lo) * g.sign_at(e->hi) < 0) return 0;
  // p(t) != 0: refine until p's Bernstein coefficients on the bracket share one strict sign.
  Bracket b(t);
  for (;;) {
    if (b.rational) return p.sign_at(b.value);
    const std::vector<Rational> bern = p.bernstein(b.lo, b.hi);
    const bool pos = std::all_of(bern.begin(), bern.end(), [](const Rational& x) { return sign_of(x) > 0; });
    const bool neg = std::all_of(bern.begin(), bern.end(), [](const Rational& x) { return sign_of(x) < 0; });
    if (pos) return 1;
    if (neg) return -1;
    b.refine();
  }
}

int certain_sign_at(const CertificatePolynomial& p, const RootTime& t) {
  if (p.degree() < 0) return 0;
  CGAL::Protect_FPU_rounding<true> upward;
  // Homogeneous Bernstein form: sum_k H_k t^k (1 - t)^(n - k), evaluated on t's enclosure.
  const Interval x(t.lower_bound(), t.upper_bound()), y = Interval(1) - x;
  Interval sum(0);
  for (int k = 0; k <= p.degree(); ++k) {
    Interval term = p.enclosure()[k];
    for (int i = 0; i < k; ++i) term = term * x;
    for (int i = k; i < p.degree(); ++i) term = term * y;
    sum = sum + term;
  }
  return certain_sign(sum);
}

int sign_after(const ExactPolynomial& p, const RootTime& t) {
  if (p.is_zero()) return 0;
  const int s = sign_at(p, t);
  return s != 0 ? s : sign_after(p.derivative(), t);
}

int sign_before(const ExactPolynomial& p, const RootTime& t) {
  if (p.is_zero()) return 0;
  const int s = sign_at(p, t);
  return s != 0 ? s : -sign_before(p.derivative(), t);
}

// ---- Isolation ------------------------------------------------------------------------------------------

bool certainly_no_root(const CertificatePolynomial& p) {
  const auto& h = p.enclosure();
  const int n = p.degree();
  if (n < 0) return false;
  if (h[0].inf() > 0) {
    for (int k = 1; k <= n; ++k)
      if (!(h[k].inf() > 0)) return false;
    return true;
  }
  if (h[0].sup() < 0) {
    for (int k = 1; k <= n; ++k)
      if (!(h[k].sup() < 0)) return false;
    return true;
  }
  return false;
}

std::optional<RootTime> first_root_after(const CertificatePolynomial& p, const RootTime& t0,
                                         IsolationStage* stage) {
  if (stage) *stage = IsolationStage::filter;
  PLEAT_ASSERT(p.degree() >= 0, "first_root_after on an empty certificate");
  if (p.degree() < 0) return std::nullopt;
  if (certainly_no_root(p)) return std::nullopt;
  if (t0.lower_bound() >= 1.0 && compare(t0, RootTime::one()) >= 0) return std::nullopt;
  if (stage) *stage = IsolationStage::subdivision;
  double a = 0.0, b = 0.0;
  int sign_a = 0;
  switch (subdivide(p, t0.lower_bound(), t0.upper_bound(), a, b, sign_a)) {
    case Subdivision::no_root:
      return std::nullopt;
    case Subdivision::found:
      if (p.degree() == 1) return make_root(p.exact(), Rational(a), Rational(b));  // rational, cheap
      return lazy_root(p, a, b, sign_a);
    case Subdivision::unknown:
      break;
  }
  if (stage) *stage = IsolationStage::exact;
  return first_root_after(p.exact(), t0);
}

std::optional<RootTime> first_root_after(const ExactPolynomial& p, const RootTime& t0) {
  PLEAT_ASSERT(compare(t0, RootTime::zero()) >= 0, "first_root_after before t = 0");
  if (p.is_zero() || compare(t0, RootTime::one()) >= 0) return std::nullopt;
  ExactPolynomial s = p.squarefree_part();
  if (s.degree() <= 0) return std::nullopt;
  const Rational one(1);
  const Rational start = t0.is_rational() ? t0.rational_value() : t0.isolating_lower();
  if (s.sign_at(start) == 0) s = s.deflate(start);
  bool root_at_one = false;
  if (s.sign_at(one) == 0) {
    root_at_one = true;
    s = s.deflate(one);
  }
  std::optional<RootTime> found;
  if (s.degree() >= 1 && search(s, start, one, s.bernstein(start, one), t0, found)) return found;
  if (root_at_one) return RootTime::one();
  return std::nullopt;
}

}  // namespace pleat::kinetic
