// The run-time models of Section 3.6: Eq. 17 t = aN + b (OctoMap) and Eq. 18 t = (ak + b)N + c (k-NN),
// fitted by least squares, with R^2.
#pragma once

#include <vector>

namespace occsweep {

struct RuntimeSample {
  double points = 0;  ///< N, points processed
  double k = 0;       ///< k (ignored by Eq. 17)
  double seconds = 0;
};

struct RuntimeFit {
  double a = 0, b = 0, c = 0;  ///< Eq. 17 uses a, b; Eq. 18 uses a, b, c
  double r_squared = 0;
};

/// Eq. 17: t = a N + b. Throws std::invalid_argument with fewer than 2 distinct N.
[[nodiscard]] RuntimeFit fitEq17(const std::vector<RuntimeSample>& samples);

/// Eq. 18: t = (a k + b) N + c, linear in (kN, N, 1). Throws std::invalid_argument when kN and N are collinear.
[[nodiscard]] RuntimeFit fitEq18(const std::vector<RuntimeSample>& samples);

}  // namespace occsweep
