// Analytic animated cloth (see cloth_generators.hpp for the shapes' no-self-intersection arguments).
//
// Conventions: y is up; a grid vertex v(i, j) has material coordinates s = i / (n - 1) across the columns
// and v = j / (n - 1) along the rows (the sleeve's columns wrap: s = i / n of a turn). The cycle
// g(t) = (1 - cos(2 pi t / T)) / 2, T = frames / fps, goes 0 -> 1 -> 0 over the sequence.
// Fold counts are capped by the resolution (about six vertices per fold at least), so small meshes still
// resolve their folds; from resolution ~50 up the shape no longer depends on the resolution.
#include "sim_io/cloth_generators.hpp"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <numbers>
#include <stdexcept>
#include <string>

namespace pleat {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr int kMaxResolution = 20000;  // 4e8 vertices: far beyond memory, but within Index

// Deterministic jitter: splitmix64, identical on every platform (std distributions are not).
class Jitter {
 public:
  explicit Jitter(std::uint64_t seed) : m_state(seed), m_enabled(seed != 0) {}
  /// x scaled by a factor uniform in [1 - rel, 1 + rel] (x itself for seed 0).
  double scale(double x, double rel) { return m_enabled ? x * (1.0 + rel * (2.0 * uniform() - 1.0)) : x; }
  /// An angle uniform in [0, 2 pi) added to x (x itself for seed 0).
  double turn(double x) { return m_enabled ? x + kTwoPi * uniform() : x; }

