// Accuracy of a per-vertex sky-visibility estimate against a reference, and the ray count at which Embree's
// error matches the cone engine's (the frame-coherence benchmark's headline).
//
// Values are per vertex and side, one vector per frame, [front..., back...]. A NaN in the reference marks a
// vertex it did not estimate (RayVisibilityParams::vertex_stride): every statistic skips it.
//
// Matched error. Embree is run over a ladder of ray counts K_1 < K_2 < ... with errors e_i (which fall like
// K^-1/2 up to noise) and times t_i (which grow like a + bK). For a target error e*, K* is found on the first
// rung (from the cheap end) whose error is at most e*, log-log interpolated from the rung below it:
//   log K* = log K_i + (log e* − log e_i) (log K_{i+1} − log K_i) / (log e_{i+1} − log e_i),
// and the time at K* is interpolated the same way in (log K, log t). A target above the cheapest rung's
// error gives K* < K_1 (Bound::Below: the time of K_1 is an upper bound of Embree's), a target below every
// rung's error gives K* > K_n (Bound::Above: the time of K_n is a lower bound).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace pleat::bench {

using SkyValues = std::vector<double>;

struct ErrorStats {
  double mean = 0, p95 = 0;
  std::size_t count = 0;  ///< values compared
};

/// |a − ref| over every (frame, value) where the reference is finite, pooled: mean and 95th percentile.
/// Frames and values must have the same sizes (throws std::invalid_argument otherwise); count 0 if none.
ErrorStats error_stats(std::span<const SkyValues> a, std::span<const SkyValues> ref);

/// Temporal flicker: the mean over consecutive frame pairs (k, k+1) and values of
/// |(a_{k+1} − a_k) − (ref_{k+1} − ref_k)|, i.e. how much the estimate's frame-to-frame change departs from
/// the truth's. NaN with fewer than two frames.
double flicker(std::span<const SkyValues> a, std::span<const SkyValues> ref);

/// One rung of the ray ladder.
struct Rung {
  double rays = 0;
  double ms = 0;     ///< time per frame
  double error = 0;  ///< the error measure matched (mean or p95)
  double flicker = 0;
};

struct MatchedRays {
  enum class Bound { Inside, Below, Above } bound = Bound::Inside;
  double rays = 0;     ///< K* (Inside), else the end rung's K
  double ms = 0;       ///< Embree's time at K* (Inside), else the end rung's time (a bound, see Bound)
  double flicker = 0;  ///< Embree's flicker at K*, interpolated like the time
};

/// K*, the time and the flicker at it, for the target error. `ladder` sorted by rays ascending, positive
/// rays, ms and errors (throws std::invalid_argument otherwise, and on an empty ladder).
MatchedRays matched_rays(std::span<const Rung> ladder, double target_error);

}  // namespace pleat::bench
