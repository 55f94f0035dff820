// Log-odds arithmetic exactly as OctoMap does it (Eq. 2): computed in double, stored as float.
#pragma once

#include <octomap/octomap_utils.h>

namespace occsweep {

/// l(p) = ln(p / (1 - p)) (Eq. 2), rounded to float like octomap::logodds, so that our
/// thresholds and updates compare bit for bit with liboctomap's.
[[nodiscard]] inline float logOdds(double probability) { return octomap::logodds(probability); }

/// Inverse of logOdds.
[[nodiscard]] inline double probability(float log_odds) { return octomap::probability(log_odds); }

/// The clamped update of Eq. 5: l <- clamp(l + delta, l_min, l_max), in float as OctoMap.
[[nodiscard]] inline float clampedUpdate(float value, float delta, float l_min, float l_max) {
  const float sum = value + delta;
  if (sum < l_min) return l_min;
  if (sum > l_max) return l_max;
  return sum;
}

}  // namespace occsweep
