// EnvironmentMap: loading, lookup, and the Green's-theorem integral over spherical polygons (see header).
#include "shading/environment_map.hpp"

#include <stb/stb_image.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <glm/geometric.hpp>
#include <iterator>
#include <stdexcept>
#include <string>

#include "support/input_error.hpp"
#include "support/srgb.hpp"

namespace pleat {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTwoPi = 2.0 * kPi;

// 3-point Gauss–Legendre on [-1, 1].
constexpr double kGaussX[3] = {-0.7745966692414834, 0.0, 0.7745966692414834};
constexpr double kGaussW[3] = {0.5555555555555556, 0.8888888888888888, 0.5555555555555556};

/// integral_0^t sin^2 and integral_0^t sin cos.
double integral_sin2(double t) { return 0.5 * t - 0.25 * std::sin(2.0 * t); }
double integral_sincos(double t) {
  const double s = std::sin(t);
  return 0.5 * s * s;
}

/// Halves both dimensions, averaging 2x2 blocks weighted by their rows' solid angles.
void halve(int& width, int& height, std::vector<glm::vec3>& texels) {
  const int w = width / 2, h = height / 2;
  std::vector<glm::vec3> out(static_cast<std::size_t>(w) * h);
  auto row_weight = [&](int r) { return std::cos(kPi * r / height) - std::cos(kPi * (r + 1) / height); };
  for (int r = 0; r < h; ++r) {
    const double w0 = row_weight(2 * r), w1 = row_weight(2 * r + 1);
    for (int c = 0; c < w; ++c) {
      const auto at = [&](int rr, int cc) {
        return glm::dvec3(texels[static_cast<std::size_t>(rr) * width + cc]);
      };
      const glm::dvec3 sum = w0 * (at(2 * r, 2 * c) + at(2 * r, 2 * c + 1)) +
                             w1 * (at(2 * r + 1, 2 * c) + at(2 * r + 1, 2 * c + 1));
      out[static_cast<std::size_t>(r) * w + c] = glm::vec3(sum / (2.0 * (w0 + w1)));
    }
  }
  width = w;
  height = h;
  texels = std::move(out);
}

// The scanlines of a Radiance .hdr file (`bytes`, whole), walked without decoding: throws InputError naming
// the byte where the data ends, or where a run goes past its scanline, when the file holds fewer than the
// header's height x width pixels (stb_image fills what is missing with black). Flat pixels or new-style
// run-length scanlines, as stb_image reads them (the first scanline decides). O(file size).
void check_radiance_pixels(const std::string& name, const std::string& bytes) {
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
  const std::size_t size = bytes.size();
  std::size_t at = bytes.find("\n\n");  // the header ends with an empty line, then the resolution line
  const std::size_t line_end = at == std::string::npos ? at : bytes.find('\n', at + 2);
  if (line_end == std::string::npos)
    throw InputError(name, "byte " + std::to_string(size), "truncated HDR header");
  int height = 0, width = 0;
  char y_sign = 0, x_sign = 0;
  if (std::sscanf(bytes.c_str() + at + 2, "%cY %d %cX %d", &y_sign, &height, &x_sign, &width) != 4 ||
      height <= 0 || width <= 0)
    return;  // another orientation or a malformed line: stb_image says what it makes of it
  at = line_end + 1;
  const auto ends = [&](int row, const char* what) {
    throw InputError(name, "byte " + std::to_string(at),
                     std::string("truncated or damaged HDR image: ") + what + " in scanline " +
                         std::to_string(row) + " of " + std::to_string(height) + " (" +
                         std::to_string(width) + " pixels wide; the file has " + std::to_string(size) +
                         " bytes)");
  };
  const auto run_length = [&] {  // a new-style run-length scanline starts 2, 2, width (big-endian)
    return at + 4 <= size && p[at] == 2 && p[at + 1] == 2 && ((p[at + 2] << 8) | p[at + 3]) == width;
  };
  if (width < 8 || width >= 32768 || !run_length()) {  // flat, as stb_image reads it then
    const std::uint64_t need = std::uint64_t(width) * std::uint64_t(height) * 4;
    if (size - at < need) {
      const std::uint64_t row = (size - at) / (std::uint64_t(width) * 4);
      at = size;
      ends(int(row), "the data ends");
    }
    return;
  }
  for (int row = 0; row < height; ++row) {
    if (!run_length())
      ends(row, at + 4 > size ? "the data ends" : "a scanline does not start with its run-length mark");
    at += 4;  // each of the 4 components in runs and literal stretches
    for (int component = 0; component < 4; ++component)
      for (int filled = 0; filled < width;) {
        if (at >= size) ends(row, "the data ends");
        const int count = p[at] > 128 ? p[at] - 128 : p[at];
        const std::size_t takes = p[at] > 128 ? 1 : std::size_t(count);
        if (count == 0 || filled + count > width) ends(row, "a run goes past the end of its scanline");
        if (at + 1 + takes > size) ends(row, "the data ends");
        at += 1 + takes;
        filled += count;
      }
  }
}

}  // namespace