 private:
  double uniform() {
    std::uint64_t z = (m_state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return static_cast<double>(z >> 11) * 0x1.0p-53;
  }
  std::uint64_t m_state;
  bool m_enabled;
};

// The grid's triangles; `wrap` closes the columns into a tube (column n-1 joins column 0).
MeshTopology grid_topology(int n, bool wrap) {
  MeshTopology topology;
  topology.num_vertices = static_cast<Index>(n) * static_cast<Index>(n);
  const int cells_across = wrap ? n : n - 1;
  topology.triangles.reserve(static_cast<std::size_t>(2) * cells_across * (n - 1));
  const auto v = [n](int i, int j) { return static_cast<Index>(j) * n + static_cast<Index>(i % n); };
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i < cells_across; ++i) {
      topology.triangles.push_back({v(i, j), v(i + 1, j), v(i + 1, j + 1)});
      topology.triangles.push_back({v(i, j), v(i + 1, j + 1), v(i, j + 1)});
    }
  return topology;
}

double fold_count_cap(int n, double nominal) { return std::min(nominal, std::max(1.0, (n - 1) / 6.0)); }

// ---- curtain: hangs from a rod along x at y = 0, pleats in z -------------------------------------------
// width W, drop H (length); `count` pleats; depth (in pleat periods) from depth_lo to depth_hi; the rod
// gathers the cloth (width x (1 - shrink g)); pleats lean by `tilt` radians of phase over the drop, are
// 35% shallower at the hem, and the hem sways by `sway`.
void curtain_frame(const ClothGenerator::Shape& c, int n, double t_cycle, double g,
                   std::vector<glm::dvec3>& out) {
  const double width = c.width * (1.0 - c.shrink * g);
  const double period = width / c.count;
  const double depth = period * (c.depth_lo + (c.depth_hi - c.depth_lo) * g);
  const double sway = c.sway * std::sin(kTwoPi * t_cycle + c.phase2);
  for (int j = 0; j < n; ++j) {
    const double v = double(j) / (n - 1);
    for (int i = 0; i < n; ++i) {
      const double s = double(i) / (n - 1);
      const double z =
          depth * (1.0 - 0.35 * v) * std::sin(kTwoPi * c.count * s + c.phase + c.tilt * v) + sway * v * v;
      out[static_cast<std::size_t>(j) * n + i] = {width * (s - 0.5), -c.length * v, z};
    }
  }
}

// ---- flag: pole along y at x = 0, a wave travelling along x ---------------------------------------------
// length L (along x), height `width`; `count` waves along the flag; the wave's steepness (amplitude x
// wavenumber) at the free end is depth_lo..depth_hi (the amplitude grows from 0 at the pole as s^0.8);
// `tilt` radians of phase over the height make the crests diagonal; `shrink` shortens the flag as it
// waves; the free end sags by `sway`; `cycles` whole wave periods pass over the sequence.
void flag_frame(const ClothGenerator::Shape& c, int n, double t_cycle, double g,
                std::vector<glm::dvec3>& out) {
  const double length = c.length * (1.0 - c.shrink * g);
  const double k = kTwoPi * c.count / length;  // wavenumber along x
  const double steepness = c.depth_lo + (c.depth_hi - c.depth_lo) * g;
  const double tip_amplitude = steepness / k;
  const double wave_phase = kTwoPi * c.cycles * t_cycle;
  for (int i = 0; i < n; ++i) {
    const double s = double(i) / (n - 1);
    const double x = length * s;
    const double amplitude = tip_amplitude * std::pow(s, 0.8);
    const double sag = c.sway * s * s;
    for (int j = 0; j < n; ++j) {
      const double v = double(j) / (n - 1);
      const double z = amplitude * std::sin(k * x - wave_phase + c.phase + c.tilt * v);
      out[static_cast<std::size_t>(j) * n + i] = {x, c.width * v - sag, z};
    }
  }
}

// ---- sleeve: a tube about the y axis, hanging down, with accordion folds ---------------------------------
// length L, radius `width`; `count` folds along it; fold amplitude (relative radius) depth_lo..depth_hi;
// the folds wind once around the tube over one fold period when tilt = 1 (a helix; 0: rings); the tube
// shortens by `shrink` as the folds deepen; the cross-section is squashed into an ellipse by `squash`
// that turns once over the sequence, starting at angle phase2.
void sleeve_frame(const ClothGenerator::Shape& c, int n, double t_cycle, double g,
                  std::vector<glm::dvec3>& out) {
  const double length = c.length * (1.0 - c.shrink * g);
  const double amplitude = c.depth_lo + (c.depth_hi - c.depth_lo) * g;
  for (int j = 0; j < n; ++j) {
    const double v = double(j) / (n - 1);
    const double y = -length * v;
    for (int i = 0; i < n; ++i) {
      const double theta = kTwoPi * i / n;
      const double fold = 1.0 + amplitude * std::sin(kTwoPi * c.count * v + c.phase + c.tilt * theta);
      const double ellipse = 1.0 + c.squash * std::cos(2.0 * theta + c.phase2 + kTwoPi * t_cycle);
      const double r = c.width * fold * ellipse;  // > 0: amplitude < 1 and squash < 1
      out[static_cast<std::size_t>(j) * n + i] = {r * std::cos(theta), y, r * std::sin(theta)};
    }
  }
}

// ---- roll: a sheet rolling into an Archimedean spiral along the floor and unrolling ----------------------
// length L along the rolling direction, width along z; rolled length L * (depth_lo .. depth_hi); spiral
// r = b phi from radius inner_radius, turns `gap` apart. The free (outer) end stays put on the floor y = 0.
struct Spiral {
  Spiral(double gap, double inner_radius) : b(gap / kTwoPi), phi0(inner_radius / b), arc0(arc(phi0)) {}
  double b;     // r = b * phi
  double phi0;  // inner end
  double arc0;  // arc(phi0)
  double arc(double phi) const { return 0.5 * b * (phi * std::sqrt(1.0 + phi * phi) + std::asinh(phi)); }
  /// phi at arc length s from the inner end: Newton from the right on a convex increasing function, so
  /// the iterates decrease monotonically to the root.
  double phi_at(double s) const {
    double phi = phi0 + s / (b * phi0);  // the arc from phi0 is at least r(phi0) * dphi: an overestimate
    for (int iteration = 0; iteration < 100; ++iteration) {
      const double step = (arc(phi) - arc0 - s) / (b * std::sqrt(1.0 + phi * phi));
      phi -= step;
      if (!(std::abs(step) > 1e-15 * phi)) break;
    }
    return phi;
  }
};

void roll_frame(const ClothGenerator::Shape& c, int n, double g, std::vector<glm::dvec3>& out) {
  const Spiral sp(c.gap, c.inner_radius);
  const double rolled = c.length * (c.depth_lo + (c.depth_hi - c.depth_lo) * g);
  const double phi1 = sp.phi_at(rolled);
  const glm::dvec2 joint = sp.b * phi1 * glm::dvec2(std::cos(phi1), std::sin(phi1));
  // Tangent d/dphi (b phi cos phi, b phi sin phi) = b (cos phi - phi sin phi, sin phi + phi cos phi).
  const glm::dvec2 tangent = glm::normalize(
      glm::dvec2(std::cos(phi1) - phi1 * std::sin(phi1), std::sin(phi1) + phi1 * std::cos(phi1)));
  // Rotate the tangent onto +x (the spiral's centre goes to +y, the left of a counter-clockwise turn) and
  // put the outer end at x = L / 2 on y = 0.
  const auto rotate = [&](glm::dvec2 p) {
    return glm::dvec2(tangent.x * p.x + tangent.y * p.y, -tangent.y * p.x + tangent.x * p.y);
  };
  const glm::dvec2 joint_r = rotate(joint);
  const glm::dvec2 offset(0.5 * c.length - (c.length - rolled) - joint_r.x, -joint_r.y);
  std::vector<glm::dvec2> section(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const double s = c.length * i / (n - 1);
    glm::dvec2 p;
    if (s < rolled) {
      const double phi = sp.phi_at(s);
      p = rotate(sp.b * phi * glm::dvec2(std::cos(phi), std::sin(phi)));
    } else {
      p = joint_r + glm::dvec2(s - rolled, 0.0);
    }
    section[static_cast<std::size_t>(i)] = p + offset;
  }
  for (int j = 0; j < n; ++j) {
    const double z = c.width * (double(j) / (n - 1) - 0.5);
    for (int i = 0; i < n; ++i) {
      const glm::dvec2 p = section[static_cast<std::size_t>(i)];
      out[static_cast<std::size_t>(j) * n + i] = {p.x, p.y, z};
    }
  }
}

}  // namespace

