// The fuzzed cloth of fuzz_engines, shared with the regression test (tests/fuzz_regressions_test.cpp): the
// input decodes to 3-40 vertices on a coarse grid (so coincident, collinear and coplanar points are common),
// 2-3 frames of positions and triangles over them (those with a repeated corner or repeating an earlier one
// are dropped, as MeshSequence drops them); check_engines runs both engines and the shading on it.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "kinetic/kinetic_visibility.hpp"
#include "shading/shade.hpp"
#include "static_core/slicing_plan.hpp"
#include "static_core/visibility.hpp"

namespace pleat::fuzz {

struct FuzzCloth {
  MeshTopology topology;
  std::vector<Frame> frames;
};

/// The cloth the bytes describe, or nothing when they give no triangle.
inline std::optional<FuzzCloth> decode_cloth(const std::uint8_t* data, std::size_t size) {
  std::size_t at = 0;
  auto next = [&]() -> std::uint8_t { return at < size ? data[at++] : 0; };
  FuzzCloth cloth;
  const Index n = 3 + next() % 38;
  const int frames = 2 + next() % 2;
  cloth.frames.resize(frames);
  for (int f = 0; f < frames; ++f) {
    cloth.frames[f].time = f;
    for (Index v = 0; v < n; ++v) {
      glm::dvec3 p;
      for (int k = 0; k < 3; ++k) p[k] = (static_cast<int>(next()) - 128) / 32.0;
      cloth.frames[f].positions.push_back(p);
    }
  }
  cloth.topology.num_vertices = n;
  std::set<std::array<Index, 3>> seen;
  while (at < size && cloth.topology.triangles.size() < 80) {
    const Triangle t{Index(next() % n), Index(next() % n), Index(next() % n)};
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
    std::array<Index, 3> key{t[0], t[1], t[2]};
    std::sort(key.begin(), key.end());
    if (!seen.insert(key).second) continue;
    cloth.topology.triangles.push_back(t);
  }
  if (cloth.topology.triangles.empty()) return std::nullopt;
  return cloth;
}

/// Both engines frame by frame (the kinetic one with its exact invariant checks on) and the shading. Returns
/// "" or where the kinetic engine's A differs from the static engine's; an InvariantError (a bug) propagates.
inline std::string check_engines(const FuzzCloth& cloth) {
  const SlicingPlan plan = make_diffuse_plan(cloth.topology, cloth.frames[0], {});
  KineticParams kinetic_params;
  kinetic_params.parallel = false;
  kinetic_params.check_invariants = true;
  KineticVisibility kinetic(cloth.topology, plan, cloth.frames[0], kinetic_params);
  Lighting lighting;
  lighting.lights.push_back(UniformSkyLight{});
  lighting.lights.push_back(DirectionalLight{});
  for (std::size_t f = 0; f < cloth.frames.size(); ++f) {
    const FrameVisibility expected = compute_visibility(cloth.topology, cloth.frames[f], plan, {false});
    const FrameVisibility& got = f == 0 ? kinetic.current() : kinetic.advance(cloth.frames[f]);
    for (Side side : kBothSides)
      for (Index v = 0; v < cloth.topology.num_vertices; ++v) {
        const double a = expected.measure(side, v).sky_visibility, b = got.measure(side, v).sky_visibility;
        if (!(std::abs(a - b) <= 1e-9)) {
          char message[160];
          std::snprintf(message, sizeof message,
                        "kinetic A %.17g != static A %.17g (frame %zu, vertex %u, side %d)", b, a, f, v,
                        static_cast<int>(side));
          return message;
        }
      }
    (void)shade_frame(cloth.topology, cloth.frames[f], expected, lighting);
  }
  return {};
}

}  // namespace pleat::fuzz