EnvironmentMap::EnvironmentMap(int width, int height, std::vector<glm::vec3> texels,
                               const EnvironmentOrientation& orientation)
    : m_width(width), m_height(height), m_orientation(orientation), m_texels(std::move(texels)) {
  if (width <= 0 || height <= 0 || m_texels.size() != static_cast<std::size_t>(width) * height)
    throw std::invalid_argument("EnvironmentMap: texel count does not match " + std::to_string(width) + "x" +
                                std::to_string(height));
  const double len = glm::length(orientation.up);
  if (!(len > 0.0) || !std::isfinite(len))
    throw std::invalid_argument("EnvironmentMap: zero or invalid up axis");
  m_u = orientation.up / len;
  const glm::dvec3 ref = std::abs(m_u.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  m_x = glm::normalize(ref - glm::dot(ref, m_u) * m_u);
  m_y = glm::cross(m_u, m_x);
  m_rotation = orientation.rotation_degrees * kPi / 180.0;
  build_tables();
}

EnvironmentMap EnvironmentMap::load(const std::filesystem::path& path,
                                    const EnvironmentOrientation& orientation, int max_width) {
  const std::string name = path.string();
  int w = 0, h = 0, channels = 0;
  std::vector<glm::vec3> texels;
  if (stbi_is_hdr(name.c_str())) {
    std::ifstream in(path, std::ios::binary);
    check_radiance_pixels(name, std::string(std::istreambuf_iterator<char>(in), {}));
    float* data = stbi_loadf(name.c_str(), &w, &h, &channels, 3);
    if (data == nullptr)
      throw InputError(name, "", std::string("cannot read HDR image: ") + stbi_failure_reason());
    texels.resize(static_cast<std::size_t>(w) * h);
    for (std::size_t i = 0; i < texels.size(); ++i)
      texels[i] = glm::vec3(data[3 * i], data[3 * i + 1], data[3 * i + 2]);
    stbi_image_free(data);
  } else {
    unsigned char* data = stbi_load(name.c_str(), &w, &h, &channels, 3);
    if (data == nullptr)
      throw InputError(name, "", std::string("cannot read image: ") + stbi_failure_reason());
    float table[256];
    for (int i = 0; i < 256; ++i) table[i] = srgb_to_linear(i / 255.0f);
    texels.resize(static_cast<std::size_t>(w) * h);
    for (std::size_t i = 0; i < texels.size(); ++i)
      texels[i] = glm::vec3(table[data[3 * i]], table[data[3 * i + 1]], table[data[3 * i + 2]]);
    stbi_image_free(data);
  }
  for (std::size_t i = 0; i < texels.size(); ++i) {
    const glm::vec3& t = texels[i];
    if (!std::isfinite(t.x) || !std::isfinite(t.y) || !std::isfinite(t.z) || t.x < 0 || t.y < 0 || t.z < 0)
      throw InputError(name, "pixel " + std::to_string(i), "radiance must be finite and non-negative");
  }
  while (max_width > 0 && w > max_width && w % 2 == 0 && h % 2 == 0) halve(w, h, texels);
  return EnvironmentMap(w, h, std::move(texels), orientation);
}

void EnvironmentMap::build_tables() {
  const std::size_t stride = static_cast<std::size_t>(m_height) + 1;
  m_row_sin2.resize(stride);
  m_row_sincos.resize(stride);
  for (int r = 0; r <= m_height; ++r) {
    m_row_sin2[r] = integral_sin2(kPi * r / m_height);
    m_row_sincos[r] = integral_sincos(kPi * r / m_height);
  }
  m_prefix_s2.assign(stride * m_width, glm::vec3(0.0f));
  m_prefix_sc.assign(stride * m_width, glm::vec3(0.0f));
  glm::dvec3 local_moment[3] = {glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0)};
  for (int c = 0; c < m_width; ++c) {
    glm::dvec3 s2(0.0), sc(0.0);
    const double psi_hi = m_rotation - kTwoPi * c / m_width;
    const double psi_lo = m_rotation - kTwoPi * (c + 1) / m_width;
    const double int_cos = std::sin(psi_hi) - std::sin(psi_lo);
    const double int_sin = std::cos(psi_lo) - std::cos(psi_hi);
    const double dpsi = psi_hi - psi_lo;
    for (int r = 0; r < m_height; ++r) {
      const double t0 = kPi * r / m_height, t1 = kPi * (r + 1) / m_height;
      const glm::dvec3 L(m_texels[static_cast<std::size_t>(r) * m_width + c]);
      const double a2 = integral_sin2(t1) - integral_sin2(t0);
      const double asc = integral_sincos(t1) - integral_sincos(t0);
      s2 += L * a2;
      sc += L * asc;
      m_prefix_s2[c * stride + r + 1] = glm::vec3(s2);
      m_prefix_sc[c * stride + r + 1] = glm::vec3(sc);
      local_moment[0] += L * (int_cos * a2);
      local_moment[1] += L * (int_sin * a2);
      local_moment[2] += L * (dpsi * asc);
    }
  }
  // World moments: integral L w_k dw = sum_j (local axis j)_k * local_moment[j].
  const glm::dvec3 axes[3] = {m_x, m_y, m_u};
  for (int k = 0; k < 3; ++k) {
    m_sphere_moment[k] = glm::dvec3(0.0);
    for (int j = 0; j < 3; ++j) m_sphere_moment[k] += axes[j][k] * local_moment[j];
  }
}

