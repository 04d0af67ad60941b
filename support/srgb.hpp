// The sRGB transfer function (IEC 61966-2-1): one definition for every reader, writer and renderer.
// Both directions clamp to [0, 1] first; NaN maps to 0.
#pragma once

#include <cmath>
#include <concepts>

namespace pleat {

template <std::floating_point T>
T srgb_to_linear(T c) {
  if (!(c > T(0))) return T(0);
  if (c >= T(1)) return T(1);
  return c <= T(0.04045) ? c / T(12.92) : std::pow((c + T(0.055)) / T(1.055), T(2.4));
}

template <std::floating_point T>
T linear_to_srgb(T c) {
  if (!(c > T(0))) return T(0);
  if (c >= T(1)) return T(1);
  return c <= T(0.0031308) ? T(12.92) * c : T(1.055) * std::pow(c, T(1) / T(2.4)) - T(0.055);
}

}  // namespace pleat
