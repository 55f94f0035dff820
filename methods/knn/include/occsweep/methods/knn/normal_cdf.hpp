// The k-NN inverse sensor model's point probability: Eq. 6 with the normal CDF of Eq. 8.
#pragma once

#include <cmath>

namespace occsweep {

/// F(s) of Eq. 6 with the normal density of Eq. 8. sigma = 0 makes F a step at mu (F(mu) = 1, right-continuous
/// like every CDF); s = +inf (a point with no neighbours) gives 1.
[[nodiscard]] inline double normalCdf(double s, double mu, double sigma) {
  if (std::isinf(s)) return s > 0 ? 1.0 : 0.0;
  if (!(sigma > 0.0)) return s < mu ? 0.0 : 1.0;
  return 0.5 * std::erfc(-(s - mu) / (sigma * std::sqrt(2.0)));
}

/// p(s) = p_u - F(s) (p_u - p_l) (Eq. 6): close neighbours give p_u, isolated points p_l.
[[nodiscard]] inline double pointProbability(double s, double mu, double sigma, double p_u, double p_l) {
  return p_u - normalCdf(s, mu, sigma) * (p_u - p_l);
}

}  // namespace occsweep