glm::dvec3 EnvironmentMap::to_local(const glm::dvec3& w) const {
  return {glm::dot(w, m_x), glm::dot(w, m_y), glm::dot(w, m_u)};
}

int EnvironmentMap::column_of_psi(double psi) const {
  double u = (m_rotation - psi) / kTwoPi;
  u -= std::floor(u);
  return std::min(m_width - 1, static_cast<int>(u * m_width));
}

void EnvironmentMap::texel_of(const glm::dvec3& w, int& column, int& row) const {
  const glm::dvec3 l = to_local(w);
  const double theta = std::acos(std::clamp(l.z / glm::length(l), -1.0, 1.0));
  row = std::min(m_height - 1, static_cast<int>(theta / kPi * m_height));
  column = column_of_psi(std::atan2(l.y, l.x));
}

glm::dvec3 EnvironmentMap::radiance(const glm::dvec3& w) const {
  if (empty()) return glm::dvec3(0.0);
  int c = 0, r = 0;
  texel_of(w, c, r);
  return glm::dvec3(m_texels[static_cast<std::size_t>(r) * m_width + c]);
}

glm::dvec3 EnvironmentMap::edge_integral(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& nl,
                                         bool from_bottom) const {
  const glm::dvec3 g = glm::cross(a, b);
  if (g.z == 0.0) return glm::dvec3(0.0);  // on a meridian: psi does not change (a pole crossing adds 0)
  // Travel direction about U from the orientation of the arc, not from a principal value: robust for arcs
  // that pass close to a pole (|delta psi| near pi).
  const bool a_pole = a.x == 0.0 && a.y == 0.0, b_pole = b.x == 0.0 && b.y == 0.0;
  if (a_pole || b_pole) return glm::dvec3(0.0);
  const double psi_a = std::atan2(a.y, a.x), psi_b = std::atan2(b.y, b.x);
  double ccw = std::fmod(psi_b - psi_a, kTwoPi);
  if (ccw < 0.0) ccw += kTwoPi;
  const double delta = g.z > 0.0 ? ccw : (ccw == 0.0 ? 0.0 : ccw - kTwoPi);
  if (delta == 0.0) return glm::dvec3(0.0);

  const double sign_gz = g.z >= 0.0 ? 1.0 : -1.0;
  const double abs_gz = std::abs(g.z);
  auto theta_at = [&](double psi) {
    const double h = g.x * std::cos(psi) + g.y * std::sin(psi);
    return std::atan2(abs_gz, -h * sign_gz);
  };
  const std::size_t stride = static_cast<std::size_t>(m_height) + 1;
  const double row_height = kPi / m_height;
  // G at azimuth psi on the arc: theta = atan2(y, x) with y = |g.z| > 0 and x = -sign(g.z) (g.x cos psi +
  // g.y sin psi), so sin(2 theta) = 2xy/r^2 and sin^2 theta = y^2/r^2 come without more trigonometry, and
  // the row boundaries' integrals are tabulated: one sincos and one atan2 per quadrature point.
  auto contour = [&](int c, double psi) {
    const double cos_psi = std::cos(psi), sin_psi = std::sin(psi);
    const double x = -sign_gz * (g.x * cos_psi + g.y * sin_psi), y = abs_gz;
    const double theta = std::atan2(y, x);
    const double r2 = x * x + y * y;
    const int r = std::min(m_height - 1, static_cast<int>(theta / row_height));
    const glm::dvec3 L(m_texels[static_cast<std::size_t>(r) * m_width + c]);
    const double sin2 = 0.5 * theta - 0.5 * x * y / r2;  // integral_sin2(theta)
    const double sincos = 0.5 * y * y / r2;              // integral_sincos(theta)
    const glm::dvec3 s2 = glm::dvec3(m_prefix_s2[c * stride + r]) + L * (sin2 - m_row_sin2[r]);
    const glm::dvec3 sc = glm::dvec3(m_prefix_sc[c * stride + r]) + L * (sincos - m_row_sincos[r]);
    const double across = nl.x * cos_psi + nl.y * sin_psi;
    if (!from_bottom) return across * s2 + nl.z * sc;
    // Swept from the bottom pole: G_bottom = -(column total - G_top), the sign making the contour integral
    // of a counter-clockwise polygon positive again.
    const glm::dvec3 s2_total(m_prefix_s2[c * stride + m_height]);
    const glm::dvec3 sc_total(m_prefix_sc[c * stride + m_height]);
    return across * (s2 - s2_total) + nl.z * (sc - sc_total);
  };

  // Walk in u = (rotation - psi) / 2 pi (unwrapped), cutting at column boundaries k / width.
  glm::dvec3 sum(0.0);
  const double u0 = (m_rotation - psi_a) / kTwoPi;
  const double u1 = u0 - delta / kTwoPi;
  const double step = u1 > u0 ? 1.0 : -1.0;
  double u = u0;
  double theta_prev = theta_at(psi_a);
  while (u != u1) {
    // Next column boundary in the direction of travel.
    double next =
        step > 0 ? (std::floor(u * m_width) + 1.0) / m_width : (std::ceil(u * m_width) - 1.0) / m_width;
    if (next == u)  // u * width rounded to just below/above a boundary that u sits on: skip to the next
      next = step > 0 ? (std::floor(u * m_width) + 2.0) / m_width : (std::ceil(u * m_width) - 2.0) / m_width;
    if ((step > 0 && next > u1) || (step < 0 && next < u1)) next = u1;
    const double mid = 0.5 * (u + next);
    int c = static_cast<int>(std::floor(mid * m_width)) % m_width;
    if (c < 0) c += m_width;
    const double psi0 = m_rotation - kTwoPi * u;
    const double psi1 = m_rotation - kTwoPi * next;
    const double theta_end = theta_at(psi1);
    const int pieces =
        std::max(1, static_cast<int>(std::ceil(std::abs(theta_end - theta_prev) / row_height)));
    const double h = (psi1 - psi0) / pieces;
    for (int p = 0; p < pieces; ++p) {
      const double centre = psi0 + h * (p + 0.5);
      for (int q = 0; q < 3; ++q) {
        const double psi = centre + 0.5 * h * kGaussX[q];
        sum += (0.5 * h * kGaussW[q]) * contour(c, psi);
      }
    }
    theta_prev = theta_end;
    u = next;
  }
  return sum;
}

