#include "kinetic/certificate_polynomial.hpp"

#include <CGAL/FPU.h>
#include <CGAL/Gmpzf.h>

#include <stdexcept>
#include <utility>

#include "static_core/assert.hpp"

namespace pleat::kinetic {
namespace {

constexpr long kBinomial[kMaxCertificateDegree + 2][kMaxCertificateDegree + 2] = {
    {1, 0, 0, 0, 0, 0, 0}, {1, 1, 0, 0, 0, 0, 0},   {1, 2, 1, 0, 0, 0, 0},   {1, 3, 3, 1, 0, 0, 0},
    {1, 4, 6, 4, 1, 0, 0}, {1, 5, 10, 10, 5, 1, 0}, {1, 6, 15, 20, 15, 6, 1}};

long binomial(int n, int k) {
  PLEAT_ASSERT(n >= 0 && n <= kMaxCertificateDegree + 1 && k >= 0 && k <= n, "binomial out of table");
  return kBinomial[n][k];
}

/// The exact coefficients are built in CGAL::Gmpzf (GMP mantissa times a power of two): the expression only
/// adds, subtracts and multiplies doubles, so it is exact there and needs no gcd per operation; converted to
/// Gmpq once at the end.
using Dyadic = CGAL::Gmpzf;

Rational to_rational(const Dyadic& x) {
  mpq_t q;
  mpq_init(q);
  mpq_set_z(q, x.man());
  if (x.exp() >= 0)
    mpq_mul_2exp(q, q, static_cast<mp_bitcnt_t>(x.exp()));
  else
    mpq_div_2exp(q, q, static_cast<mp_bitcnt_t>(-x.exp()));
  Rational r(q);
  mpq_clear(q);
  return r;
}

/// Monomial coefficients of sum_k h[k] t^k (1 - t)^(n - k), in the ring type T.
template <class T, std::size_t N>
std::vector<Rational> monomial_from_homogeneous(const std::array<T, N>& h) {
  const int n = static_cast<int>(N) - 1;
  std::array<T, N> c;
  for (auto& x : c) x = T(0);
  for (int k = 0; k <= n; ++k)
    for (int i = 0; i <= n - k; ++i) {
      const T term = h[k] * T(static_cast<int>(binomial(n - k, i)));
      if (i % 2 == 0)
        c[k + i] += term;
      else
        c[k + i] -= term;
    }
  std::vector<Rational> out;
  for (const T& x : c) out.push_back(to_rational(x));
  return out;
}

}  // namespace

// ---- ExactPolynomial ------------------------------------------------------------------------------------

ExactPolynomial::ExactPolynomial(std::vector<Rational> coefficients) : m_c(std::move(coefficients)) {
  normalize();
}

void ExactPolynomial::normalize() {
  while (!m_c.empty() && CGAL::is_zero(m_c.back())) m_c.pop_back();
}

ExactPolynomial ExactPolynomial::from_roots(const std::vector<Rational>& roots, const Rational& c) {
  ExactPolynomial p(std::vector<Rational>{c});
  for (const Rational& r : roots) p = p * ExactPolynomial(std::vector<Rational>{-r, Rational(1)});
  return p;
}

ExactPolynomial ExactPolynomial::from_homogeneous_bernstein(const std::vector<Rational>& h) {
  const int n = static_cast<int>(h.size()) - 1;
  std::vector<Rational> c(h.size(), Rational(0));
  for (int k = 0; k <= n; ++k) {
    if (CGAL::is_zero(h[k])) continue;
    // t^k (1 - t)^(n - k) = sum_i C(n - k, i) (-1)^i t^(k + i)
    for (int i = 0; i <= n - k; ++i) {
      const Rational term = h[k] * Rational(binomial(n - k, i));
      if (i % 2 == 0)
        c[k + i] += term;
      else
        c[k + i] -= term;
    }
  }
  return ExactPolynomial(std::move(c));
}

Rational ExactPolynomial::coefficient(int i) const {
  return i >= 0 && i < static_cast<int>(m_c.size()) ? m_c[i] : Rational(0);
}

Rational ExactPolynomial::evaluate(const Rational& t) const {
  Rational r(0);
  for (auto it = m_c.rbegin(); it != m_c.rend(); ++it) r = r * t + *it;
  return r;
}

int ExactPolynomial::sign_at(const Rational& t) const { return static_cast<int>(CGAL::sign(evaluate(t))); }

ExactPolynomial ExactPolynomial::derivative() const {
  std::vector<Rational> c;
  for (std::size_t i = 1; i < m_c.size(); ++i) c.push_back(m_c[i] * Rational(static_cast<long>(i)));
  return ExactPolynomial(std::move(c));
}

ExactPolynomial ExactPolynomial::compose_affine(const Rational& a, const Rational& b) const {
  const ExactPolynomial line(std::vector<Rational>{a, b - a});
  ExactPolynomial r;
  for (auto it = m_c.rbegin(); it != m_c.rend(); ++it)
    r = r * line + ExactPolynomial(std::vector<Rational>{*it});
  return r;
}

std::vector<Rational> ExactPolynomial::bernstein(const Rational& a, const Rational& b) const {
  const ExactPolynomial q = compose_affine(a, b);
  const int n = std::max(degree(), 0);
  std::vector<Rational> out(n + 1, Rational(0));
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= std::min(k, q.degree()); ++j)
      out[k] += q.m_c[j] * Rational(binomial(k, j)) / Rational(binomial(n, j));
  return out;
}