std::optional<ClothKind> parse_cloth_kind(std::string_view name) {
  if (name == "curtain") return ClothKind::Curtain;
  if (name == "roll" || name == "spiral") return ClothKind::Roll;
  if (name == "flag") return ClothKind::Flag;
  if (name == "sleeve" || name == "tube") return ClothKind::Sleeve;
  return std::nullopt;
}

std::string_view cloth_kind_name(ClothKind kind) {
  switch (kind) {
    case ClothKind::Curtain:
      return "curtain";
    case ClothKind::Roll:
      return "roll";
    case ClothKind::Flag:
      return "flag";
    case ClothKind::Sleeve:
      return "sleeve";
  }
  return "unknown";
}

Index cloth_vertex_count(int resolution) {
  return static_cast<Index>(resolution) * static_cast<Index>(resolution);
}

ClothGenerator::ClothGenerator(ClothKind kind, const GeneratorParams& params)
    : m_kind(kind), m_params(params) {
  if (params.resolution < 3 || params.resolution > kMaxResolution)
    throw std::invalid_argument("resolution must be in [3, " + std::to_string(kMaxResolution) + "], got " +
                                std::to_string(params.resolution));
  if (params.frames < 1)
    throw std::invalid_argument("frames must be at least 1, got " + std::to_string(params.frames));
  if (!std::isfinite(params.fps) || params.fps <= 0.0)
    throw std::invalid_argument("fps must be a positive number, got " + std::to_string(params.fps));

  const int n = params.resolution;
  Jitter jitter(params.seed);
  Shape& c = m_shape;
  switch (kind) {
    case ClothKind::Curtain:
      c.width = jitter.scale(2.0, 0.1);
      c.length = jitter.scale(2.4, 0.1);
      c.count = fold_count_cap(n, jitter.scale(7.0, 0.15));
      c.depth_lo = jitter.scale(0.4, 0.1);  // pleat depth in pleat periods: steepness 2.5 .. 5
      c.depth_hi = jitter.scale(0.8, 0.1);
      c.phase = jitter.turn(0.0);
      c.phase2 = jitter.turn(0.0);
      c.tilt = jitter.scale(0.8, 0.5);
      c.sway = jitter.scale(0.12, 0.3);
      c.shrink = jitter.scale(0.25, 0.2);
      break;
    case ClothKind::Flag:
      c.length = jitter.scale(1.8, 0.1);
      c.width = jitter.scale(1.2, 0.1);
      c.count = fold_count_cap(n, jitter.scale(1.75, 0.15));
      c.depth_lo = jitter.scale(2.8, 0.1);  // steepness at the free end
      c.depth_hi = jitter.scale(3.6, 0.1);
      c.phase = jitter.turn(0.0);
      c.tilt = jitter.scale(0.6, 0.5);
      c.shrink = jitter.scale(0.12, 0.2);
      c.sway = jitter.scale(0.1, 0.3);
      c.cycles = std::max(1.0, std::round(jitter.scale(2.0, 0.5)));  // whole cycles: the motion loops
      break;
    case ClothKind::Sleeve:
      c.length = jitter.scale(2.0, 0.1);
      c.width = jitter.scale(0.3, 0.1);
      c.count = fold_count_cap(n, jitter.scale(7.0, 0.15));
      c.depth_lo = jitter.scale(0.2, 0.1);  // relative radius change; steepness up to ~4
      c.depth_hi = jitter.scale(0.45, 0.1);
      c.phase = jitter.turn(0.0);
      c.phase2 = jitter.turn(0.0);
      c.tilt = 1.0;  // must be an integer: the folds close up around the tube
      c.squash = jitter.scale(0.15, 0.3);
      c.shrink = jitter.scale(0.25, 0.2);
      break;
    case ClothKind::Roll: {
      c.length = jitter.scale(4.0, 0.1);
      c.width = jitter.scale(1.6, 0.1);
      c.depth_lo = jitter.scale(0.2, 0.2);  // rolled fraction of the length
      c.depth_hi = jitter.scale(0.75, 0.1);
      // The spacing bound of the header: gap >= ds / 2, inner radius > ds^2 / (4 gap) and >= 2 ds / pi,
      // with 5% to spare; coarse grids get a looser, fatter roll.
      const double ds = c.length / (n - 1);
      c.gap = std::max(jitter.scale(0.05, 0.15), 0.5 * ds);
      c.inner_radius =
          std::max(jitter.scale(0.12, 0.15), 1.05 * std::max(ds * ds / (4.0 * c.gap), 2.0 * ds / kPi));
      break;
    }
  }
  m_topology = grid_topology(n, kind == ClothKind::Sleeve);
}