glm::dvec3 EnvironmentMap::integrate_cosine(const SphericalPolygon& poly, const glm::dvec3& n) const {
  if (empty() || poly.size() < 3) return glm::dvec3(0.0);
  // Sweep from the pole outside the hemisphere of n (the polygon lies within it): then that pole is neither
  // inside the polygon nor on its boundary, and no whole-sphere correction is needed. When both poles are
  // within 1e-9 of the horizon of n (e.g. a vertical surface under a map whose up is vertical), the
  // polygon is first pulled 1e-7 rad towards n, off the poles, which changes the result by O(1e-7).
  constexpr double kPoleMargin = 1e-9;
  constexpr double kNudge = 1e-7;
  const double nu = glm::dot(n, m_u);
  const SphericalPolygon* source = &poly;
  thread_local SphericalPolygon nudged;
  if (std::abs(nu) < kPoleMargin) {
    nudged.resize(poly.size());
    for (std::size_t i = 0; i < poly.size(); ++i) nudged[i] = glm::normalize(poly[i] + kNudge * n);
    source = &nudged;
  }
  const bool from_bottom = nu < -kPoleMargin;
  const glm::dvec3 nl = to_local(n);
  glm::dvec3 sum(0.0);
  const std::size_t count = source->size();
  glm::dvec3 a = to_local((*source)[0]);
  for (std::size_t i = 0; i < count; ++i) {
    const glm::dvec3 b = to_local((*source)[(i + 1) % count]);
    sum += edge_integral(a, b, nl, from_bottom);
    a = b;
  }
  return sum;
}

}  // namespace pleat
