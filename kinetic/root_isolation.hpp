// Exact event times of the kinetic layer: the first root of a certificate polynomial after a given time,
// and exact comparison of such times (DESIGN.md §3, "Root isolation" and "Events").
//
// A certificate holds while its polynomial P keeps the strict sign it has just after the current time t0.
// Its **event** is the first zero of P in the half-open interval (t0, 1]: every zero counts, whatever its
// multiplicity. A zero of an orientation certificate means three slice vertices are collinear, which is
// itself a state the kinetic structure must agree on with a static recompute at that instant (a hull vertex
// is flat, a funnel straightens, a triangle is degenerate), and a frame time may fall exactly on it; so a
// touching (even-multiplicity) zero is reported too. The caller learns whether the sign really changes from
// sign_before / sign_after (exact); a touch usually needs no repair. Two further rules:
//   * P identically zero (e.g. three slice vertices of a flat sheet, collinear for all t) has no event.
//   * Zeros at t0 itself are not events of (t0, 1]. A certificate that is zero at t0 and leaves with the
//     "wrong" sign (e.g. a vertex on the plane at t = 0, above by the slicer's symbolic perturbation,
//     moving down) is detected by the caller comparing its recorded sign with sign_after(P, t0).
//
// Method (cheapest first):
//   (a) filter: the interval homogeneous-Bernstein coefficients of P on [0, 1] all strictly of one sign
//       prove "no zero in [0, 1]" (the common case: ~6 ns on a built certificate, no allocation);
//   (b) interval de Casteljau subdivision (depth <= 6, no allocation): sub-intervals after t0 are proven
//       root-free, or the first one with exactly one certain sign variation holds exactly one simple root;
//   (c) exact: squarefree part of the rational polynomial, exact Bernstein subdivision with Descartes' rule
//       of signs (0 variations: no root, 1: one root), exact deflation of rational roots hit by a midpoint.
// Every algebraic RootTime is then narrowed to a tight isolating interval (a guess by double bisection, a
// bracket around it verified by interval evaluation, exact evaluation when that cannot decide), so most
// comparisons are decided by two double comparisons. A root found in stage (b) keeps only the certificate
// and builds its exact polynomial on first need (a tie, a sign the intervals cannot decide, or a narrowing
// that intervals cannot take below 1e-11): an event then costs ~6 us instead of ~50 us (an orientation
// certificate, bench/root_isolation_bench.cpp). Comparing two times with disjoint enclosures: ~2 ns; an exact
// tie (gcd of the two polynomials): ~4 us.
//
// Exactness: every decision rests on interval arithmetic with outward rounding or on Gmpq arithmetic, never
// on an epsilon. Equal event times from different certificates compare equal (gcd of their polynomials).
#pragma once

#include <memory>
#include <optional>
#include <ostream>

#include "kinetic/certificate_polynomial.hpp"

namespace pleat::kinetic {

/// An exact real number in [0, 1] used as an event time: a double, a rational, or the unique (simple) root of
/// a rational polynomial in an open isolating interval with rational endpoints. Copies are cheap (shared).
class RootTime {
 public:
  RootTime() = default;  ///< t = 0
  static RootTime zero() { return RootTime(); }
  static RootTime one() { return RootTime(1.0); }
  explicit RootTime(double t);  ///< precondition: finite
  static RootTime rational(const Rational& t);
  /// The unique root of p in (lo, hi). Preconditions (checked): lo < hi, p(lo) and p(hi) nonzero with
  /// opposite signs, and p has exactly one root (a simple one) in (lo, hi). Narrows the interval.
  static RootTime algebraic(const ExactPolynomial& p, const Rational& lo, const Rational& hi);

  bool is_rational() const;
  /// Precondition: is_rational().
  Rational rational_value() const;
  /// A double within the enclosure: a few ulps from the value when the exact polynomial was built; when an
  /// event was isolated by intervals alone (its exact polynomial is built lazily, on the first tie or
  /// ambiguous sign), the enclosure is as narrow as interval evaluation can certify, at most 1e-11 wide
  /// (exact arithmetic finishes the narrowing where intervals stop earlier).
  double approximate() const;
  /// Doubles enclosing the exact value: lower_bound() <= value <= upper_bound().
  double lower_bound() const { return m_lo; }
  double upper_bound() const { return m_hi; }
  /// For an algebraic time: its polynomial and its isolating interval (exact values). Precondition:
  /// !is_rational().
  const ExactPolynomial& polynomial() const;
  const Rational& isolating_lower() const;
  const Rational& isolating_upper() const;

  /// Exact three-way comparison: -1, 0 (the same real number), 1.
  friend int compare(const RootTime& a, const RootTime& b);
  friend bool operator<(const RootTime& a, const RootTime& b) { return compare(a, b) < 0; }
  friend bool operator>(const RootTime& a, const RootTime& b) { return compare(a, b) > 0; }
  friend bool operator<=(const RootTime& a, const RootTime& b) { return compare(a, b) <= 0; }
  friend bool operator>=(const RootTime& a, const RootTime& b) { return compare(a, b) >= 0; }
  friend bool operator==(const RootTime& a, const RootTime& b) { return compare(a, b) == 0; }
  friend std::ostream& operator<<(std::ostream& out, const RootTime& t);

  struct Exact;  ///< implementation detail (a rational, or polynomial + isolating interval)

 private:
  double m_lo = 0.0, m_hi = 0.0;         ///< enclosure; when m_exact is null the value is m_lo == m_hi
  std::shared_ptr<const Exact> m_exact;  ///< null when the value is the double m_lo
  friend struct RootTimeAccess;
};

/// Which stage of first_root_after decided (for tests and statistics).
enum class IsolationStage { filter, subdivision, exact };

/// Stage (a) alone: true when the enclosure proves P has no zero on [0, 1]. No allocation, no exact work.
bool certainly_no_root(const CertificatePolynomial& p);

/// The first zero of P in (t0, 1], every multiplicity counted (see the header comment), or nullopt when
/// there is none or P is identically zero. Stages (a) to (c); `stage`, if given, says which one decided.
/// Allocation-free when (a) or a root-free (b) decides.
std::optional<RootTime> first_root_after(const CertificatePolynomial& p, const RootTime& t0,
                                         IsolationStage* stage = nullptr);
/// The same on an exact polynomial (stage (c) only).
std::optional<RootTime> first_root_after(const ExactPolynomial& p, const RootTime& t0);

/// The sign of P at t when interval arithmetic certifies it (P's enclosure over t's enclosure excludes 0; P
/// then has that sign just after t and just before it too); 0 when it cannot. No allocation, no exact work.
int certain_sign_at(const CertificatePolynomial& p, const RootTime& t);

/// Exact sign of P at t (0 when t is a root).
int sign_at(const ExactPolynomial& p, const RootTime& t);
/// Exact sign of P on (t, t + eps) and on (t - eps, t) for small enough eps (0 only for the zero polynomial).
/// At a root, sign_before != sign_after exactly when the root has odd multiplicity (the certificate flips).
int sign_after(const ExactPolynomial& p, const RootTime& t);
int sign_before(const ExactPolynomial& p, const RootTime& t);

}  // namespace pleat::kinetic