Frame ClothGenerator::frame(std::size_t i) const {
  if (i >= num_frames())
    throw std::out_of_range("frame " + std::to_string(i) + " of " + std::to_string(num_frames()));
  Frame frame;
  frame.time = static_cast<double>(i) / m_params.fps;
  const double t_cycle = static_cast<double>(i) / static_cast<double>(m_params.frames);  // in [0, 1)
  const double g = 0.5 - 0.5 * std::cos(kTwoPi * t_cycle);
  const int n = m_params.resolution;
  frame.positions.resize(m_topology.num_vertices);
  switch (m_kind) {
    case ClothKind::Curtain:
      curtain_frame(m_shape, n, t_cycle, g, frame.positions);
      break;
    case ClothKind::Flag:
      flag_frame(m_shape, n, t_cycle, g, frame.positions);
      break;
    case ClothKind::Sleeve:
      sleeve_frame(m_shape, n, t_cycle, g, frame.positions);
      break;
    case ClothKind::Roll:
      roll_frame(m_shape, n, g, frame.positions);
      break;
  }
  return frame;
}

GeneratedCloth generate_cloth(ClothKind kind, const GeneratorParams& params) {
  const ClothGenerator generator(kind, params);
  GeneratedCloth cloth;
  cloth.name = std::string(cloth_kind_name(kind));
  cloth.topology = generator.topology();
  cloth.fps = params.fps;
  cloth.frames.reserve(generator.num_frames());
  for (std::size_t i = 0; i < generator.num_frames(); ++i) cloth.frames.push_back(generator.frame(i));
  return cloth;
}

}  // namespace pleat