std::vector<Rational> ExactPolynomial::homogeneous_bernstein(int n) const {
  PLEAT_ASSERT(n >= degree() && n <= kMaxCertificateDegree, "Bernstein degree below the polynomial's");
  std::vector<Rational> h(n + 1, Rational(0));
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= std::min(k, degree()); ++j) h[k] += m_c[j] * Rational(binomial(n - j, k - j));
  return h;
}

ExactPolynomial operator+(const ExactPolynomial& a, const ExactPolynomial& b) {
  std::vector<Rational> c(std::max(a.m_c.size(), b.m_c.size()), Rational(0));
  for (std::size_t i = 0; i < a.m_c.size(); ++i) c[i] += a.m_c[i];
  for (std::size_t i = 0; i < b.m_c.size(); ++i) c[i] += b.m_c[i];
  return ExactPolynomial(std::move(c));
}

ExactPolynomial operator-(const ExactPolynomial& a, const ExactPolynomial& b) {
  std::vector<Rational> c(std::max(a.m_c.size(), b.m_c.size()), Rational(0));
  for (std::size_t i = 0; i < a.m_c.size(); ++i) c[i] += a.m_c[i];
  for (std::size_t i = 0; i < b.m_c.size(); ++i) c[i] -= b.m_c[i];
  return ExactPolynomial(std::move(c));
}

ExactPolynomial operator*(const ExactPolynomial& a, const ExactPolynomial& b) {
  if (a.is_zero() || b.is_zero()) return {};
  std::vector<Rational> c(a.m_c.size() + b.m_c.size() - 1, Rational(0));
  for (std::size_t i = 0; i < a.m_c.size(); ++i)
    for (std::size_t j = 0; j < b.m_c.size(); ++j) c[i + j] += a.m_c[i] * b.m_c[j];
  return ExactPolynomial(std::move(c));
}

void ExactPolynomial::divide(const ExactPolynomial& a, const ExactPolynomial& divisor,
                             ExactPolynomial& quotient, ExactPolynomial& remainder) {
  PLEAT_ASSERT(!divisor.is_zero(), "division by the zero polynomial");
  std::vector<Rational> r = a.m_c;
  const int db = divisor.degree();
  std::vector<Rational> q(std::max(a.degree() - db + 1, 0), Rational(0));
  const Rational& lead = divisor.m_c.back();
  for (int i = a.degree() - db; i >= 0; --i) {
    const Rational f = r[i + db] / lead;
    q[i] = f;
    if (CGAL::is_zero(f)) continue;
    for (int j = 0; j <= db; ++j) r[i + j] -= f * divisor.m_c[j];
  }
  if (static_cast<int>(r.size()) > db) r.resize(std::max(db, 0));
  quotient = ExactPolynomial(std::move(q));
  remainder = ExactPolynomial(std::move(r));
}

ExactPolynomial ExactPolynomial::gcd(ExactPolynomial a, ExactPolynomial b) {
  while (!b.is_zero()) {
    ExactPolynomial q, r;
    divide(a, b, q, r);
    a = std::move(b);
    b = std::move(r);
  }
  if (a.is_zero()) return a;
  const Rational lead = a.m_c.back();
  for (Rational& c : a.m_c) c /= lead;
  return a;
}

ExactPolynomial ExactPolynomial::squarefree_part() const {
  if (degree() <= 0) return *this;
  const ExactPolynomial g = gcd(*this, derivative());
  if (g.degree() == 0) return *this;
  ExactPolynomial q, r;
  divide(*this, g, q, r);
  PLEAT_ASSERT(r.is_zero(), "gcd does not divide");
  return q;
}

ExactPolynomial ExactPolynomial::deflate(const Rational& root) const {
  ExactPolynomial q, r;
  divide(*this, ExactPolynomial(std::vector<Rational>{-root, Rational(1)}), q, r);
  PLEAT_ASSERT(r.is_zero(), "deflation by a non-root");
  return q;
}

// ---- Certificates ---------------------------------------------------------------------------------------

CertificatePolynomial planar_orientation_certificate(const std::array<glm::dvec2, 6>& points) {
  CertificatePolynomial out;
  {
    CGAL::Protect_FPU_rounding<true> upward;
    const std::array<Interval, 3> h = planar_orientation_coefficients<Interval>(points);
    for (int k = 0; k < 3; ++k) out.m_h[k] = h[k];
  }
  out.m_degree = 2;
  out.m_source = CertificatePolynomial::PlanarOrientation{points};
  return out;
}

CertificatePolynomial CertificatePolynomial::from_exact(const ExactPolynomial& p) {
  if (p.degree() > kMaxCertificateDegree)
    throw std::invalid_argument("CertificatePolynomial::from_exact: degree above 5");
  CertificatePolynomial out;
  out.m_degree = std::max(p.degree(), 0);
  const std::vector<Rational> h = p.homogeneous_bernstein(out.m_degree);
  for (int k = 0; k <= out.m_degree; ++k) out.m_h[k] = Interval(CGAL::to_interval(h[k]));
  out.m_source = p;
  return out;
}

ExactPolynomial CertificatePolynomial::exact() const {
  if (const auto* o = std::get_if<PlanarOrientation>(&m_source))
    return ExactPolynomial(monomial_from_homogeneous(planar_orientation_coefficients<Dyadic>(o->points)));
  if (const auto* p = std::get_if<ExactPolynomial>(&m_source)) return *p;
  PLEAT_ASSERT(false, "exact() of an empty certificate");
  return {};
}

}  // namespace pleat::kinetic
